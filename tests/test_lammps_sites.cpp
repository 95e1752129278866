// Birth sites per rank on the LAMMPS engine (src/fill/held_sites.hpp,
// site_choice.hpp; issue 31): each rank chooses and holds only the sites in
// its own sub-domain; together they are the sites one process chooses
// over the whole box, each held once; when the sub-domains move the sites go to
// their new owners. ctest runs it at one process and under `mpirun -np 2`
// (mpi2.test_lammps_sites). Without LAMMPS built in it does nothing.
#include <doctest/doctest.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "fill/held_sites.hpp"
#include "fill/large_first.hpp"
#include "fill/mesh_sites.hpp"
#include "lammps_fixtures.hpp"
#include "pfill/boundary.hpp"
#include "pfill/lammps.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

// Every rank's held keys (sites and room sites), sorted, on every rank.
std::vector<uint64_t> all_keys(const HeldSites& held, ParticleEngine& engine) {
  std::vector<uint64_t> keys = held.keys;
  keys.insert(keys.end(), held.room_keys.begin(), held.room_keys.end());
  engine.gather_over_processes(keys);
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::vector<uint64_t> keys_of(const std::vector<KeyedSite>& sites) {
  std::vector<uint64_t> keys;
  for (const KeyedSite& s : sites) keys.push_back(s.key);
  return keys;
}

// Each rank holds only sites its view decides.
void check_held_where_decided(const HeldSites& held, const BirthView& view) {
  for (const BirthSite& s : held.sites) CHECK(view.decides(s.position));
  for (const BirthSite& s : held.room_sites) CHECK(view.decides(s.position));
  CHECK(held.keys.size() == held.sites.size());
  CHECK(held.room_keys.size() == held.room_sites.size());
  CHECK(std::is_sorted(held.keys.begin(), held.keys.end()));
  CHECK(std::is_sorted(held.room_keys.begin(), held.room_keys.end()));
}

double& component(Vec3& v, int a) { return a == 0 ? v.x : a == 1 ? v.y : v.z; }

// The view with every cut between sub-domains moved by `shift` (as a
// `balance` moves them): the boxes still cover space once.
BirthView moved_cuts(BirthView view, double shift) {
  for (int a = 0; a < 3; ++a) {
    double lo = view.regions[0].lo[a], hi = view.regions[0].hi[a];
    for (const Box3& b : view.regions) lo = std::min(lo, b.lo[a]), hi = std::max(hi, b.hi[a]);
    for (Box3& b : view.regions) {
      if (b.lo[a] != lo) component(b.lo, a) += shift;
      if (b.hi[a] != hi) component(b.hi, a) += shift;
    }
  }
  return view;
}

}  // namespace

TEST_CASE("lammps engine: sites held per rank are one process's, each once, and follow the sub-domains") {
  if (!lammps_available()) return;
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(test::small_params());
  lmp->share_field(test::ball_field(0.5, 0.02));
  const Mesh ball = make_icosphere(0.45, 4);
  const Boundary boundary(ball);
  const SiteLattice waves(ball.bounds(), 0.1, 0.05), rooms(ball.bounds(), 0.04, 0.03);
  const BirthView view = lmp->birth_view(0.05, false);
  HeldSites held = split_sites(boundary, waves, rooms, *lmp, view);
  check_held_where_decided(held, view);

  // One process's choice: a complete view (no region), one sweep.
  const std::vector<KeyedSite> whole = choose_sites(boundary, waves, BirthView{}, *lmp, 0);
  const std::vector<KeyedSite> whole_rooms = choose_sites(boundary, rooms, BirthView{}, *lmp, kRoomKeyBase);
  INFO(whole.size() << " sites, " << whole_rooms.size() << " room sites");
  REQUIRE(whole.size() > 20);
  CHECK(held.total_sites == whole.size());
  CHECK(held.total_room_sites == whole_rooms.size());
  std::vector<uint64_t> expected = keys_of(whole), rooms_expected = keys_of(whole_rooms);
  expected.insert(expected.end(), rooms_expected.begin(), rooms_expected.end());
  CHECK(all_keys(held, *lmp) == expected);
  // The report's list: every rank's sites, in key order, at their places.
  const std::vector<BirthSite> listed = all_sites(held, *lmp);
  REQUIRE(listed.size() == whole.size());
  for (size_t k = 0; k < whole.size(); ++k) CHECK(length(listed[k].position - whole[k].site.position) == 0);

  const MpiWorld world = lammps_mpi_start();
  if (world.size == 1) {
    CHECK(view.complete());
    CHECK(held.sites.size() == whole.size());
    return;
  }
  CHECK(held.sites.size() < whole.size());  // no rank holds them all
  // A balance moves the cuts: the sites go to their new owners, none lost or doubled.
  const BirthView moved = moved_cuts(view, 0.12);
  size_t leaving = 0;
  for (const BirthSite& s : held.sites) leaving += moved.decides(s.position) ? 0 : 1;
  std::vector<int> left{static_cast<int>(leaving)};
  lmp->sum_over_processes(left);
  CHECK(left[0] > 0);  // the test moves some
  hand_over_sites(held, *lmp, moved);
  check_held_where_decided(held, moved);
  CHECK(all_keys(held, *lmp) == expected);
}

// Unequal spheres' rare large ones (src/fill/large_first.hpp): each rank
// holds the candidates of its sub-domain only, and the placement over the
// ranks is the one process's on every candidate, sphere for sphere.
TEST_CASE("lammps engine: large spheres placed on candidates held per rank, as one process places them") {
  if (!lammps_available()) return;
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(test::small_params());
  lmp->share_field(test::ball_field(0.5, 0.02));
  const Mesh ball = make_icosphere(0.45, 4);
  const Boundary boundary(ball);
  const BirthView view = lmp->birth_view(0.05, false);
  const HeldCandidates held = mesh_candidates(boundary, ball.bounds(), 0.012, 0.05, view);
  const HeldCandidates whole = mesh_candidates(boundary, ball.bounds(), 0.012, 0.05, BirthView{});
  REQUIRE(whole.points.size() > 1000);
  std::vector<uint64_t> orders, expected;
  for (const LargeCandidate& c : held.points) orders.push_back(c.order);
  for (const LargeCandidate& c : whole.points) expected.push_back(c.order);
  lmp->gather_over_processes(orders);
  std::sort(orders.begin(), orders.end());
  CHECK(orders == expected);  // each candidate held once

  LargeFirstSettings s;
  s.wall_gap = 0.005;
  s.pair_gap = 0.01;
  const std::vector<double> radii{0.2, 0.15, 0.12, 0.1, 0.1, 0.08, 0.08, 0.06, 0.06, 0.06};
  const std::shared_ptr<ProcessGroup> group = lmp->process_group();
  ProcessGroup one;
  const LargePlacement split = place_large_first(held, radii, s, *group);
  const LargePlacement alone = place_large_first(whole, radii, s, one);
  INFO(alone.centres.size() << " of " << radii.size() << " placed");
  CHECK(alone.centres.size() >= 6);
  REQUIRE(split.centres.size() == alone.centres.size());
  for (size_t k = 0; k < alone.centres.size(); ++k) {
    CHECK(length(split.centres[k] - alone.centres[k]) == 0);
    CHECK(split.radii[k] == alone.radii[k]);
    CHECK(-boundary.signed_distance(alone.centres[k]) >= alone.radii[k] + s.wall_gap);
  }
  if (lammps_mpi_start().size > 1) CHECK(held.points.size() < whole.points.size());  // no rank holds them all

  // The report's few sites (round a torus: a ball has one): one process's, site for site.
  const Mesh torus = make_torus(0.3, 0.12);
  const Boundary ring(torus);
  const std::vector<BirthSite> sites =
      choose_birth_sites(mesh_candidates(ring, torus.bounds(), 0.01, 0.03, view), 3, 0.03, 0.5, *group);
  const std::vector<BirthSite> sites_alone =
      choose_birth_sites(mesh_candidates(ring, torus.bounds(), 0.01, 0.03, BirthView{}), 3, 0.03, 0.5, one);
  CHECK(sites_alone.size() == 3);
  REQUIRE(sites.size() == sites_alone.size());
  for (size_t k = 0; k < sites.size(); ++k) {
    CHECK(length(sites[k].position - sites_alone[k].position) == 0);
    CHECK(sites[k].depth == sites_alone[k].depth);
  }
}

// The finish on the LAMMPS engine per sub-domain (issue 31, src/fill/
// finish_view.hpp): each rank sees its own spheres and a halo
// (ParticleEngine::local_view), deletes only its own and finds holes only
// in its own sub-domain. ctest runs this file as it is (one process) and
// under `mpirun -np 2` (mpi2.test_lammps_finish), where the views are
// partial. Without LAMMPS built in, nothing here runs.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <set>
#include <vector>

#include "fill/finish.hpp"
#include "fill/near_region.hpp"
#include "lammps_fixtures.hpp"
#include "pfill/engine/local_view.hpp"
#include "pfill/engine/reference.hpp"
#include "pfill/lammps.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/particle_share.hpp"
#include "pfill/radius_distribution.hpp"

using namespace pfill;

namespace {

constexpr double kR = 0.1;
constexpr double kBall = 1.0;

EngineParams base_params() {
  EngineParams p;
  p.radius = kR;
  p.max_radius = kR * (1 + 1e-6);
  return p;
}

/// A simple cubic lattice of spacing `spacing` in the ball, centres r deep.
std::vector<Particle> lattice(double spacing) {
  std::vector<Particle> ps;
  const int n = static_cast<int>(kBall / spacing) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 p = Vec3(i, j, k) * spacing + Vec3(0.003, -0.002, 0.001);
        if (length(p) > kBall - kR) continue;
        Particle q;
        q.position = p;
        q.radius = kR;
        q.id = ps.size() + 1;
        ps.push_back(q);
      }
  return ps;
}

double worst_overlap(const ParticleSet& s) {
  double worst = 0;
  for (const Overlap& o : find_overlaps(s)) worst = std::max(worst, o.fraction);
  return worst;
}

}  // namespace

TEST_CASE("lammps engine: the finish's view per rank: each sphere own on one rank, the halo as the whole set") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(kBall, kR / 3);
  const std::vector<Particle> start = lattice(1.7 * kR);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(base_params());
  lmp->share_field(field);
  lmp->add_particles(start);
  lmp->run_steps(5);
  const std::vector<Particle> whole = lmp->read_particles();  // (the test's gather, to compare with)
  const double reach = 4.5 * kR;
  const LocalView view = lmp->local_view(reach);
  REQUIRE(view.indices.size() == view.own);
  REQUIRE(view.keys.size() == view.particles.size());
  // Every index own on exactly one rank, at the whole set's position.
  std::vector<uint64_t> owned(view.indices.begin(), view.indices.end());
  lmp->gather_over_processes(owned);
  std::sort(owned.begin(), owned.end());
  std::vector<uint64_t> every(whole.size());
  for (size_t i = 0; i < every.size(); ++i) every[i] = i;
  CHECK(owned == every);
  size_t misplaced = 0;
  for (size_t k = 0; k < view.own; ++k)
    misplaced += length(view.particles[k].position - whole[view.indices[k]].position) > 0 ||
                 view.particles[k].id != whole[view.indices[k]].id;
  CHECK(misplaced == 0);
  std::set<uint64_t> keys(view.keys.begin(), view.keys.end());
  CHECK(keys.size() == view.keys.size());
  const MpiWorld world = lammps_mpi_start();
  if (world.size == 1) {
    CHECK(view.complete());
    CHECK(view.own == whole.size());
    return;
  }
  // The halo: every other rank's sphere within the reach of this rank's
  // sub-domain, where the whole set has it.
  REQUIRE_FALSE(view.complete());
  CHECK(view.own < whole.size());
  CHECK(view.particles.size() < whole.size());
  std::set<uint64_t> own_ids, halo_ids;
  for (size_t k = 0; k < view.particles.size(); ++k) (k < view.own ? own_ids : halo_ids).insert(view.particles[k].id);
  const Box3& mine = view.regions[static_cast<size_t>(view.region)];
  size_t expected = 0, missing = 0;
  for (const Particle& p : whole)
    if (!own_ids.count(p.id) && distance_to_box(mine, p.position) <= reach) ++expected, missing += !halo_ids.count(p.id);
  CHECK(expected > 0);
  CHECK(missing == 0);
}

// A ball over-full by 1.6 times (a lattice of 1.5 r): the finish must
// delete, may fill holes, and ends within the bound with every centre
// inside, as the reference engine's finish in one process does; at 2 ranks
// no rank looks at every sphere in any round.
TEST_CASE("lammps engine: the finish per sub-domain holds the bound, each rank deciding on part of the spheres") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(kBall, kR / 3);
  const std::vector<Particle> start = lattice(1.5 * kR);
  REQUIRE(start.size() > 700);
  FinishSettings s;
  s.radius = kR;
  s.max_overlap = 0.001;
  s.first_id = start.size() + 1;
  FinishStats on_lammps, on_reference;
  // (each rank returns its own spheres: the whole, gathered, is checked on every rank)
  const ParticleSet out = gather_particles(
      *lammps_process_group(), finish_packing(lammps_engine_factory(), base_params(), field, start, s, on_lammps), true);
  const ParticleSet ref = finish_packing([](const EngineParams& p) { return std::make_unique<ReferenceEngine>(p); },
                                         base_params(), field, start, s, on_reference);
  INFO("LAMMPS " << out.size() << " spheres (" << on_lammps.removed << " deleted, " << on_lammps.inserted
                 << " inserted, " << on_lammps.rounds << " rounds, largest view " << on_lammps.largest_view
                 << "); reference " << ref.size() << " (" << on_reference.removed << " deleted, "
                 << on_reference.inserted << " inserted)");
  CHECK(on_lammps.removed > 0);
  CHECK(out.size() + on_lammps.removed == start.size() + on_lammps.inserted);
  CHECK(worst_overlap(out) <= 0.001);
  size_t outside = 0;
  for (const Vec3& p : out.positions) outside += length(p) > kBall - kR * (1 - 1e-3);
  CHECK(outside == 0);
  std::set<uint64_t> ids(out.ids.begin(), out.ids.end());
  CHECK(ids.size() == out.size());
  // The same packing as one process finds, to a few percent (the
  // relaxations differ: float sums in another order, deletions per rank).
  CHECK(std::fabs(static_cast<double>(out.size()) - static_cast<double>(ref.size())) <= 0.03 * ref.size());
  const MpiWorld world = lammps_mpi_start();
  // Its largest view: the first round's (the most spheres), at one
  // process all of them, at 2 ranks a part.
  if (world.size > 1) {
    CHECK(on_lammps.largest_view < start.size());
  } else {
    CHECK(on_lammps.largest_view >= out.size());
  }
}

// The fill hands the finish each rank's own spheres (ParticleEngine::
// local_view) at their places in the set (SetShare: in rank order), so no
// rank is given every sphere nor every id: split so (rank r: the r-th of P
// runs of the set, spread over the ball; LAMMPS sends each to the rank whose
// sub-domain holds it), the finish ends as from the whole set.
TEST_CASE("lammps engine: the finish takes the set split over the ranks, each id once") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(kBall, kR / 3);
  const std::vector<Particle> start = lattice(1.5 * kR);
  const MpiWorld world = lammps_mpi_start();
  const size_t ranks = static_cast<size_t>(world.size), rank = static_cast<size_t>(world.rank);
  SetShare share;
  share.first = start.size() * rank / ranks, share.total = start.size();
  const std::vector<Particle> mine(start.begin() + static_cast<ptrdiff_t>(share.first),
                                   start.begin() + static_cast<ptrdiff_t>(start.size() * (rank + 1) / ranks));
  FinishSettings s;
  s.radius = kR;
  s.max_overlap = 0.001;
  s.first_id = start.size() + 1;
  FinishStats split_stats, whole_stats;
  const std::shared_ptr<ProcessGroup> group = lammps_process_group();
  const ParticleSet split =
      gather_particles(*group, finish_packing(lammps_engine_factory(), base_params(), field, mine, share, s, split_stats), true);
  const ParticleSet whole =
      gather_particles(*group, finish_packing(lammps_engine_factory(), base_params(), field, start, s, whole_stats), true);
  INFO("split " << split.size() << " (" << split_stats.removed << " deleted), whole " << whole.size() << " ("
                << whole_stats.removed << " deleted)");
  CHECK(split.size() + split_stats.removed == start.size() + split_stats.inserted);
  CHECK(worst_overlap(split) <= 0.001);
  std::set<uint64_t> unique(split.ids.begin(), split.ids.end());
  CHECK(unique.size() == split.size());
  if (world.size == 1) {
    CHECK(split.positions == whole.positions);  // the same call: the same spheres
  } else {
    CHECK(std::fabs(static_cast<double>(split.size()) - static_cast<double>(whole.size())) <= 0.03 * whole.size());
  }
}

// The finish's last jams relaxed where they are (ParticleEngine::hold): on
// LAMMPS the spheres near a place move as on an engine of their own that
// holds only them and, as good as infinitely heavy, those around them
// (the reference engine here, as finish.cpp's relax_near builds it); held
// spheres and those out of it do not move at all; released, all move.
TEST_CASE("lammps engine: a hold moves the spheres near the places as an engine of their own, the rest still") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(kBall, kR / 3);
  std::vector<Particle> start = lattice(1.9 * kR);  // every neighbour 5% of r too close
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> jitter(-0.05 * kR, 0.05 * kR);  // so that no push cancels another
  for (Particle& q : start) q.position += Vec3(jitter(rng), jitter(rng), jitter(rng));
  EngineParams p = base_params();
  p.cutoff_sigma = 0;  // the finish's: purely repulsive, so no pair reaches from moving to out
  p.rest_distance = 2 * kR * 1.001;
  const std::vector<Vec3> places{{0.05, 0, 0}, {-0.4, 0.3, 0.1}};
  const double reach = 2.5 * kR, hold = 2.5 * kR;
  const NearRegion region = region_near(start, places, reach, hold);
  REQUIRE(region.moving.size() > 20);
  REQUIRE(region.held.size() > 20);
  REQUIRE(region.moving.size() + region.held.size() < start.size() / 2);

  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->share_field(field);
  lmp->add_particles(start);
  const std::optional<size_t> taking_part = lmp->hold(NearParts(places, reach, hold));
  REQUIRE(taking_part.has_value());
  CHECK(*taking_part == region.moving.size() + region.held.size());
  lmp->run_steps(200);
  const std::vector<Particle> held = lmp->read_particles();

  ReferenceEngine own(p);
  own.set_field(field);
  own.add_particles(region_particles(start, region, 1e30));
  own.run_steps(200);
  std::vector<Vec3> expected(start.size());
  for (size_t i = 0; i < start.size(); ++i) expected[i] = start[i].position;  // held and out: still
  for (const Particle& q : own.read_particles()) expected[q.id] = q.position;
  REQUIRE(held.size() == start.size());
  size_t moved = 0;
  double worst = 0;
  std::vector<bool> moving(start.size(), false);
  for (uint32_t i : region.moving) moving[i] = true;
  for (size_t i = 0; i < held.size(); ++i) {
    const size_t k = held[i].id - 1;  // lattice ids from 1, in order
    REQUIRE(k < start.size());
    if (!moving[k]) {
      CHECK(held[i].position == start[k].position);
      continue;
    }
    moved += length(held[i].position - start[k].position) > 1e-4 * kR;
    worst = std::max(worst, length(held[i].position - expected[k]));
  }
  INFO(moved << " of " << region.moving.size() << " moving spheres moved; worst difference " << worst);
  CHECK(moved > region.moving.size() / 2);
  CHECK(worst < 1e-9 * kR);

  lmp->release_hold();
  lmp->run_steps(5);
  const std::vector<Particle> released = lmp->read_particles();
  REQUIRE(released.size() == held.size());  // (both in the engine's order: nothing removed)
  size_t out_moved = 0;
  for (size_t i = 0; i < released.size(); ++i)
    if (!moving[released[i].id - 1]) out_moved += length(released[i].position - held[i].position) > 1e-6 * kR;
  CHECK(out_moved > start.size() / 4);
}

TEST_CASE("lammps engine: the finish's last jams relaxed where they are meet the bound as relaxing all does") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(kBall, kR / 3);
  const std::vector<Particle> start = lattice(1.5 * kR);
  FinishSettings s;
  s.radius = kR;
  s.max_overlap = 0.001;
  s.hole_rounds = 0;
  s.first_id = start.size() + 1;
  s.near_share = 0;
  FinishStats all, near;
  const std::shared_ptr<ProcessGroup> group = lammps_process_group();
  const ParticleSet by_all =
      gather_particles(*group, finish_packing(lammps_engine_factory(), base_params(), field, start, s, all), true);
  s.near_share = 1;
  s.near_min_spheres = 0;
  s.near_reach = 3;
  const ParticleSet by_near =
      gather_particles(*group, finish_packing(lammps_engine_factory(), base_params(), field, start, s, near), true);
  INFO("all: " << all.steps << " steps, " << by_all.size() << " spheres; near: " << near.steps << " steps, "
               << by_near.size() << " spheres, " << near.near_rounds << " of " << near.rounds << " relaxations near");
  CHECK(all.near_rounds == 0);
  CHECK(near.near_rounds > 0);
  CHECK(near.near_rounds < near.rounds);  // the first is of all
  CHECK(worst_overlap(by_near) <= 0.001);
  CHECK(near.forced == 0);
  CHECK(by_near.size() + near.removed == start.size() + near.inserted);
  CHECK(std::fabs(static_cast<double>(by_near.size()) - static_cast<double>(by_all.size())) <= 0.03 * by_all.size());
  for (const Vec3& q : by_near.positions) CHECK(length(q) <= kBall - kR * (1 - 1e-3));
}

// Unequal spheres per sub-domain (issue 31): the size classes' counts are
// sums over the ranks, and every rank walks every rank's holes alike to
// give them radii. A ball over-full by a 1:1.4 mix (radii 0.085 and 0.119
// drawn at random on a lattice of 2 small radii) with three holes carved
// out: at 2 ranks the finish holds the bound of each pair's smaller
// radius with no rank looking at every sphere, fills holes, and ends as
// one process's reference finish does, to a few percent, the classes near
// their halves.
TEST_CASE("lammps engine: the finish of unequal spheres per sub-domain keeps the bound and the classes' shares") {
  if (!lammps_available()) return;
  constexpr double r = 0.085;
  const ScalarGrid field = test::ball_field(kBall, r / 3);
  const std::vector<Vec3> holes{{0.45, 0.1, 0}, {-0.45, -0.1, 0.1}, {0.02, 0.4, -0.2}};
  std::vector<Particle> start;
  std::mt19937 rng(11);
  const int n = static_cast<int>(kBall / (2 * r)) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        Particle q;
        q.position = Vec3(i, j, k) * (2 * r) + Vec3(0.003, -0.002, 0.001);
        q.radius = rng() % 2 ? 1.4 * r : r;
        bool carved = false;
        for (const Vec3& h : holes) carved = carved || length(q.position - h) < 3.2 * r;
        if (carved || length(q.position) > kBall - q.radius) continue;
        q.id = start.size() + 1;
        start.push_back(q);
      }
  FinishSettings s;
  s.radius = r;
  s.sizes = RadiusDistribution::parse("discrete:0.085:0.5,0.119:0.5");
  s.fire = false;  // (the fill's relaxation of unequal spheres)
  s.max_overlap = 0.001;
  s.first_id = start.size() + 1;
  EngineParams p = base_params();
  p.radius = r;
  p.max_radius = 1.4 * r * (1 + 1e-6);
  FinishStats on_lammps, on_reference;
  const ParticleSet out = gather_particles(
      *lammps_process_group(), finish_packing(lammps_engine_factory(), p, field, start, s, on_lammps), true);
  const ParticleSet ref = finish_packing([](const EngineParams& e) { return std::make_unique<ReferenceEngine>(e); },
                                         p, field, start, s, on_reference);
  size_t large = 0, large_ref = 0;
  for (double q : out.radii) large += q > 1.2 * r;
  for (double q : ref.radii) large_ref += q > 1.2 * r;
  INFO("LAMMPS " << out.size() << " spheres, " << large << " large (" << on_lammps.removed << " deleted, "
                 << on_lammps.inserted << " inserted, largest view " << on_lammps.largest_view << " of "
                 << start.size() << "); reference " << ref.size() << ", " << large_ref << " large ("
                 << on_reference.inserted << " inserted)");
  CHECK(on_lammps.removed > 0);
  CHECK(on_lammps.inserted > 0);
  CHECK(out.size() + on_lammps.removed == start.size() + on_lammps.inserted);
  CHECK(worst_overlap(out) <= 0.001);
  size_t outside = 0;
  for (size_t i = 0; i < out.size(); ++i) outside += length(out.positions[i]) > kBall - out.radii[i] * (1 - 1e-2);
  CHECK(outside == 0);
  CHECK(std::set<uint64_t>(out.ids.begin(), out.ids.end()).size() == out.size());
  CHECK(std::fabs(static_cast<double>(out.size()) - static_cast<double>(ref.size())) <= 0.05 * ref.size());
  CHECK(std::fabs(static_cast<double>(large) / static_cast<double>(out.size()) - 0.5) <= 0.03);
  if (lammps_mpi_start().size > 1) {
    CHECK(on_lammps.largest_view < start.size());
    CHECK_FALSE(on_lammps.regions.empty());  // the result in parts
  }
}

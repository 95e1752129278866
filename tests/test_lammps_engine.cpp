// The LAMMPS engine (src/lammps/lammps_engine.cpp) against the C++
// reference engine on the same input, its bookkeeping (births, removals,
// ids, flags), and a small fill on it, finish included. ctest runs this
// file as it is (one process: MPI as a singleton) and under
// `mpirun -np 2` (tests/CMakeLists.txt: mpi2.test_lammps_engine), where
// every rank runs the same calls and LAMMPS splits the atoms between them.
// Without LAMMPS built in, only the one-line refusal is checked.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "fill/site_verdicts.hpp"
#include "lammps/birth_tally.hpp"
#include "lammps/particle_book.hpp"
#include "pfill/birth_sites.hpp"
#include "lammps_fixtures.hpp"
#include "pfill/engine/reference.hpp"
#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/lammps.hpp"
#include "pfill/boundary.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/particle_share.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

using test::small_params;

// Particles on a jittered lattice inside the ball, some overlapping, moving.
std::vector<Particle> lattice(double R, double spacing, uint64_t seed) {
  return test::jittered_lattice(R, spacing, seed, 0.08, 100);
}

Vec3 momentum(const std::vector<Particle>& ps) {
  Vec3 m;
  for (const Particle& p : ps) m += p.velocity * p.mass;
  return m;
}


/// Runs `ref` and `lmp` 3 x 10 steps side by side, checking each step's
/// record alike; returns the most colliding pairs of any step.
uint32_t steps_side_by_side(ReferenceEngine& ref, ParticleEngine& lmp) {
  uint32_t pairs = 0;
  for (int round = 0; round < 3; ++round) {
    ref.run_steps(10);
    lmp.run_steps(10);
    const std::vector<StepRecord> hr = ref.read_history(), hl = lmp.read_history();
    REQUIRE(hl.size() == hr.size());
    for (size_t s = 0; s < hr.size(); ++s) {
      pairs = std::max(pairs, hr[s].colliding_pairs);
      CHECK(hl[s].step == hr[s].step);
      CHECK(hl[s].particles == hr[s].particles);
      CHECK(hl[s].colliding_pairs == hr[s].colliding_pairs);
      CHECK(hl[s].flagged == hr[s].flagged);
      CHECK(hl[s].kinetic_energy == doctest::Approx(hr[s].kinetic_energy).epsilon(1e-6));
      CHECK(hl[s].max_speed == doctest::Approx(hr[s].max_speed).epsilon(1e-6));
    }
  }
  return pairs;
}

// A LAMMPS engine of small_params() on `field` (which must outlive it),
// holding `start`, run `steps` steps.
std::unique_ptr<ParticleEngine> lattice_engine(const ScalarGrid& field, const std::vector<Particle>& start, int steps) {
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(small_params());
  lmp->share_field(field);
  lmp->add_particles(start);
  lmp->run_steps(steps);
  return lmp;
}

}  // namespace

TEST_CASE("lammps engine: without LAMMPS built in, one line says so") {
  if (lammps_available()) {
    CHECK(lammps_mpi_start().size >= 1);
    return;
  }
  CHECK_THROWS_WITH_AS(make_lammps_engine(small_params()), doctest::Contains("built without LAMMPS"), Error);
}

TEST_CASE("lammps engine: the same steps as the reference engine (positions, records, momentum)") {
  if (!lammps_available()) return;
  const EngineParams p = small_params();
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  const std::vector<Particle> start = lattice(0.5, 0.098, 7);
  REQUIRE(start.size() > 200);

  ReferenceEngine ref(p);
  ref.set_field(field);
  ref.add_particles(start);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->share_field(field);
  CHECK(lmp->add_particles(start) == 0);
  REQUIRE(lmp->size() == start.size());
  CHECK(lmp->describe().find("LAMMPS") != std::string::npos);

  const Vec3 p0 = momentum(lmp->read_particles());
  steps_side_by_side(ref, *lmp);
  const std::vector<Particle> a = ref.read_particles(), b = lmp->read_particles();
  REQUIRE(a.size() == b.size());
  double worst = 0, worst_v = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(b[i].id == a[i].id);
    worst = std::max(worst, length(a[i].position - b[i].position));
    worst_v = std::max(worst_v, length(a[i].velocity - b[i].velocity));
    CHECK(length(b[i].position) <= 0.5 - 0.05 + 1e-3);  // inside the ball's wall
  }
  INFO("largest position difference " << worst << ", velocity " << worst_v);
  CHECK(worst < 1e-9);
  CHECK(worst_v < 1e-7);
  CHECK(lmp->steps_done() == 30);
  (void)p0;
}

// Unequal spheres (radii 0.05 and 0.08): each pair's lengths scale with
// its radii on LAMMPS as on the other engines (the callback's pair scales,
// the list's reach at the largest pair's).
TEST_CASE("lammps engine: unequal spheres take the same steps as the reference engine") {
  if (!lammps_available()) return;
  EngineParams p = small_params();
  p.max_radius = 0.08 * (1 + 1e-6);
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  std::vector<Particle> start = test::jittered_lattice(0.5, 0.13, 5, 0.08, 100);
  for (size_t i = 0; i < start.size(); i += 3) start[i].radius = 0.08;
  REQUIRE(start.size() > 100);
  ReferenceEngine ref(p);
  ref.set_field(field);
  ref.add_particles(start);
  REQUIRE(ref.constants().polydisperse);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->share_field(field);
  lmp->add_particles(start);
  CHECK(steps_side_by_side(ref, *lmp) > 10);  // large and small spheres overlap: the scales are at work
  const std::vector<Particle> a = ref.read_particles(), b = lmp->read_particles();
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, length(a[i].position - b[i].position));
  INFO("largest position difference " << worst);
  CHECK(worst < 1e-9);
}

// `--radii` on LAMMPS: hard within the bound of each pair's smaller radius,
// inside, both classes at their shares, the count the OpenCL engine gives
// (500 at radii 1:2, half each: 495 at 0.6014 on it, 493 at 0.5990 here at
// 1 and 2 ranks, seed 1; 491 at 2 ranks since each finishes its own).
// At 2 ranks the result is in parts, as for equal spheres: each rank's own
// spheres, fewer than all, gathered here to check every pair; the fit of
// the radii, summed over the ranks, is the whole's.
TEST_CASE("lammps engine: a fill of unequal spheres, hard and inside, each class at its share") {
  if (!lammps_available()) return;
  FillOptions o;
  o.count = 500;
  o.seed = 1;
  o.radii = RadiusDistribution::parse("discrete:1:0.5,2:0.5");
  o.colour = ColourOptions{ColourMode::None, {}};
  o.engine = lammps_engine_factory();
  o.finish_on_engine = true;
  o.wall_from_mesh = true;
  const FillResult r = fill(make_icosphere(1.0, 4), o);
  INFO("particles " << r.metrics.count << ", packing " << r.metrics.packing_fraction << ", largest overlap "
                    << r.metrics.max_overlap);
  const bool several = lammps_mpi_start().size > 1;
  CHECK(r.in_parts == several);
  const ParticleSet all = gather_particles(*lammps_process_group(), r.particles, true);
  REQUIRE(all.size() == r.metrics.count);
  if (several) CHECK(r.particles.size() < all.size());
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_overlap <= o.max_overlap + 1e-9);
  double worst = 0;  // every pair, of its smaller radius
  for (size_t i = 0; i < all.size(); ++i)
    for (size_t j = i + 1; j < all.size(); ++j) {
      const double ri = all.radii[i], rj = all.radii[j];
      worst = std::max(worst, (ri + rj - length(all.positions[i] - all.positions[j])) / std::min(ri, rj));
    }
  CHECK(worst <= o.max_overlap + 1e-9);
  REQUIRE(r.radii_fit);
  REQUIRE(r.radii_fit->classes.size() == 2);
  const DistributionFit whole = compare_distribution(*r.radii, all.radii);
  CHECK(r.radii_fit->distance == doctest::Approx(whole.distance).epsilon(1e-12));
  for (const auto& c : r.radii_fit->classes) CHECK(std::abs(c.achieved_number - 0.5) < 0.03);
  CHECK(r.metrics.count >= 470);
  CHECK(r.metrics.count <= 520);
  CHECK(r.metrics.packing_fraction > 0.58);
}

TEST_CASE("lammps engine: momentum is conserved without a wall or damping") {
  if (!lammps_available()) return;
  EngineParams p = small_params();
  p.damping = 0;
  p.domain = Box3{{-0.6, -0.6, -0.6}, {0.6, 0.6, 0.6}};
  std::vector<Particle> start = lattice(0.3, 0.095, 11);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->add_particles(start);
  const Vec3 m0 = momentum(lmp->read_particles());
  lmp->run_steps(40);
  const std::vector<StepRecord> h = lmp->read_history();
  REQUIRE(h.size() == 40);
  CHECK(h.back().colliding_pairs > 0);  // the lattice overlaps: forces and dashpots act
  const std::vector<Particle> now = lmp->read_particles();
  const Vec3 m1 = momentum(now);
  INFO("momentum before " << m0.x << "," << m0.y << "," << m0.z << " after " << m1.x << "," << m1.y << "," << m1.z);
  CHECK(length(m1 - m0) < 1e-10 * (1 + length(m0)));
}

TEST_CASE("lammps engine: births, removals, flags and ids as the reference keeps them") {
  if (!lammps_available()) return;
  const EngineParams p = small_params();
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  ReferenceEngine ref(p);
  ref.set_field(field);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->share_field(field);
  std::vector<Particle> start = lattice(0.5, 0.11, 3);
  // One particle outside the wall: flagged by both after a step.
  Particle out;
  out.position = {0.52, 0, 0};
  out.radius = 0.05;
  out.id = 9999;
  start.push_back(out);
  ref.add_particles(start);
  lmp->add_particles(start);
  ref.run_steps(1);
  lmp->run_steps(1);
  CHECK(lmp->read_history().back().flagged == ref.read_history().back().flagged);
  CHECK(lmp->flagged_particles() == ref.flagged_particles());
  lmp->clear_flags();
  ref.clear_flags();
  const std::vector<size_t> gone = {3, 0, static_cast<size_t>(start.size() - 1), 17};
  ref.remove_particles(gone);
  lmp->remove_particles(gone);
  REQUIRE(lmp->size() == ref.size());
  // Newborns where the removed ones were (room there: no deep overlaps,
  // where the reference's pair force cap, which LAMMPS lacks, would act).
  std::vector<Particle> more;
  for (size_t k : {size_t(3), size_t(0), size_t(17)}) {
    Particle q = start[k];
    q.id += 5000;
    q.velocity = {0.1, -0.1, 0.05};
    more.push_back(q);
  }
  CHECK(lmp->add_particles(more) == ref.add_particles(more));
  ref.run_steps(5);
  lmp->run_steps(5);
  const std::vector<Particle> a = ref.read_particles(), b = lmp->read_particles();
  REQUIRE(a.size() == b.size());
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].id == b[i].id);
    worst = std::max(worst, length(a[i].position - b[i].position));
  }
  CHECK(worst < 1e-9);
  // LAMMPS keeps its own order: a sort names no new order, and the indices stay.
  CHECK(lmp->sort_by_cells().empty());
  const std::vector<Particle> sorted = lmp->read_particles();
  REQUIRE(sorted.size() == b.size());
  for (size_t i = 0; i < b.size(); ++i) CHECK(sorted[i].id == b[i].id);
}

TEST_CASE("lammps engine: what LAMMPS would stop the program on is refused first, in one line") {
  // LAMMPS (Debian's, no C++ exceptions) exits on an error, silently under
  // -screen none: the engine refuses these before handing them over, on
  // every rank alike, so the fill's one-line error says why.
  if (!lammps_available()) return;
  SUBCASE("a domain that is no box") {
    EngineParams p = small_params();
    p.domain = Box3{{-1, -1, -1}, {1, std::numeric_limits<double>::infinity(), 1}};
    CHECK_THROWS_WITH_AS(make_lammps_engine(p), doctest::Contains("is not a box"), Error);
    p.domain = Box3{{-1, 1, -1}, {1, -1, 1}};  // lo > hi on y only (Box3::empty looks at x)
    CHECK_THROWS_WITH_AS(make_lammps_engine(p), doctest::Contains("is not a box"), Error);
  }
  SUBCASE("a box far larger than the spheres: too many neighbour-list bins") {
    EngineParams p = small_params();
    p.radius = 1e-4;
    p.max_radius = p.radius * (1 + 1e-6);
    p.domain = Box3{{-1, -1, -1}, {1, 1, 1}};  // (2 / 1.4e-4)^3 ~ 3e12 bins
    CHECK_THROWS_WITH_AS(make_lammps_engine(p), doctest::Contains("neighbour-list bins"), Error);
  }
  SUBCASE("a particle not at a finite place") {
    std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(small_params());
    Particle q;
    q.radius = 0.05;
    q.position = {0, std::nan(""), 0};
    CHECK_THROWS_WITH_AS(lmp->add_particles({q}), doctest::Contains("not a finite number"), Error);
    CHECK(lmp->size() == 0);
    q.position = {0, 0, 0};  // the engine still works after the refusal
    CHECK(lmp->add_particles({q}) == 0);
    lmp->run_steps(2);
    CHECK(lmp->read_particles().size() == 1);
  }
  SUBCASE("an id past what the atom's id property holds exactly (2^53)") {
    std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(small_params());
    Particle q;
    q.radius = 0.05;
    q.id = (uint64_t{1} << 53) + 1;
    CHECK_THROWS_WITH_AS(lmp->add_particles({q}), doctest::Contains("is past 2^53"), Error);
    CHECK_THROWS_WITH_AS(lmp->add_decided_particles({q}, {0}, 1), doctest::Contains("is past 2^53"), Error);
    CHECK(lmp->size() == 0);
    q.id = uint64_t{1} << 53;  // the largest it takes, kept exactly
    CHECK(lmp->add_particles({q}) == 0);
    CHECK(lmp->read_particles()[0].id == q.id);
  }
}

TEST_CASE("lammps engine: a small fill of a sphere, the finish on LAMMPS too") {
  if (!lammps_available()) return;
  FillOptions o;
  o.count = 300;
  o.seed = 2;
  o.colour = ColourOptions{ColourMode::None, {}};
  o.engine = lammps_engine_factory();
  o.finish_on_engine = true;
  std::string logged;
  o.log = [&logged](const std::string& line) { logged += line + "\n"; };
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  CHECK(logged.find("LAMMPS") != std::string::npos);
  INFO("particles " << r.metrics.count << ", packing " << r.metrics.packing_fraction << ", largest overlap "
                    << r.metrics.max_overlap << ", stop " << r.stop_reason);
  bool left_out = false;
  for (const std::string& w : r.warnings) left_out = left_out || w.find("finish was left out") != std::string::npos;
  CHECK_FALSE(left_out);
  CHECK(r.finish_rounds >= 1);
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_overlap <= o.max_overlap + 1e-9);
  // The OpenCL engine packs a sphere at -n 300 to 0.55-0.60 (about 290-310 spheres).
  CHECK(r.metrics.count >= 250);
  CHECK(r.metrics.count <= 340);
  CHECK(r.metrics.packing_fraction > 0.5);
  // Issue 31: each rank ends with its own spheres, none with all; together
  // they are the set the metrics, measured over the ranks, describe.
  const std::shared_ptr<ProcessGroup> group = lammps_process_group();
  const ParticleSet all = gather_particles(*group, r.particles, true);
  CHECK(all.size() == r.metrics.count);
  CHECK(std::set<uint64_t>(all.ids.begin(), all.ids.end()).size() == all.size());
  CHECK(r.in_parts == (group->size() > 1));
  if (group->size() > 1) CHECK(r.particles.size() < r.metrics.count);
  MetricsOptions mo;
  mo.holes = false;
  const PackingMetrics whole = measure_packing(Boundary(make_icosphere(1.0, 3)), r.metrics.mesh_volume, all, mo);
  CHECK(whole.packing_fraction == doctest::Approx(r.metrics.packing_fraction).epsilon(1e-12));
  CHECK(whole.overlapping_pairs == r.metrics.overlapping_pairs);
  CHECK(whole.max_overlap == r.metrics.max_overlap);
  CHECK(whole.mean_coordination == doctest::Approx(r.metrics.mean_coordination).epsilon(1e-12));
  CHECK(whole.max_penetration == r.metrics.max_penetration);
}

// Issue 31: the births' room test per rank. Each site is decided by the one
// rank whose sub-domain holds it, on that rank's atoms and the others'
// within the reach of its sub-domain: the verdicts shared over the ranks
// are the verdicts of the whole set, and at 2 ranks no rank holds every atom.
TEST_CASE("lammps engine: the births' view per rank gives every site the verdict of the whole set") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  const std::vector<Particle> start = lattice(0.5, 0.11, 5);
  std::unique_ptr<ParticleEngine> lmp = lattice_engine(field, start, 20);
  const double reach = 0.08;  // less than the lattice's spacing: room between its points
  const BirthView whole = lmp->birth_view(reach, true);
  const BirthView mine = lmp->birth_view(reach, false);
  REQUIRE(whole.complete());
  REQUIRE(whole.centres.size() == start.size());
  const MpiWorld world = lammps_mpi_start();
  if (world.size > 1) {
    CHECK_FALSE(mine.complete());
    CHECK(mine.centres.size() < start.size());
  }
  // Sites on a lattice through the ball, some with room and some without.
  std::vector<BirthSite> sites;
  for (double x = -0.45; x <= 0.45; x += 0.037)
    for (double y = -0.45; y <= 0.45; y += 0.041)
      for (double z = -0.45; z <= 0.45; z += 0.043)
        if (length(Vec3{x, y, z}) < 0.45) sites.push_back({{x, y, z}, 0});
  const RoomGrid all(whole.centres, reach), near(mine.centres, reach);
  std::vector<int> expected(sites.size(), 0), got(sites.size(), 0), deciders(sites.size(), 0);
  for (size_t k = 0; k < sites.size(); ++k) {
    expected[k] = all.has_room(sites[k].position) ? 1 : 0;
    deciders[k] = mine.decides(sites[k].position) ? 1 : 0;
    got[k] = deciders[k] && near.has_room(sites[k].position) ? 1 : 0;
  }
  share_verdicts(*lmp, mine, got);  // as the fill shares them: the sites with room, gathered
  if (!mine.complete()) lmp->sum_over_processes(deciders);
  int with_room = 0;
  for (size_t k = 0; k < sites.size(); ++k) with_room += expected[k];
  INFO(sites.size() << " sites, " << with_room << " with room");
  CHECK(with_room > 0);
  CHECK(with_room < static_cast<int>(sites.size()));
  CHECK(deciders == std::vector<int>(sites.size(), 1));
  CHECK(got == expected);
}

// The verdicts' gather: every rank's values, in rank order, on every
// rank, whatever each rank's count (rank r gives r + 1 values, rank 1 none
// when there are 3 or more).
TEST_CASE("lammps engine: a gather over the ranks gives every rank's values in rank order") {
  if (!lammps_available()) return;
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(small_params());
  const MpiWorld world = lammps_mpi_start();
  auto given = [&](int r) {
    std::vector<uint64_t> v;
    if (r == 1 && world.size > 2) return v;
    for (int k = 0; k <= r; ++k) v.push_back(1000 * static_cast<uint64_t>(r) + static_cast<uint64_t>(k) + (1ull << 40));
    return v;
  };
  std::vector<uint64_t> expected;
  for (int r = 0; r < world.size; ++r) {
    const std::vector<uint64_t> v = given(r);
    expected.insert(expected.end(), v.begin(), v.end());
  }
  std::vector<uint64_t> got = given(world.rank);
  lmp->gather_over_processes(got);
  CHECK(got == expected);
}

// Issue 31: a fill's first waves on LAMMPS (at this process count) birth
// the same newborns, with the same ids, as on the reference engine in one
// process: each newborn's draws are keyed by (seed, step, site), not by
// the order sites were tried in, and each site's room test runs on the
// rank that holds it. Frames after the first three waves are compared.
TEST_CASE("lammps engine: the first waves' newborns as on one process") {
  if (!lammps_available()) return;
  // Unequal spheres (src/fill/size_wave.cpp): each rank tests its own
  // sites for every size class, every rank walks the answers alike, so
  // the newborns and their ids are one process's at any rank count.
  // Room sites a rest distance apart may crowd each other across a
  // border: their waves are gathered and chosen alike on every rank, in
  // key order (FillPasses::wave_sites), so the ids are one process's too.
  bool unequal = false, close_rooms = false;
  SUBCASE("equal spheres") {}
  SUBCASE("unequal spheres") { unequal = true; }
  SUBCASE("room sites a rest distance apart") { close_rooms = true; }
  auto frames_of = [unequal, close_rooms](std::function<std::unique_ptr<ParticleEngine>(const EngineParams&)> engine) {
    FillOptions o;
    o.count = 2000;
    if (unequal) o.radii = RadiusDistribution::parse("lognormal:1,0.2");
    if (close_rooms) o.room_spacing = 1.0;
    o.sites = 0;  // waves
    o.seed = 7;
    // Slow newborns: no collision deep enough for the reference's pair
    // force cap (which LAMMPS lacks) to act, so the trajectories agree.
    o.birth_speed = {0.02, 0.05};
    o.colour = ColourOptions{ColourMode::None, {}};
    o.engine = std::move(engine);
    o.frame_every = unequal ? 240 : 48;  // (unequal spheres: no room sites, slower growth)
    std::vector<ParticleSet> frames;
    o.on_frame = [&frames](uint64_t, const ParticleSet& s) { frames.push_back(s); };
    o.cancelled = [&frames] { return frames.size() >= 3; };
    CHECK_THROWS_AS(fill(make_icosphere(1.0, 3), o), Cancelled);
    return frames;
  };
  const std::vector<ParticleSet> ref = frames_of([](const EngineParams& p) {
    return std::unique_ptr<ParticleEngine>(std::make_unique<ReferenceEngine>(p));
  });
  const std::vector<ParticleSet> lmp = frames_of(lammps_engine_factory());
  REQUIRE(ref.size() == 3);
  REQUIRE(lmp.size() == 3);
  if (lammps_mpi_start().rank != 0) {  // each frame gathered to the first rank only
    for (const ParticleSet& f : lmp) CHECK(f.size() == 0);
    return;
  }
  // At several ranks a wave's newborns are numbered in the ranks' order
  // (src/fill/wave_choice.hpp): the same ids, given to the same spheres
  // in another order; each sphere is matched by place.
  const bool one_rank = unequal || close_rooms || lammps_mpi_start().size == 1;
  for (size_t f = 0; f < 3; ++f) {
    INFO("frame " << f << ": " << ref[f].size() << " on the reference, " << lmp[f].size() << " on LAMMPS");
    REQUIRE(ref[f].size() == lmp[f].size());
    std::vector<uint64_t> ref_ids = ref[f].ids, lmp_ids = lmp[f].ids;
    if (!one_rank) std::sort(ref_ids.begin(), ref_ids.end()), std::sort(lmp_ids.begin(), lmp_ids.end());
    REQUIRE(ref_ids == lmp_ids);
    double worst = 0;
    size_t at = 0;
    for (size_t i = 0; i < ref[f].size(); ++i) {
      double d = length(ref[f].positions[i] - lmp[f].positions[i]);
      for (size_t j = 0; !one_rank && j < lmp[f].size(); ++j) d = std::min(d, length(ref[f].positions[i] - lmp[f].positions[j]));
      if (d > worst) worst = d, at = i;
    }
    INFO("worst at id " << ref[f].ids[at] << " index " << at);
    CHECK(worst < 1e-6);
  }
  CHECK(ref[2].size() > ref[0].size());
}

// Issue 31: births split over the ranks. Each rank hands LAMMPS only the
// newborns it decided (ParticleEngine::add_decided_particles) with their
// places in the batch, and none is given the batch's ids, yet each newborn
// gets the index of its place and keeps its id; a newborn a rank gives
// from outside its sub-domain (decided on an older one) is sent on and
// still created once.
TEST_CASE("lammps engine: births split over the ranks, booked on every rank") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  const std::vector<Particle> start = lattice(0.5, 0.11, 5);
  std::unique_ptr<ParticleEngine> lmp = lattice_engine(field, start, 5);
  const BirthView view = lmp->birth_view(0.08, false);
  // Births between the lattice's points, ids of their own.
  std::vector<Particle> births = lattice(0.44, 0.11, 6);
  for (Particle& b : births) b.position += Vec3{0.055, 0.055, 0.055}, b.id += 5000;
  const MpiWorld world = lammps_mpi_start();
  const lammps_engine::BirthTally before = lammps_engine::birth_tally();
  std::vector<Particle> mine;
  std::vector<size_t> places;
  auto give = [&](size_t k) { mine.push_back(births[k]), places.push_back(k); };
  bool all_on_rank_0 = false;
  SUBCASE("each rank gives the births at its own sites") {
    for (size_t k = 0; k < births.size(); ++k)
      if (view.decides(births[k].position)) give(k);
  }
  SUBCASE("rank 0 gives them all (the last first): the others' sent on") {
    all_on_rank_0 = true;
    if (world.rank == 0)
      for (size_t k = births.size(); k-- > 0;) give(k);
  }
  SUBCASE("all in rank 0's sub-domain: the others give none") {
    std::vector<Particle> kept;
    for (const Particle& b : births)
      if (view.complete() || owning_region(view.regions, b.position) == 0) kept.push_back(b);
    births = kept;
    for (size_t k = 0; k < births.size(); ++k)
      if (view.decides(births[k].position)) give(k);
    if (world.rank > 0) CHECK(mine.empty());
  }
  REQUIRE_FALSE(births.empty());
  const size_t first = lmp->add_decided_particles(mine, places, births.size());
  const lammps_engine::BirthTally after = lammps_engine::birth_tally();
  CHECK(first == start.size());
  CHECK(after.newborns - before.newborns == births.size());
  const uint64_t sent = after.outside - before.outside;
  if (!all_on_rank_0 || world.size == 1) CHECK(sent == 0);
  if (all_on_rank_0 && world.size > 1 && world.rank == 0) CHECK(sent > 0);
  const std::vector<Particle> out = lmp->read_particles();
  REQUIRE(out.size() == start.size() + births.size());
  for (size_t k = 0; k < births.size(); ++k) {
    CHECK(out[first + k].id == births[k].id);
    CHECK(length(out[first + k].position - births[k].position) == 0.0);
    CHECK(out[first + k].radius == births[k].radius);
  }
}

// Issue 31: in a fill's waves each rank creates only its own sub-domain's
// newborns: the counts the ranks passed to lammps_create_atoms sum to the
// waves' births (each newborn handed over by exactly one rank), and none
// a rank passed lay outside its sub-domain then.
TEST_CASE("lammps engine: a fill's waves, each newborn created by the rank whose sub-domain holds it") {
  if (!lammps_available()) return;
  lammps_engine::birth_tally() = {};
  FillOptions o;
  o.count = 2000;
  o.sites = 0;  // waves
  o.seed = 7;
  SUBCASE("equal spheres") {}
  SUBCASE("unequal spheres") { o.radii = RadiusDistribution::parse("discrete:1:0.5,2:0.5"); }
  o.colour = ColourOptions{ColourMode::None, {}};
  o.engine = lammps_engine_factory();
  int batches = 0;
  o.cancelled = [&batches] { return ++batches > 12; };
  CHECK_THROWS_AS(fill(make_icosphere(1.0, 3), o), Cancelled);
  const lammps_engine::BirthTally t = lammps_engine::birth_tally();
  INFO(t.batches << " waves, " << t.newborns << " newborns, " << t.passed << " passed here, " << t.outside
                 << " outside");
  CHECK(t.batches >= 5);
  CHECK(t.newborns > 100);
  CHECK(t.outside == 0);
  std::vector<int> passed = {static_cast<int>(t.passed)};
  make_lammps_engine(small_params())->sum_over_processes(passed);
  CHECK(passed[0] == static_cast<int>(t.newborns));
  if (lammps_mpi_start().size > 1) {
    CHECK(t.passed > 0);
    CHECK(t.passed < t.newborns);
  }
}

// A batch's places must be given once each over the ranks (two atoms with
// one tag would stop LAMMPS at its next run): refused in one line on every
// rank, before LAMMPS sees them, the engine unchanged.
TEST_CASE("lammps engine: a batch whose places are not each given once is refused") {
  if (!lammps_available()) return;
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  std::unique_ptr<ParticleEngine> lmp = lattice_engine(field, lattice(0.5, 0.11, 5), 5);
  const size_t before = lmp->size();
  const MpiWorld world = lammps_mpi_start();
  Particle a, b;
  a.radius = b.radius = 0.05;
  a.id = 7001, b.id = 7002;
  b.position = {0.1, 0, 0};
  std::vector<Particle> mine;
  std::vector<size_t> places;
  if (world.rank == 0) mine = {a, b}, places = {1, 1};  // place 0 missing, place 1 twice
  CHECK_THROWS_WITH_AS(lmp->add_decided_particles(mine, places, 2), doctest::Contains("not each place once"), Error);
  CHECK(lmp->size() == before);
  if (world.rank == 0) places = {1, 0};
  CHECK(lmp->add_decided_particles(mine, places, 2) == before);
  const std::vector<Particle> out = lmp->read_particles();
  REQUIRE(out.size() == before + 2);
  CHECK(out[before].id == 7002);
  CHECK(out[before + 1].id == 7001);
}

TEST_CASE("an engine of one process takes a birth batch whole, in its places' order") {
  ReferenceEngine ref(small_params());
  Particle a, b;
  a.radius = b.radius = 0.05;
  a.id = 9, b.id = 10;
  b.position = {0.2, 0, 0};
  CHECK(ref.add_decided_particles({b, a}, {1, 0}, 2) == 0);
  REQUIRE(ref.size() == 2);
  const std::vector<Particle> out = ref.read_particles();
  CHECK(out[0].id == 9);
  CHECK(out[1].id == 10);
  CHECK_THROWS_WITH_AS(ref.add_decided_particles({}, {}, 1), doctest::Contains("one process must give them all"),
                       Error);
  CHECK_THROWS_WITH_AS(ref.add_decided_particles({a, b}, {1, 1}, 2), doctest::Contains("each of 0..1 once"), Error);
  CHECK(ref.size() == 2);
}

// Issue 31: the LAMMPS engine keeps no record of every particle; its book
// works out from the removed indices alone where the survivors go. That
// must be what removing from an array does, the last into each hole from
// the largest index down (the other engines' rule, Engine::remove_particles).
TEST_CASE("the LAMMPS engine's book moves indices on removal as the array's swaps do") {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    const size_t n = 1 + rng() % 60;
    lammps_engine::ParticleBook book;
    book.added(n);
    std::vector<size_t> labels(n);  // the array: who sits at each index
    for (size_t i = 0; i < n; ++i) labels[i] = i;
    std::vector<size_t> removed;
    const size_t k = rng() % (n + 1);
    for (size_t j = 0; j < k; ++j) removed.push_back(rng() % n);  // repeats too
    std::vector<size_t> desc = removed;
    std::sort(desc.begin(), desc.end(), std::greater<size_t>());
    desc.erase(std::unique(desc.begin(), desc.end()), desc.end());
    for (size_t idx : desc) labels[idx] = labels.back(), labels.pop_back();
    const lammps_engine::Removal r = book.remove(removed);
    REQUIRE(book.size() == labels.size());
    CHECK(r.gone == std::vector<size_t>(desc.rbegin(), desc.rend()));
    std::vector<size_t> after(n, n);  // each original's new index (n: gone or unmoved)
    for (const auto& [from, to] : r.moves) after[from] = to;
    for (size_t i = 0; i < labels.size(); ++i) {
      const size_t original = labels[i];
      const size_t expected = original != i ? i : n;  // moved here, or never moved
      CHECK(after[original] == expected);
    }
  }
  lammps_engine::ParticleBook book;
  CHECK(book.new_tags(3) == 1);  // tags never given twice, removals or not
  book.added(3);
  CHECK(book.new_tags(2) == 4);
  CHECK_THROWS_WITH_AS(book.remove({1, 3}), doctest::Contains("cannot remove particle 3 of 3"), Error);
  CHECK(book.size() == 3);
}


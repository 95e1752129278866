// FIRE on the LAMMPS engine (src/lammps/fire_minimiser.hpp) against the
// C++ reference engine's (src/engine/reference.cpp, kernels/physics.cl
// pf_fire_next) on the same input: the same positions, powers and FIRE
// state (dt, alpha, restarts) step for step; the state the same on every
// rank; and a small fill whose finish relaxes by FIRE on LAMMPS. ctest
// runs this file in one process and under `mpirun -np 2`
// (mpi2.test_lammps_fire), where LAMMPS splits the atoms between the ranks
// and each step's power is summed over them.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <random>
#include <vector>

#include "lammps_fixtures.hpp"
#include "pfill/engine/reference.hpp"
#include "pfill/fill.hpp"
#include "pfill/lammps.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

// The finish's kind of engine: purely repulsive, FIRE, no damping.
EngineParams fire_params() {
  EngineParams p;
  p.radius = 0.05;
  p.max_radius = p.radius * (1 + 1e-6);
  p.restitution = 1;  // (no dashpot, as the finish runs FIRE)
  p.wall_restitution = 0;
  p.damping = 0;
  p.dt = 0.01 * derive_constants(p).tau;
  p.max_step_fraction = 0.1;
  p.fire.on = true;
  return p;
}

// Overlapping spheres on a jittered lattice inside a ball of radius R, moving.
std::vector<Particle> squeezed(double R, double spacing, uint64_t seed) {
  return test::jittered_lattice(R, spacing, seed, 0.1, 1);
}

// A double as four 16-bit pieces (sums of a few ranks' pieces cannot overflow an int).
void push_bits(std::vector<int>& out, double v) {
  uint64_t b = 0;
  std::memcpy(&b, &v, sizeof b);
  for (int k = 0; k < 4; ++k) out.push_back(static_cast<int>((b >> (16 * k)) & 0xFFFF));
}

}  // namespace

TEST_CASE("lammps engine: FIRE steps as the reference's (positions, powers, dt, alpha, restarts)") {
  if (!lammps_available()) return;
  const EngineParams p = fire_params();
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  const std::vector<Particle> start = squeezed(0.5, 0.092, 3);
  REQUIRE(start.size() > 200);
  ReferenceEngine ref(p);
  ref.set_field(field);
  ref.add_particles(start);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->share_field(field);
  lmp->add_particles(start);
  const double first_dt = ref.constants().dt;
  CHECK(lmp->minimiser_state().dt == first_dt);
  double largest_dt = 0, most_restarts = 0, steps = 0;
  bool rose = false, fell = false;
  // Reads between runs of uneven length (each takes the records in flight
  // in), a restart of the minimiser half-way, and a last stretch read at once.
  const int runs[] = {7, 25, 40, 3, 60, 0, 45, 80};
  for (int k : runs) {
    if (k == 0) {
      ref.restart_minimiser();
      lmp->restart_minimiser();
      CHECK(lmp->minimiser_state().restarts == 0);
      continue;
    }
    ref.run_steps(k);
    lmp->run_steps(k);
    const std::vector<StepRecord> hr = ref.read_history(), hl = lmp->read_history();
    REQUIRE(hl.size() == hr.size());
    for (size_t s = 0; s < hr.size(); ++s) {
      INFO("step " << hr[s].step << ": power " << hl[s].power << " against " << hr[s].power);
      CHECK(hl[s].step == hr[s].step);
      CHECK(hl[s].colliding_pairs == hr[s].colliding_pairs);
      CHECK(hl[s].power == doctest::Approx(hr[s].power).epsilon(1e-7).scale(1e-9));
      CHECK(hl[s].kinetic_energy == doctest::Approx(hr[s].kinetic_energy).epsilon(1e-7));
      rose = rose || hr[s].power > 0, fell = fell || (s > 0 && hr[s].power < 0);
    }
    const ParticleEngine::MinimiserState a = ref.minimiser_state(), b = lmp->minimiser_state();
    INFO("after " << steps + k << " steps: dt " << b.dt << " against " << a.dt << ", alpha " << b.alpha << " against "
                  << a.alpha << ", restarts " << b.restarts << " against " << a.restarts);
    CHECK(b.dt == doctest::Approx(a.dt).epsilon(1e-12));
    CHECK(b.alpha == doctest::Approx(a.alpha).epsilon(1e-12));
    CHECK(b.restarts == a.restarts);
    largest_dt = std::max(largest_dt, a.dt), most_restarts = std::max(most_restarts, a.restarts);
    steps += k;
  }
  // Not a trivial run: dt grew, P turned negative and FIRE restarted.
  CHECK(rose);
  CHECK(fell);
  CHECK(largest_dt > 1.5 * first_dt);
  CHECK(most_restarts >= 1);
  const std::vector<Particle> a = ref.read_particles(), b = lmp->read_particles();
  REQUIRE(a.size() == b.size());
  double worst = 0, worst_v = 0, moved = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(b[i].id == a[i].id);
    worst = std::max(worst, length(a[i].position - b[i].position));
    worst_v = std::max(worst_v, length(a[i].velocity - b[i].velocity));
    moved = std::max(moved, length(a[i].position - start[i].position));
  }
  INFO("largest position difference " << worst << ", velocity " << worst_v << "; largest move " << moved);
  CHECK(moved > 0.01);
  CHECK(worst < 1e-7);
  CHECK(worst_v < 1e-5);
}

TEST_CASE("lammps engine: without FIRE the records' power is 0 and the minimiser's state zeros") {
  if (!lammps_available()) return;
  EngineParams p = fire_params();
  p.fire.on = false;
  p.damping = 1;
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->share_field(field);
  lmp->add_particles(squeezed(0.5, 0.092, 4));
  lmp->restart_minimiser();  // ignored
  lmp->run_steps(10);
  for (const StepRecord& r : lmp->read_history()) CHECK(r.power == 0);
  CHECK(lmp->minimiser_state().dt == 0);
  CHECK(lmp->minimiser_state().restarts == 0);
}

// At 2 ranks each rank sums only its own atoms' F.v: the engine sums the
// shares over the ranks every step, and each rank's FIRE state follows
// from the same sums. Checked bit for bit: each rank's dt, alpha,
// restarts and every record's power, summed over the ranks, are the
// ranks' count times this rank's.
TEST_CASE("lammps engine: FIRE's state the same on every rank, step for step") {
  if (!lammps_available()) return;
  const EngineParams p = fire_params();
  const ScalarGrid field = test::ball_field(0.5, 0.02);
  const std::vector<Particle> start = squeezed(0.5, 0.092, 5);
  std::unique_ptr<ParticleEngine> lmp = make_lammps_engine(p);
  lmp->share_field(field);
  lmp->add_particles(start);
  const MpiWorld world = lammps_mpi_start();
  if (world.size > 1) CHECK_FALSE(lmp->birth_view(0.1, false).complete());  // the atoms are split
  std::vector<int> mine;
  double restarts = 0;
  for (int round = 0; round < 6; ++round) {
    lmp->run_steps(30);
    for (const StepRecord& r : lmp->read_history()) push_bits(mine, r.power);
    const ParticleEngine::MinimiserState s = lmp->minimiser_state();
    push_bits(mine, s.dt), push_bits(mine, s.alpha), push_bits(mine, s.restarts);
    restarts = std::max(restarts, s.restarts);
    if (round == 2) lmp->restart_minimiser();
  }
  CHECK(restarts >= 1);  // P's sign changed: the ranks had a decision to agree on
  std::vector<int> summed = mine;
  lmp->sum_over_processes(summed);
  size_t differ = 0;
  for (size_t k = 0; k < mine.size(); ++k) differ += summed[k] != world.size * mine[k];
  CHECK(differ == 0);
}

TEST_CASE("lammps engine: a small fill's finish relaxes by FIRE on LAMMPS, within the bound") {
  if (!lammps_available()) return;
  FillOptions o;
  o.count = 300;
  o.seed = 3;
  o.colour = ColourOptions{ColourMode::None, {}};
  bool fire_engine = false;
  o.engine = [&fire_engine](const EngineParams& p) {
    fire_engine = fire_engine || p.fire.on;
    return make_lammps_engine(p);
  };
  o.finish_on_engine = true;
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  INFO("particles " << r.metrics.count << ", packing " << r.metrics.packing_fraction << ", largest overlap "
                    << r.metrics.max_overlap << ", finish rounds " << r.finish_rounds);
  CHECK(fire_engine);
  CHECK(r.finish_rounds >= 1);
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_overlap <= o.max_overlap + 1e-9);
  CHECK(r.metrics.count >= 250);
  CHECK(r.metrics.count <= 340);
  CHECK(r.metrics.packing_fraction > 0.5);
}

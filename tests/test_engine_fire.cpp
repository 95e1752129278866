// FIRE (EngineParams::fire; kernels/physics.cl PF_DEFINE_FIRE_KICK_DRIFT and
// pf_fire_next): every step form against the double-precision reference on
// an over-full, purely repulsive system in a ball: one step (positions,
// velocities, the power), then a run long enough for dt to grow and for
// restarts, the history read at the same steps by both (the records the
// steps still have in flight are taken in when it is read), and FIRE
// lowering the energy where damped dynamics of the same step would not
// yet. Each test loops over the step forms itself.
#include <doctest/doctest.h>

#include <cmath>
#include <string>
#include <vector>

#include "engine_fixtures.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/engine/reference.hpp"
#include "pfill/error.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

using Form = StepFormCase;
const Form kForms[] = {kStepForms[0], kStepForms[1], kStepForms[2], kStepForms[5]};

constexpr double kR = 0.5;
constexpr double kBall = 4.0;

EngineParams fire_params(const Form& f) {
  EngineParams p;
  f.apply(p);
  p.radius = kR;
  p.cutoff_sigma = 0;  // purely repulsive, as the finish
  p.restitution = 1;   // no dashpots: FIRE alone takes the energy out
  p.wall_restitution = 0;
  p.dt = 0.03 * derive_constants(p).tau;  // the finish's first step
  p.fire.on = true;
  return p;
}

// Spheres 0.8 of a diameter apart at the closest: every contact overlaps by up to 20% of r.
std::vector<Particle> crowded(unsigned seed) {
  return random_particles(220, kR, kBall, 0.8, 0.0, seed, [](const Vec3& x) { return sphere_distance(x, kBall); });
}

double worst_position_gap(const std::vector<Particle>& a, const std::vector<Particle>& b) {
  double worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, length(a[i].position - b[i].position));
  return worst;
}

}  // namespace

TEST_CASE("FIRE: every step form takes the reference's steps, powers and restarts") {
  const ScalarGrid field = sphere_grid(kBall, 0.125);
  const std::vector<Particle> start = crowded(1);
  REQUIRE(start.size() > 150);
  for (const Form& f : kForms) {
    CAPTURE(f.name);
    const EngineParams p = fire_params(f);
    Engine engine(shared_device(), p);
    ReferenceEngine ref(p);
    engine.set_field(field);
    ref.set_field(field);
    engine.add_particles(start);
    ref.add_particles(start);
    // Two steps: the first (a restart from rest: power 0) and one that moves with FIRE's mixing.
    engine.run_steps(2);
    ref.run_steps(2);
    const std::vector<StepRecord> h = engine.read_history(), r = ref.read_history();
    REQUIRE(h.size() == 2);
    CHECK(h[0].power == 0);
    CHECK(r[0].power == 0);
    CHECK(r[1].power > 0);
    CHECK(h[1].power == doctest::Approx(r[1].power).epsilon(1e-4));
    CHECK(h[1].colliding_pairs == r[1].colliding_pairs);
    CHECK(!h[1].lists_rebuilt);  // (not recorded under FIRE: the fourth sum is the power)
    CHECK(worst_position_gap(engine.read_particles(), ref.particles()) < 1e-5);
    // On to where dt has grown and restarts have come, read in chunks at the same steps.
    for (size_t chunk : {7, 40, 1, 100, 50}) {
      engine.run_steps(chunk);
      ref.run_steps(chunk);
      const std::vector<StepRecord> hc = engine.read_history(), rc = ref.read_history();
      REQUIRE(hc.size() == rc.size());
      for (size_t k = 0; k < hc.size(); ++k) CHECK((hc[k].power > 0) == (rc[k].power > 0));
    }
    const ParticleEngine::MinimiserState ms = engine.minimiser_state(), mr = ref.minimiser_state();
    INFO("restarts " << mr.restarts << ", dt " << mr.dt / p.dt << " x the first");
    CHECK(mr.restarts > 0);
    CHECK(ms.restarts == mr.restarts);
    CHECK(ms.dt == doctest::Approx(mr.dt).epsilon(1e-5));
    CHECK(ms.alpha == doctest::Approx(mr.alpha).epsilon(1e-5));
    // Float and double part where a contact or the wall switches on a step
    // apart; most spheres stay together.
    const std::vector<Particle> got = engine.read_particles();
    size_t apart = 0;
    for (size_t i = 0; i < got.size(); ++i) apart += length(got[i].position - ref.particles()[i].position) > 1e-3;
    CHECK(apart <= got.size() / 10);
    CHECK(engine.read_history().empty());
  }
}

TEST_CASE("FIRE: restarting the minimiser drops every velocity and the first step is the first dt") {
  const ScalarGrid field = sphere_grid(kBall, 0.125);
  const EngineParams p = fire_params(kForms[1]);
  Engine engine(shared_device(), p);
  engine.set_field(field);
  engine.add_particles(crowded(2));
  engine.run_steps(60);
  engine.read_history();
  CHECK(engine.minimiser_state().restarts > 0);  // dt changed by each
  engine.restart_minimiser();
  const ParticleEngine::MinimiserState m = engine.minimiser_state();
  CHECK(m.dt == doctest::Approx(p.dt));
  CHECK(m.alpha == doctest::Approx(p.fire.alpha_start));
  CHECK(m.restarts == 0);
  engine.run_steps(1);
  const std::vector<StepRecord> h = engine.read_history();
  REQUIRE(h.size() == 1);
  CHECK(h[0].power != 0);  // taken with the velocities the restart then dropped
  CHECK(engine.minimiser_state().restarts == 0);  // and so not a restart of its own
}

TEST_CASE("FIRE: lowers an over-full system's energy faster than damped dynamics at its first step") {
  const ScalarGrid field = sphere_grid(kBall, 0.125);
  const std::vector<Particle> start = crowded(3);
  EngineParams fire = fire_params(kForms[1]);
  EngineParams damped = fire;
  damped.fire.on = false;
  damped.damping = -std::log(1 - 0.01) / damped.dt;  // the finish's damped relaxation: 1% a step
  ReferenceEngine a(fire), b(damped);
  for (ReferenceEngine* e : {&a, &b}) {
    e->set_field(field);
    e->add_particles(start);
  }
  const double e0 = a.potential_energy();
  a.run_steps(150);
  b.run_steps(150);
  INFO("energy from " << e0 << ": FIRE " << a.potential_energy() << ", damped " << b.potential_energy());
  CHECK(a.potential_energy() < b.potential_energy());
  CHECK(a.potential_energy() < 0.5 * e0);
}

TEST_CASE("FIRE: bad settings are clear errors") {
  EngineParams p = fire_params(kForms[1]);
  p.damping = 1;
  CHECK_THROWS_WITH_AS(derive_constants(p), doctest::Contains("damping must be 0 with fire.on"), Error);
  p.damping = 0;
  p.fire.shrink = 1.5;
  CHECK_THROWS_WITH_AS(derive_constants(p), doctest::Contains("shrink"), Error);
}

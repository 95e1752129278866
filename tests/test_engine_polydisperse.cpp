// Unequal spheres (issue 29, the engine's part): each pair's sigma, cutoff,
// rest distance and dashpot scale with q = (r_i + r_j) / (2 radius), its
// energy with q^3 (kernels/physics.cl PF_DEFINE_PAIR_SCALE2 and _SCALE). Every step form against the
// double-precision reference on mixtures of radii 1:2 and 1:4, momentum
// with unequal masses, the wall with each sphere's own radius, a big and a
// small sphere coming apart to their pair's contact distance, and equal
// spheres run as before. Each test loops over the step forms itself (the
// ctest variants do not run this file).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "engine_fixtures.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/engine/reference.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

constexpr double kSmall = 0.25;  // EngineParams::radius: the smallest sphere

using Form = StepFormCase;
const auto& kForms = kStepForms;

EngineParams poly_params(const Form& f, double cutoff_sigma, double max_radius) {
  EngineParams p;
  f.apply(p);
  p.radius = kSmall;
  p.max_radius = max_radius;
  p.cutoff_sigma = cutoff_sigma;
  p.restitution = 0.7;
  p.wall_restitution = 0.8;
  p.damping = 0.1;
  return p;
}

// n spheres in a ball of radius R, radii drawn from `radii` (equal odds),
// centres inside by their own radius and pairwise at least 0.9 (r_i + r_j)
// apart, velocities uniform in [-speed, speed]^3. Deterministic for a seed.
std::vector<Particle> mixed_particles(size_t n, const std::vector<double>& radii, double R, double speed,
                                      unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-R, R), vel(-speed, speed);
  std::uniform_int_distribution<size_t> pick(0, radii.size() - 1);
  std::vector<Particle> out;
  for (size_t tries = 0; out.size() < n && tries < 200000; ++tries) {
    const double r = radii[pick(rng)];
    const Vec3 x{pos(rng), pos(rng), pos(rng)};
    if (length(x) > R - r) continue;
    bool ok = true;
    for (const Particle& q : out)
      if (length(q.position - x) < 0.9 * (q.radius + r)) { ok = false; break; }
    if (!ok) continue;
    Particle p;
    p.position = x;
    p.velocity = {vel(rng), vel(rng), vel(rng)};
    p.radius = r;
    out.push_back(p);
  }
  return out;
}

double max_position_difference(const std::vector<Particle>& a, const std::vector<Particle>& b) {
  REQUIRE(a.size() == b.size());
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, length(a[i].position - b[i].position));
  return d;
}
double max_velocity_difference(const std::vector<Particle>& a, const std::vector<Particle>& b) {
  REQUIRE(a.size() == b.size());
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, length(a[i].velocity - b[i].velocity));
  return d;
}

}  // namespace

TEST_CASE("polydisperse engine: the pair scale is exactly 1 for two reference spheres") {
  EngineParams p;
  p.radius = 0.3;
  p.max_radius = 1.2;
  ReferenceEngine ref(p);
  CHECK(ref.constants().polydisperse);
  CHECK(ref.pair_scale2(0.6) == 1.0);
  CHECK(ref.pair_scale2(1.2) == doctest::Approx(4.0).epsilon(1e-12));
  CHECK(ref.pair_scale2(2.4) == doctest::Approx(16.0).epsilon(1e-12));
  // what the fill and its finish pass for equal spheres is not polydisperse...
  p.max_radius = 0.3 * (1 + 1e-6) / (1 - 0.0005);
  CHECK_FALSE(ReferenceEngine(p).constants().polydisperse);
  CHECK(ReferenceEngine(p).pair_scale2(1.2) == 1.0);
  // ...unless asked, and a large spread is not unless told off
  p.pair_scaling = PairScaling::on;
  CHECK(ReferenceEngine(p).constants().polydisperse);
  p.max_radius = 1.2;
  p.pair_scaling = PairScaling::off;
  CHECK_FALSE(ReferenceEngine(p).constants().polydisperse);
  CHECK(derive_constants(p).list_reach < 2 * 1.2 + 1.0);
}

TEST_CASE("polydisperse engine: a pair's energy scales with its volume, q^3, its stiffness with q") {
  // Two spheres of radius a at a distance d and two of radius q a at q d:
  // the same shape of pair, q times as large. The energy is q^3 times the
  // reference pair's (eps_ij = q^3 eps) at every distance, so the force at
  // the same relative overlap q^2 times and the stiffness q times (as a
  // contact's under one pressure), not 1/q and 1/q^2 (eps fixed).
  EngineParams p;
  p.radius = kSmall;
  p.max_radius = 4 * kSmall;
  p.cutoff_sigma = 2.5;
  p.domain.add({-8, -8, -8});
  p.domain.add({8, 8, 8});
  const double q_of[2] = {2.0, 4.0};
  for (double q : q_of) {
    for (double d : {0.45, 0.5, 0.55, 0.7}) {  // overlapping, at contact, in the well
      auto pair_energy = [&](double r, double at) {
        ReferenceEngine ref(p);
        std::vector<Particle> two(2);
        two[0].radius = two[1].radius = r;
        two[1].position = {at, 0, 0};
        ref.add_particles(two);
        return ref.potential_energy();
      };
      const double e1 = pair_energy(kSmall, d), eq = pair_energy(q * kSmall, q * d);
      INFO("q " << q << ", d " << d);
      REQUIRE(e1 != 0.0);
      CHECK(eq == doctest::Approx(q * q * q * e1).epsilon(1e-9));
    }
    ReferenceEngine ref(p);
    CHECK(ref.pair_scale(2 * q * kSmall) == doctest::Approx(q).epsilon(1e-12));
  }
  CHECK(ReferenceEngine(p).pair_scale(2 * kSmall) == 1.0);  // exactly, as pair_scale2
}

TEST_CASE("polydisperse engine: every step form matches the reference (radii 1:2 and 1:4 mixed)") {
  for (double cutoff : {0.0, 2.5}) {
    for (const Form& f : kForms) {
      const EngineParams p = poly_params(f, cutoff, 4 * kSmall);
      const double R = 4.0;
      const ScalarGrid field = sphere_grid(R, 0.125);
      const auto start = mixed_particles(160, {kSmall, 2 * kSmall, 4 * kSmall}, R, 1.0, 7);
      REQUIRE(start.size() == 160);
      Engine engine(shared_device(), p);
      ReferenceEngine ref(p);
      engine.set_field(field);
      ref.set_field(field);
      engine.add_particles(start);
      ref.add_particles(start);
      INFO("form " << f.name << ", cutoff " << cutoff);
      std::vector<StepRecord> refs;
      for (int steps : {1, 4}) {
        for (int s = 0; s < steps; ++s) refs.push_back(ref.step());
        engine.run_steps(steps);
        const auto got = engine.read_particles();
        INFO("after " << refs.size() << " steps");
        CHECK(max_position_difference(got, ref.particles()) < 1e-5);
        CHECK(max_velocity_difference(got, ref.particles()) < 5e-4);
        const auto h = engine.read_history();
        REQUIRE(h.size() == static_cast<size_t>(steps));
        CHECK(h.back().colliding_pairs == refs.back().colliding_pairs);
        CHECK(h.back().kinetic_energy == doctest::Approx(refs.back().kinetic_energy).epsilon(1e-4));
        CHECK(h.back().cell_overflow == 0);
      }
      CHECK(refs.front().colliding_pairs > 0);  // the start has overlaps (0.9 of the pair contact)
    }
  }
}

TEST_CASE("polydisperse engine: momentum is conserved with unequal masses") {
  for (const Form& f : {kForms[0], kForms[1], kForms[3], kForms[4]}) {
    EngineParams p = poly_params(f, 2.5, 4 * kSmall);
    p.damping = 0;
    p.domain.add({-6, -6, -6});
    p.domain.add({6, 6, 6});
    const auto start = mixed_particles(160, {kSmall, 4 * kSmall}, 4.0, 0.5, 3);
    Engine engine(shared_device(), p);
    engine.add_particles(start);
    const auto first = engine.read_particles();
    double heavy = 0, light = 1e300, scale = 0;
    for (const Particle& q : first) {
      heavy = std::max(heavy, q.mass);
      light = std::min(light, q.mass);
      scale += q.mass * length(q.velocity);
    }
    REQUIRE(heavy == doctest::Approx(64 * light));  // mass from each sphere's own volume
    engine.run_steps(50);
    const auto after = engine.read_particles();
    double pairs = 0;
    for (const StepRecord& r : engine.read_history()) pairs += r.colliding_pairs;
    INFO("form " << f.name);
    CHECK(pairs > 0);
    CHECK(length(total_momentum(after) - total_momentum(first)) < 1e-5 * scale);
  }
}

TEST_CASE("polydisperse engine: each sphere stays its own radius inside the wall") {
  for (const Form& f : {kForms[0], kForms[1], kForms[5]}) {
    const EngineParams p = poly_params(f, 0.0, 4 * kSmall);
    const double R = 3.0;
    Engine engine(shared_device(), p);
    engine.set_field(sphere_grid(R, 0.0625));
    // one sphere of each size near the wall, each flying out along its own axis
    std::vector<Particle> three(3);
    const double radii[3] = {kSmall, 2 * kSmall, 4 * kSmall};
    for (int k = 0; k < 3; ++k) {
      three[k].radius = radii[k];
      Vec3 axis;
      (k == 0 ? axis.x : k == 1 ? axis.y : axis.z) = 1;
      three[k].position = axis * (R - radii[k] - 0.05);
      three[k].velocity = axis * 2.0;
    }
    engine.add_particles(three);
    INFO("form " << f.name);
    bool bounced[3] = {false, false, false};
    for (int round = 0; round < 10; ++round) {
      engine.run_steps(10);
      const auto got = engine.read_particles();
      for (int k = 0; k < 3; ++k) {
        INFO("radius " << got[k].radius << ", round " << round);
        CHECK(length(got[k].position) <= R - got[k].radius * (1 - 0.01));  // penetration below 1% of its radius
        if (dot(got[k].velocity, got[k].position) < 0) bounced[k] = true;   // turned back at the wall
      }
    }
    for (int k = 0; k < 3; ++k) CHECK(bounced[k]);
  }
}

TEST_CASE("polydisperse engine: a big and a small sphere overlapping come apart to their pair's contact distance") {
  for (double cutoff : {0.0, 2.5}) {
    for (const Form& f : {kForms[0], kForms[1], kForms[3]}) {
      // overdamped (u *= 0.8 a step: the pair is 2.5 times as stiff as the
      // reference pair, k q), so that they creep apart and stop where the
      // potential's force ends or has its minimum: the pair's rest
      // distance, here r_i + r_j (5/2 of the reference pair's)
      EngineParams p = poly_params(f, cutoff, 4 * kSmall);
      p.damping = 100.0;
      p.domain.add({-4, -4, -4});
      p.domain.add({4, 4, 4});
      std::vector<Particle> two(2);
      two[0].radius = 4 * kSmall;
      two[1].radius = kSmall;
      const double rs = two[0].radius + two[1].radius;
      two[0].position = {0, 0.1, 0.2};
      two[1].position = {0.8 * rs, 0.1, 0.2};  // 20% of the pair's contact distance overlapping
      Engine engine(shared_device(), p);
      ReferenceEngine ref(p);
      engine.add_particles(two);
      ref.add_particles(two);
      engine.run_steps(3000);
      for (int s = 0; s < 3000; ++s) ref.step();
      const auto got = engine.read_particles();
      const double d = length(got[1].position - got[0].position);
      const double d_ref = length(ref.particles()[1].position - ref.particles()[0].position);
      INFO("form " << f.name << ", cutoff " << cutoff << ", d " << d << ", reference " << d_ref);
      CHECK(d == doctest::Approx(d_ref).epsilon(1e-4));
      CHECK(d == doctest::Approx(rs).epsilon(1e-3));  // at the pair's rest distance, r_i + r_j
    }
  }
}

TEST_CASE("polydisperse engine: equal spheres in a polydisperse engine run as in an equal one") {
  // Spheres all of the reference radius: the pair scale is exactly 1, so
  // the reference is bit for bit the same, and so is the gpu form (forces
  // summed in fixed point, whose scale the list capacity sets: the equal
  // engine gets the polydisperse one's capacity by another skin; the
  // lists' other entries and rebuild steps change no sum).
  const double R = 4.0;
  const ScalarGrid field = sphere_grid(R, 0.125);
  const auto start = mixed_particles(200, {0.5}, R, 2.0, 5);
  for (double cutoff : {0.0, 2.5}) {
    EngineParams equal = poly_params(kForms[0], cutoff, 0);
    equal.radius = 0.5;
    equal.skin_sigma = kGpuFormSkinSigma;
    EngineParams poly = equal;
    poly.max_radius = 0.6;
    const unsigned capacity = derive_constants(poly).list_capacity;
    while (equal.skin_sigma < 2 && derive_constants(equal).list_capacity != capacity) equal.skin_sigma += 0.01;
    REQUIRE(derive_constants(equal).list_capacity == capacity);
    INFO("cutoff " << cutoff);
    ReferenceEngine a(equal), b(poly);
    REQUIRE(b.constants().polydisperse);
    a.set_field(field);
    b.set_field(field);
    a.add_particles(start);
    b.add_particles(start);
    for (int s = 0; s < 20; ++s) {
      a.step();
      b.step();
    }
    CHECK(max_position_difference(a.particles(), b.particles()) == 0.0);
    CHECK(max_velocity_difference(a.particles(), b.particles()) == 0.0);
    Engine ea(shared_device(), equal), eb(shared_device(), poly);
    ea.set_field(field);
    eb.set_field(field);
    ea.add_particles(start);
    eb.add_particles(start);
    ea.run_steps(20);
    eb.run_steps(20);
    CHECK(max_position_difference(ea.read_particles(), eb.read_particles()) == 0.0);
    CHECK(max_velocity_difference(ea.read_particles(), eb.read_particles()) == 0.0);
  }
}

// The OpenCL engine against the double-precision reference, and its
// host-side contract (history batching, births, removals, growth). The
// device comes from PFILL_DEVICE (PoCL in CI).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <random>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/engine/reference.hpp"
#include "pfill/error.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

// Largest position and velocity differences between the engine and the reference.
std::pair<double, double> max_difference(const std::vector<Particle>& a, const std::vector<Particle>& b) {
  REQUIRE(a.size() == b.size());
  double dx = 0, dv = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    dx = std::max(dx, length(a[i].position - b[i].position));
    dv = std::max(dv, length(a[i].velocity - b[i].velocity));
  }
  return {dx, dv};
}

EngineParams sphere_params(double cutoff_sigma) {
  EngineParams p = test_params();
  p.radius = 0.5;
  p.cutoff_sigma = cutoff_sigma;
  p.restitution = 0.7;
  p.wall_restitution = 0.8;
  p.damping = 0.1;
  return p;
}

// The pruning tests' settings (rc 2.5): no damping, a list skin of 1
// sigma (the lists' rebuild would come only after 50 steps of B's drift)
// and an inner skin of 0.1 (a pruning every 5 steps of it).
EngineParams pruning_params(double restitution) {
  EngineParams p = sphere_params(2.5);
  p.damping = 0;
  p.restitution = restitution;
  p.skin_sigma = 1.0;
  p.inner_skin_sigma = 0.1;
  p.domain.add({-8, -8, -8});
  p.domain.add({8, 8, 8});
  return p;
}

// A at rest near the origin and B at x = b_x, flying at A at 0.01 sigma a step.
std::vector<Particle> flying_pair(const EngineConstants& c, double b_x) {
  std::vector<Particle> two(2);
  two[0].position = {0, 0.1, 0.2};
  two[1].position = {b_x, 0.1, 0.2};
  two[1].velocity = {-0.01 * c.sigma / c.dt, 0, 0};
  two[0].radius = two[1].radius = 0.5;
  return two;
}

// After a pruning test's run: the lists rebuilt on the first step only,
// and both particles where the brute-force reference has them.
void check_pair_as_reference(Engine& engine, const ReferenceEngine& ref) {
  const auto got = engine.read_particles();
  size_t rebuilds = 0;
  for (const StepRecord& r : engine.read_history()) rebuilds += r.lists_rebuilt;
  CHECK(rebuilds == 1);
  for (int k = 0; k < 2; ++k) {
    INFO("particle " << k);
    CHECK(length(got[k].velocity - ref.particles()[k].velocity) < 1e-3 * length(ref.particles()[k].velocity));
    CHECK(length(got[k].position - ref.particles()[k].position) < 1e-5);
  }
}

// The engine and the reference on the same particles and field, stepped together.
struct EngineAndReference {
  Engine engine;
  ReferenceEngine ref;
  EngineAndReference(const EngineParams& p, const ScalarGrid& field, const std::vector<Particle>& ps)
      : engine(shared_device(), p), ref(p) {
    engine.set_field(field);
    ref.set_field(field);
    engine.add_particles(ps);
    ref.add_particles(ps);
  }
  void step(int steps) {
    engine.run_steps(static_cast<size_t>(steps));
    for (int s = 0; s < steps; ++s) ref.step();
  }
  /// After `steps` more steps, the engine's particles are where the reference has them.
  void check_steps(int steps) {
    step(steps);
    auto [dx, dv] = max_difference(engine.read_particles(), ref.particles());
    INFO("after " << steps << " more steps");
    CHECK(dx < 1e-4);
    CHECK(dv < 1e-2);
  }
};

}  // namespace

TEST_CASE("engine: the force between two particles is the analytic derivative of the potential") {
  for (double cutoff : {0.0, 2.5}) {
    EngineParams p = sphere_params(cutoff);
    p.damping = 0;
    p.domain.add({-5, -5, -5});
    p.domain.add({5, 5, 5});
    Engine engine(shared_device(), p);
    const EngineConstants& c = engine.constants();
    // Centre distances inside the repulsive core, between rest and cutoff, and beyond it.
    for (double d_over_sigma : {0.95, 1.1, 1.3, 2.0, 3.0}) {
      const double d = d_over_sigma * c.sigma;
      std::vector<Particle> two(2);
      two[0].position = {-d / 2, 0.1, 0.2};
      two[1].position = {d / 2, 0.1, 0.2};
      two[0].radius = two[1].radius = 0.2;  // no contact: forces only
      two[0].mass = two[1].mass = 1;
      if (engine.size() > 0) engine.remove_particles({0, 1});
      engine.add_particles(two);
      engine.run_steps(1);
      const auto after = engine.read_particles();
      // Analytic F(d) = -du/dd = 4 eps (a s^a - b s^b) / d, s = sigma / d; zero beyond the cutoff.
      const double s = c.sigma / d;
      const double f = d < c.cutoff ? 4 * p.eps * (12 * std::pow(s, 12) - 6 * std::pow(s, 6)) / d : 0.0;
      const double expected = -f * c.dt;  // particle 0 sits at -x: repulsion pushes it to -x
      INFO("cutoff " << cutoff << ", d/sigma " << d_over_sigma);
      CHECK(after[0].velocity.x == doctest::Approx(expected).epsilon(1e-4).scale(1e-6));
      CHECK(after[1].velocity.x == doctest::Approx(-expected).epsilon(1e-4).scale(1e-6));
      CHECK(std::fabs(after[0].velocity.y) < 1e-7);
    }
  }
}

TEST_CASE("engine: matches the reference after 1 and 100 steps (random systems in a sphere)") {
  for (double cutoff : {0.0, 2.5}) {
    for (unsigned seed : {1u, 2u}) {
      const EngineParams p = sphere_params(cutoff);
      const double R = 4.0;
      const ScalarGrid field = sphere_grid(R, 0.125);
      const auto start = random_particles(300, 0.5, R, 0.9, 2.0, seed, [R](const Vec3& x) { return sphere_distance(x, R); });
      Engine engine(shared_device(), p);
      ReferenceEngine ref(p);
      engine.set_field(field);
      ref.set_field(field);
      engine.add_particles(start);
      ref.add_particles(start);
      INFO("cutoff " << cutoff << ", seed " << seed << ", n " << start.size());
      engine.run_steps(1);
      const StepRecord r1 = ref.step();
      auto [dx1, dv1] = max_difference(engine.read_particles(), ref.particles());
      CHECK(dx1 < 1e-5);  // positions ~4, float rounding ~5e-7
      CHECK(dv1 < 2e-4);  // velocities ~2; forces up to the cap are float-rounded
      const auto h1 = engine.read_history();
      REQUIRE(h1.size() == 1);
      CHECK(h1[0].kinetic_energy == doctest::Approx(r1.kinetic_energy).epsilon(1e-5));
      CHECK(h1[0].colliding_pairs == r1.colliding_pairs);
      CHECK(h1[0].max_speed == doctest::Approx(r1.max_speed).epsilon(1e-5));
      CHECK(h1[0].max_displacement == doctest::Approx(r1.max_displacement).epsilon(1e-4));
      CHECK(h1[0].particles == start.size());
      CHECK(h1[0].flagged == 0);
      std::vector<StepRecord> refs;
      for (int s = 0; s < 99; ++s) refs.push_back(ref.step());
      engine.run_steps(99);
      // Contacts and wall hits switch on at a threshold, and particles resting
      // on the wall sit right at it (pushed to exactly -r), so float and
      // double sometimes take a hit a step apart (measured: up to 17 of 210
      // particles with rc = 2.5 after 100 steps); the rest must agree to 1e-3.
      const auto got = engine.read_particles();
      size_t apart = 0;
      for (size_t i = 0; i < got.size(); ++i)
        if (length(got[i].position - ref.particles()[i].position) > 1e-3) ++apart;
      CHECK(apart <= got.size() / 10);
      const auto h = engine.read_history();
      REQUIRE(h.size() == 99);
      CHECK(h.back().step == 99);
      CHECK(h.back().kinetic_energy == doctest::Approx(refs.back().kinetic_energy).epsilon(2e-2));
      CHECK(h.back().cell_overflow == 0);
    }
  }
}

TEST_CASE("engine: inner lists (dynamic pruning) are pruned again before a pair left out comes within reach") {
  // B starts listed but outside the inner reach (cutoff + inner skin) of A
  // and flies straight at it, crossing the cutoff well before its drift
  // would rebuild the lists (skin 1 sigma: half of it). Only pruning again
  // on B's drift (half the inner skin) brings the pair into the inner list,
  // and so A's pull on B and B's on A match the brute-force reference.
  const EngineParams p = pruning_params(1.0);
  Engine engine(shared_device(), p);
  ReferenceEngine ref(p);
  const EngineConstants& c = engine.constants();
  // (B not a whole number of steps from the cutoff; at it after 30 steps)
  const std::vector<Particle> two = flying_pair(c, c.cutoff + 0.305 * c.sigma);
  engine.add_particles(two);
  ref.add_particles(two);
  for (int s = 0; s < 45; ++s) ref.step();
  engine.run_steps(45);  // B at cutoff - 0.15 sigma; the lists' rebuild would come at 50
  REQUIRE(length(ref.particles()[0].velocity) > 1e-4);  // A was pulled
  check_pair_as_reference(engine, ref);
}

TEST_CASE("engine: a particle moves alike in whichever octet (8 lanes) advance takes it") {
  // The CPU form's advance takes particles 8 at a time as float8 lanes,
  // the last octet partial, the wall included; each lane must compute on
  // its own, or which particles share an octet would change a fill's
  // result. 21 particles in lanes 2.5 sigma apart along z in a box (they
  // meet the speed cap and the walls, never each other), added in two
  // orders (so in other lanes and octets, and 5 in the partial octet):
  // each must end the same, bit for bit.
  const Vec3 h{8, 8, 4};
  const ScalarGrid field = box_grid(h, 0.125);
  EngineParams p = sphere_params(0.0);
  p.damping = 0;
  std::vector<Particle> start(21);
  double speed_cap = 0;
  {
    Engine probe(shared_device(), p);
    speed_cap = probe.constants().max_speed;
  }
  for (size_t i = 0; i < start.size(); ++i) {
    start[i].radius = 0.5;
    start[i].position = {-6.0 + 2.5 * double(i % 5), -6.0 + 2.5 * double(i / 5), -2.0 + 0.2 * double(i % 7)};
    start[i].velocity = {0, 0, (i % 2 ? 1.0 : -1.0) * speed_cap * (0.4 + 0.15 * double(i % 6))};  // some over the cap
  }
  const size_t shift = 5;
  std::vector<Particle> got[2];
  for (int order = 0; order < 2; ++order) {
    std::vector<Particle> in(start.size());
    for (size_t i = 0; i < start.size(); ++i) in[order ? (i + shift) % start.size() : i] = start[i];
    Engine engine(shared_device(), p);
    engine.set_field(field);
    engine.add_particles(in);
    engine.run_steps(400);
    const auto out = engine.read_particles();
    REQUIRE(out.size() == start.size());
    got[order].resize(start.size());
    for (size_t i = 0; i < start.size(); ++i) got[order][i] = out[order ? (i + shift) % start.size() : i];
  }
  size_t differ = 0, turned = 0;
  for (size_t i = 0; i < start.size(); ++i) {
    const Particle &a = got[0][i], &b = got[1][i];
    differ += a.position.x != b.position.x || a.position.y != b.position.y || a.position.z != b.position.z ||
              a.velocity.x != b.velocity.x || a.velocity.y != b.velocity.y || a.velocity.z != b.velocity.z;
    turned += a.velocity.z * start[i].velocity.z < 0 || std::fabs(a.velocity.z) < std::fabs(start[i].velocity.z);
    CHECK(a.position.x == start[i].position.x);  // no pair force ever acted
  }
  CHECK(differ == 0);
  CHECK(turned >= start.size() / 2);  // the walls were met
}

TEST_CASE("engine: an automatic skin is the step form's, and a given one is kept") {
  EngineParams p = sphere_params(2.5);
  p.skin_sigma = 0;
  p.domain.add({-4, -4, -4});
  p.domain.add({4, 4, 4});
  for (StepForm form : {StepForm::cpu, StepForm::gpu}) {
    p.step_form = form;
    Engine engine(shared_device(), p);
    const double want = form == StepForm::cpu ? kCpuFormSkinSigma : kGpuFormSkinSigma;
    CHECK(engine.params().skin_sigma == want);
    CHECK(engine.constants().skin == doctest::Approx(want * engine.constants().sigma));
  }
  p.skin_sigma = 0.4;
  CHECK(Engine(shared_device(), p).params().skin_sigma == 0.4);
  p.skin_sigma = -0.1;
  CHECK_THROWS_WITH_AS(derive_constants(p), doctest::Contains("skin_sigma"), Error);
}

TEST_CASE("engine settings: the automatic choices are made for a device's kind, cores and limits, in one line") {
  DeviceInfo cpu;
  cpu.type = "CPU";
  cpu.name = "some cpu";
  cpu.compute_units = 2;
  cpu.max_work_group = 4096;
  DeviceInfo gpu = cpu;
  gpu.type = "GPU";
  gpu.compute_units = 80;
  gpu.max_work_group = 64;
  EngineParams repulsive;  // cutoff 0
  EngineParams lj;
  lj.cutoff_sigma = 2.5;
  const DeviceChoices c = resolve_for_device(cpu, repulsive);
  CHECK(!c.gpu_form);
  CHECK(c.skin_sigma == kCpuFormSkinSigma);
  EngineParams mix = repulsive;  // radii 1:4: the cpu form's wider skin, the gpu form's as for equal spheres
  mix.max_radius = 4 * mix.radius;
  CHECK(resolve_for_device(cpu, mix).skin_sigma == kCpuFormMixSkinSigma);
  CHECK(resolve_for_device(gpu, mix).skin_sigma == kGpuFormSkinSigma);
  mix.max_radius = 1.5 * mix.radius;
  CHECK(resolve_for_device(cpu, mix).skin_sigma == kCpuFormSkinSigma);
  mix.max_radius = 4 * mix.radius;
  mix.cutoff_sigma = 2.5;  // long rows with a cutoff: the equal spheres' skin
  CHECK(resolve_for_device(cpu, mix).skin_sigma == kCpuFormSkinSigma);
  EngineParams births = repulsive;  // a fill's passes 1-2: the cpu form's wider skin, not with a cutoff
  births.births_at_speed = true;
  CHECK(resolve_for_device(cpu, births).skin_sigma == kCpuFormBirthsSkinSigma);
  CHECK(resolve_for_device(gpu, births).skin_sigma == kGpuFormSkinSigma);
  births.cutoff_sigma = 2.5;
  CHECK(resolve_for_device(cpu, births).skin_sigma == kCpuFormSkinSigma);
  CHECK(c.newton);  // at most 4 cores
  CHECK(c.pair_queue);  // purely repulsive
  CHECK(!c.inner_lists);
  CHECK(c.work_group == 128);
  CHECK(c.describe() == "engine on CPU 'some cpu' (2 compute units): cpu step form (automatic), skin 0.5 sigma "
                        "(automatic), work-group 128, newton on (automatic), pair queue on (automatic), inner lists "
                        "off (automatic)");
  const DeviceChoices l = resolve_for_device(cpu, lj);
  CHECK(!l.pair_queue);
  CHECK(l.inner_lists);
  cpu.compute_units = 16;
  CHECK(!resolve_for_device(cpu, lj).newton);
  const DeviceChoices g = resolve_for_device(gpu, lj);
  CHECK(g.gpu_form);
  CHECK(g.skin_sigma == kGpuFormSkinSigma);
  CHECK(!g.newton);
  CHECK(!g.inner_lists);
  CHECK(g.work_group == 64);  // the device's limit
  lj.step_form = StepForm::cpu;
  lj.skin_sigma = 0.4;
  lj.work_group = 100;
  const DeviceChoices set = resolve_for_device(gpu, lj);
  CHECK(!set.gpu_form);
  CHECK(set.skin_sigma == 0.4);
  CHECK(set.work_group == 64);
  CHECK(set.describe().find("cpu step form (set), skin 0.4 sigma (set)") != std::string::npos);
}

TEST_CASE("engine: a pair pruned as unable to touch is pruned again before it touches") {
  // A pruning lists first the entries that may touch before the next one
  // (within touch distance plus the inner skin), and the pair loop runs
  // the contact damping on those only. B starts just beyond that and flies
  // at A; it touches after about 14 steps, long before its drift would
  // rebuild the lists. The prunings on its drift (every 5 steps) must move
  // it into the first run in time, or the dashpot misses steps of contact
  // and the velocities leave the reference's.
  const EngineParams p = pruning_params(0.3);
  Engine engine(shared_device(), p);
  ReferenceEngine ref(p);
  const EngineConstants& c = engine.constants();
  const double touch = std::max(1.0, c.contact_distance);  // radii 0.5
  const std::vector<Particle> two = flying_pair(c, touch + c.inner_skin + 0.035 * c.sigma);
  engine.add_particles(two);
  ref.add_particles(two);
  int touching_steps = 0;
  for (int s = 0; s < 24; ++s) {
    ref.step();
    touching_steps += length(ref.particles()[0].position - ref.particles()[1].position) < touch;
  }
  engine.run_steps(24);
  REQUIRE(touching_steps >= 5);  // the pair was in contact for a while
  check_pair_as_reference(engine, ref);
}

TEST_CASE("engine: any number of pair-force buffers (cpu form) matches the reference") {
  const EngineParams base = sphere_params(2.5);
  const double R = 4.0;
  const ScalarGrid field = sphere_grid(R, 0.125);
  const auto start = random_particles(300, 0.5, R, 0.9, 2.0, 3, [R](const Vec3& x) { return sphere_distance(x, R); });
  ReferenceEngine ref(base);
  ref.set_field(field);
  ref.add_particles(start);
  const StepRecord r1 = ref.step();
  for (int s = 0; s < 19; ++s) ref.step();
  for (size_t buffers : {1u, 2u, 5u}) {
    EngineParams p = base;
    p.force_buffers = buffers;
    Engine engine(shared_device(), p);
    engine.set_field(field);
    engine.add_particles(start);
    engine.run_steps(20);
    INFO(buffers << " force buffers");
    const auto got = engine.read_particles();
    size_t apart = 0;  // contacts switch on at a threshold (see the test above)
    for (size_t i = 0; i < got.size(); ++i)
      if (length(got[i].position - ref.particles()[i].position) > 1e-4) ++apart;
    CHECK(apart <= got.size() / 20);
    CHECK(engine.read_history().front().colliding_pairs == r1.colliding_pairs);
  }
}

TEST_CASE("engine: births one at a time, growth past the first capacity, removal by swap with last") {
  EngineParams p = sphere_params(0);
  const double R = 5.0;
  const ScalarGrid field = sphere_grid(R, 0.125);
  const auto all = random_particles(150, 0.5, R, 1.0, 1.0, 7, [R](const Vec3& x) { return sphere_distance(x, R); });
  REQUIRE(all.size() == 150);
  Engine engine(shared_device(), p);
  ReferenceEngine ref(p);
  engine.set_field(field);
  ref.set_field(field);
  for (const Particle& q : all) {  // one birth per step, as the fill does; the engine grows 64 -> 128 -> 256
    engine.add_particle(q);
    ref.add_particles({q});
    engine.run_steps(1);
    ref.step();
  }
  CHECK(engine.size() == 150);
  auto [dx, dv] = max_difference(engine.read_particles(), ref.particles());
  CHECK(dx < 1e-3);
  CHECK(dv < 2e-2);
  const auto before = engine.read_particles();
  engine.remove_particles({3, 149, 10});
  REQUIRE(engine.size() == 147);
  const auto after = engine.read_particles();
  // Descending: 149 (the last) goes; 148 moves into 10; 147 moves into 3.
  CHECK(after[10].position == before[148].position);
  CHECK(after[3].position == before[147].position);
  CHECK(after[0].position == before[0].position);
  // index_after_removal follows every particle the same way.
  for (size_t i = 0; i < before.size(); ++i) {
    const size_t now = Engine::index_after_removal(i, {3, 149, 10}, before.size());
    if (i == 3 || i == 149 || i == 10) {
      CHECK(now == Engine::kGone);
    } else {
      REQUIRE(now < after.size());
      CHECK(after[now].position == before[i].position);
    }
  }
  // The neighbour lists were updated in place by the removals: the engine
  // still follows the reference.
  // (Compared after 3 steps too: a list left stale would be repaired by the
  // next skin-triggered rebuild, some 30 steps later.)
  ref.remove_particles({3, 149, 10});
  for (int steps : {3, 17}) {
    engine.run_steps(steps);
    for (int s = 0; s < steps; ++s) ref.step();
    auto [dx2, dv2] = max_difference(engine.read_particles(), ref.particles());
    CHECK(dx2 < 1e-3);
    CHECK(dv2 < 2e-2);
  }
  CHECK(engine.read_history().size() == 170);
  CHECK_THROWS_AS(engine.remove_particles({147}), Error);
}

TEST_CASE("engine: removals and births in a dense system keep the neighbour lists right") {
  EngineParams p = sphere_params(0);
  const Vec3 h{3, 3, 3};
  const ScalarGrid field = box_grid(h, 0.2);
  auto ps = random_particles(300, 0.5, 3, 0.9, 1.0, 17, [h](const Vec3& x) { return box_distance(x, h); });
  const Particle newcomer = ps.back();
  ps.pop_back();
  EngineAndReference both(p, field, ps);
  both.step(2);  // lists built: what follows updates them in place
  const std::vector<size_t> gone = {5, 77, ps.size() - 1, 150, 151};
  both.engine.remove_particles(gone);
  both.ref.remove_particles(gone);
  both.engine.add_particle(newcomer);
  both.ref.add_particles({newcomer});
  for (int steps : {1, 3}) both.check_steps(steps);  // before any skin-triggered rebuild could repair a stale list
}

TEST_CASE("engine: many removals at once rebuild the lists at the next step, and the physics stays right") {
  EngineParams p = sphere_params(0);
  const Vec3 h{3, 3, 3};
  const ScalarGrid field = box_grid(h, 0.2);
  const auto ps = random_particles(300, 0.5, 3, 0.9, 1.0, 29, [h](const Vec3& x) { return box_distance(x, h); });
  REQUIRE(ps.size() > 100);
  EngineAndReference both(p, field, ps);
  both.step(3);  // lists built, and no drift has asked for another build yet
  both.engine.read_history();
  std::vector<size_t> gone;
  for (size_t k = 0; k < 30; ++k) gone.push_back(3 * k + 2);  // (more than are edited in place)
  gone.push_back(ps.size() - 1);
  both.engine.remove_particles(gone);
  both.ref.remove_particles(gone);
  REQUIRE(both.engine.size() == ps.size() - gone.size());
  both.check_steps(1);
  CHECK(both.engine.read_history().front().lists_rebuilt);
  both.check_steps(3);
}

TEST_CASE("engine: the same input gives bit-identical particles (births and removals included)") {
  EngineParams p = sphere_params(2.5);
  const Vec3 h{3, 3, 3};
  const ScalarGrid field = box_grid(h, 0.2);
  const auto ps = random_particles(320, 0.5, 3, 0.9, 1.5, 23, [h](const Vec3& x) { return box_distance(x, h); });
  auto run = [&]() {
    Engine engine(shared_device(), p);
    engine.set_field(field);
    engine.add_particles(std::vector<Particle>(ps.begin(), ps.end() - 20));
    for (size_t b = ps.size() - 20; b < ps.size(); ++b) {  // linked births, then a removal
      engine.add_particle(ps[b]);
      engine.run_steps(10);
      if (b % 5 == 0) engine.remove_particles({b / 3});
    }
    engine.run_steps(200);
    return engine.read_particles();
  };
  const auto a = run(), b = run();
  REQUIRE(a.size() == b.size());
  size_t differ = 0;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].position != b[i].position || a[i].velocity != b[i].velocity) ++differ;
  CHECK(differ == 0);
}

TEST_CASE("engine: a wall offset moves the wall as a shifted copy of the field does, bit for bit") {
  // The finish moves its wall in by an offset the kernels add as they read
  // the field (EngineParams::wall_offset), reading the fill's field in
  // place (share_field), instead of a shifted copy of it: the same sums.
  EngineParams p = sphere_params(0);
  const double R = 3.0, offset = 0.3;
  const ScalarGrid field = sphere_grid(R, 0.2);
  ScalarGrid shifted = field;
  for (float& v : shifted.values) v += static_cast<float>(offset);
  const auto ps = random_particles(200, 0.5, R, 1.0, 1.0, 31, [R](const Vec3& x) { return sphere_distance(x, R); });
  auto run = [&](const EngineParams& q, bool share) {
    Engine engine(shared_device(), q);
    if (share)
      engine.share_field(field);
    else
      engine.set_field(shifted);
    engine.add_particles(ps);
    engine.run_steps(300);
    return engine.read_particles();
  };
  EngineParams moved = p;
  moved.wall_offset = offset;
  const auto a = run(p, false), b = run(moved, true);
  REQUIRE(a.size() == b.size());
  size_t differ = 0;
  double deepest_wall = 0;  // the moved wall keeps every centre r + offset inside the sphere
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].position != b[i].position || a[i].velocity != b[i].velocity) ++differ;
    deepest_wall = std::max(deepest_wall, length(b[i].position) + b[i].radius + offset);
  }
  CHECK(differ == 0);
  CHECK(deepest_wall < R + 0.02);
  // and the wall did move: without the offset the same run ends elsewhere
  const auto c = run(p, true);
  size_t moved_by_offset = 0;
  for (size_t i = 0; i < a.size(); ++i) moved_by_offset += a[i].position != c[i].position;
  CHECK(moved_by_offset > 0);
  EngineParams bad = p;
  bad.wall_offset = std::nan("");
  CHECK_THROWS_AS(Engine(shared_device(), bad), Error);
}

TEST_CASE("engine: past 65,536 particles the buffers grow by a quarter, and the step runs as before") {
  // Capacity doubles up to 65,536, then grows by a quarter (a million
  // particles would otherwise hold buffers for two): a capacity that is no
  // power of two must step like any other.
  EngineParams p = sphere_params(0);
  const Vec3 h{26, 26, 26};
  std::vector<Particle> lattice;
  for (int k = 0; k < 42; ++k)
    for (int j = 0; j < 42; ++j)
      for (int i = 0; i < 42; ++i) {
        Particle q;
        q.position = Vec3(i, j, k) * 1.2 - Vec3(24.6, 24.6, 24.6);
        q.velocity = Vec3((i % 3) - 1, (j % 3) - 1, (k % 3) - 1) * 0.01;
        q.radius = 0.5;
        lattice.push_back(q);
      }
  REQUIRE(lattice.size() == 74088);
  Engine engine(shared_device(), p);
  engine.set_field(box_grid(h, 1.0));
  engine.add_particles(std::vector<Particle>(lattice.begin(), lattice.begin() + 65000));
  engine.run_steps(2);
  engine.add_particles(std::vector<Particle>(lattice.begin() + 65000, lattice.end()));  // 65,536 -> 81,920
  engine.run_steps(3);
  const auto history = engine.read_history();
  REQUIRE(history.size() == 5);
  CHECK(history.back().particles == lattice.size());
  CHECK(history.back().cell_overflow == 0);
  CHECK(history.back().colliding_pairs == 0);  // 1.2 apart, barely moving: nobody touches
  const auto after = engine.read_particles();
  REQUIRE(after.size() == lattice.size());
  double moved = 0;
  for (size_t i = 0; i < after.size(); ++i) moved = std::max(moved, length(after[i].position - lattice[i].position));
  CHECK(moved < 0.01);
  CHECK(engine.flagged_particles().empty());
}

TEST_CASE("engine: the history survives more steps than its capacity, and records come in order") {
  EngineParams p = sphere_params(0);
  p.history_capacity = 16;
  const double R = 3.0;
  Engine engine(shared_device(), p);
  engine.set_field(sphere_grid(R, 0.25));
  engine.add_particles(random_particles(40, 0.5, R, 1.0, 1.0, 3, [R](const Vec3& x) { return sphere_distance(x, R); }));
  engine.run_steps(50);
  auto h = engine.read_history();
  REQUIRE(h.size() == 50);
  for (size_t s = 0; s < h.size(); ++s) {
    CHECK(h[s].step == s);
    CHECK(h[s].particles == 40);
    CHECK(h[s].kinetic_energy > 0);
  }
  CHECK(engine.read_history().empty());
}

TEST_CASE("engine: cell-list neighbours equal brute-force neighbours") {
  for (double cutoff : {0.0, 2.5}) {
    EngineParams p = sphere_params(cutoff);
    const Vec3 h{3, 2.5, 4};
    const ScalarGrid field = box_grid(h, 0.2);
    const auto ps = random_particles(400, 0.5, 4, 0.85, 1.0, 11, [h](const Vec3& x) { return box_distance(x, h); });
    Engine engine(shared_device(), p);
    ReferenceEngine ref(p);
    engine.set_field(field);
    engine.add_particles(ps);
    ref.add_particles(ps);
    const ListsCompared lists = compare_lists(engine.neighbour_lists(), ref.neighbour_lists());
    CHECK(lists.differ == 0);
    CHECK(lists.pairs > ps.size());  // dense enough that the lists are not trivially empty
  }
}

TEST_CASE("engine: bad settings and bad particles are clear errors") {
  EngineParams p = test_params();
  p.exponent_a = 6;
  p.exponent_b = 12;
  CHECK_THROWS_WITH_AS(Engine(shared_device(), p), doctest::Contains("a > b"), Error);
  EngineParams q;
  Engine engine(shared_device(), q);
  Particle big;
  big.radius = 2;
  CHECK_THROWS_WITH_AS(engine.add_particle(big), doctest::Contains("max_radius"), Error);
  Particle ok;
  ok.radius = 0.5;
  engine.add_particle(ok);
  CHECK_THROWS_WITH_AS(engine.run_steps(1), doctest::Contains("set_field"), Error);
}

// The per-step scalars of a system spread over many work-groups (two
// levels of partials, and with small groups more level-2 partials than a
// group has items): each record sums every particle, and a record made in
// flight equals one finished by read_history() bit for bit.
TEST_CASE("engine: per-step scalars over many work-groups, in flight and finished alike") {
  for (size_t group : {16, 128}) {
    EngineParams p = test_params();
    p.radius = 0.5;
    p.cutoff_sigma = 0;
    p.work_group = group;
    const int side = 28;  // 21,952 particles on a lattice 1.2 apart: no contacts
    p.domain.add({-1, -1, -1});
    p.domain.add({side * 1.2 + 1, side * 1.2 + 1, side * 1.2 + 1});
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> speed(-1, 1);
    std::vector<Particle> ps;
    for (int k = 0; k < side; ++k)
      for (int j = 0; j < side; ++j)
        for (int i = 0; i < side; ++i) {
          Particle q;
          q.position = Vec3(i, j, k) * 1.2;
          q.velocity = {speed(rng), speed(rng), speed(rng)};
          q.radius = 0.5;
          ps.push_back(q);
        }
    ps.resize(ps.size() - 13);  // not a whole number of groups
    Engine every(shared_device(), p), once(shared_device(), p);
    every.add_particles(ps);
    once.add_particles(ps);
    std::vector<StepRecord> read_each_step;
    for (int s = 0; s < 6; ++s) {
      every.run_steps(1);
      for (const StepRecord& r : every.read_history()) read_each_step.push_back(r);  // finished by finalize_history
    }
    once.run_steps(6);
    const std::vector<StepRecord> read_at_end = once.read_history();  // steps 1-4 finished in flight
    REQUIRE(read_each_step.size() == 6);
    REQUIRE(read_at_end.size() == 6);
    INFO("work-group " << group);
    for (size_t s = 0; s < 6; ++s) {
      CHECK(read_each_step[s].kinetic_energy == read_at_end[s].kinetic_energy);
      CHECK(read_each_step[s].max_speed == read_at_end[s].max_speed);
      CHECK(read_at_end[s].particles == ps.size());
      CHECK(read_at_end[s].colliding_pairs == 0);
    }
    double ke = 0, top = 0;
    for (const Particle& q : once.read_particles()) {
      ke += 0.5 * q.mass * dot(q.velocity, q.velocity);
      top = std::max(top, length(q.velocity));
    }
    CHECK(read_at_end.back().kinetic_energy == doctest::Approx(ke).epsilon(1e-5));
    CHECK(read_at_end.back().max_speed == doctest::Approx(top).epsilon(1e-6));
  }
}

// sort_by_cells renumbers the particles (returning new -> old) so that
// neighbours in space are neighbours in memory, and changes nothing else:
// the same system with and without the renumbering moves the same way.
TEST_CASE("engine: sort_by_cells renumbers particles along the cells and leaves the physics alone") {
  for (double cutoff : {0.0, 2.5}) {
    const EngineParams p = sphere_params(cutoff);
    const double R = 6.0;
    const ScalarGrid field = sphere_grid(R, 0.125);
    const auto start = random_particles(800, 0.5, R, 0.9, 1.0, 3, [R](const Vec3& x) { return sphere_distance(x, R); });
    Engine plain(shared_device(), p), sorted(shared_device(), p);
    for (Engine* e : {&plain, &sorted}) {
      e->set_field(field);
      e->add_particles(start);
      e->run_steps(10);
    }
    const auto before = sorted.read_particles();
    const std::vector<size_t> order = sorted.sort_by_cells();
    const auto after = sorted.read_particles();
    REQUIRE(order.size() == before.size());
    std::vector<size_t> seen(order);
    std::sort(seen.begin(), seen.end());
    for (size_t k = 0; k < seen.size(); ++k) REQUIRE(seen[k] == k);  // a permutation
    double gap_before = 0, gap_after = 0;
    for (size_t k = 0; k < after.size(); ++k) {
      CHECK(after[k].position == before[order[k]].position);
      CHECK(after[k].velocity == before[order[k]].velocity);
      if (k > 0) {
        gap_before += length(before[k].position - before[k - 1].position);
        gap_after += length(after[k].position - after[k - 1].position);
      }
    }
    INFO("cutoff " << cutoff << ": mean gap between consecutive particles " << gap_before / after.size() << " -> "
                   << gap_after / after.size());
    CHECK(gap_after < 0.5 * gap_before);  // random order -> cell order
    plain.run_steps(50);
    sorted.run_steps(50);
    const auto a = plain.read_particles(), b = sorted.read_particles();
    size_t apart = 0;
    for (size_t k = 0; k < b.size(); ++k)
      if (length(b[k].position - a[order[k]].position) > 1e-4) ++apart;
    CHECK(apart <= b.size() / 50);  // only float rounding (sums in another order) separates them
  }
}

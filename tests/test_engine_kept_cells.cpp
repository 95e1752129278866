// The wall's kept cells (kernels/cpu_step.cl pf_field_sample8_kept: each
// particle keeps the corners of the field's cell it last sampled): the
// same positions, bit for bit, as sampling the field afresh every time
// (the kernels built with PF_KEPT_CELLS=0), through births, removals and a
// renumbering; and a new field is read, not the old one's kept corners.
#include <doctest/doctest.h>

#include "skip.hpp"

#include <memory>
#include <string>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

EngineParams wall_params() {
  EngineParams p;
  p.radius = 0.5;
  p.restitution = 0.7;
  p.wall_restitution = 0.8;
  p.damping = 0.1;
  p.step_form = StepForm::cpu;  // the kept cells are the CPU form's
  return p;
}

/// An engine whose kernels are built with PFILL_CL_OPTIONS set to `options`.
std::unique_ptr<Engine> engine_built_with(const std::string& options, const EngineParams& p) {
  const ScopedClOptions with(options);
  return std::make_unique<Engine>(shared_device(), p);
}

}  // namespace

TEST_CASE("engine: the wall's kept cells give the positions of fresh samples, bit for bit") {
  if (shared_device().info().type != "CPU") PFILL_SKIP("the kept cells are the CPU form's; the device is a GPU");
  const double R = 4.0;
  const ScalarGrid field = sphere_grid(R, 0.125);
  auto inside = [R](const Vec3& x) { return sphere_distance(x, R); };
  const auto start = random_particles(200, 0.5, R, 0.9, 3.0, 7u, inside);
  const auto later = random_particles(40, 0.5, R, 0.9, 3.0, 8u, inside);
  std::vector<Particle> got[2];
  for (int kept = 0; kept < 2; ++kept) {
    auto engine = engine_built_with(kept ? "" : "-DPF_KEPT_CELLS=0", wall_params());
    engine->set_field(field);
    engine->add_particles(start);
    engine->run_steps(150);
    engine->remove_particles({3, 50, 177});
    for (const Particle& p : later) {
      bool clear = true;  // born only where nothing overlaps it
      for (const Particle& q : engine->read_particles()) clear = clear && length(q.position - p.position) > 1.0;
      if (clear) engine->add_particles({p});
    }
    engine->run_steps(100);
    engine->sort_by_cells();
    engine->run_steps(150);
    got[kept] = engine->read_particles();
    CHECK(engine->flagged_particles().empty());
  }
  REQUIRE(got[0].size() == got[1].size());
  size_t differ = 0;
  for (size_t i = 0; i < got[0].size(); ++i)
    differ += got[0][i].position != got[1][i].position || got[0][i].velocity != got[1][i].velocity;
  CHECK(differ == 0);
  // The wall was in play: spheres against it sample it every step.
  size_t at_wall = 0;
  for (const Particle& p : got[1]) at_wall += sphere_distance(p.position, R) + p.radius > -0.05;
  MESSAGE(at_wall << " of " << got[1].size() << " spheres against the wall at the end");
  CHECK(at_wall > 20);
}

TEST_CASE("engine: a new field is read, not the corners kept from the old one") {
  // A sphere resting on the floor of a box keeps its cell's corners; the
  // floor then rises by 0.3 in a field of the same grid (same cells), and
  // the sphere must be pushed up by the new floor, not left where the old
  // corners put it.
  const Vec3 h{3, 3, 3}, raised{3, 3, 2.7};
  const ScalarGrid floor = box_grid(h, 0.125), new_floor = box_grid(raised, 0.125);
  REQUIRE(floor.dims == new_floor.dims);
  EngineParams p = wall_params();
  p.step_form = StepForm::automatic;
  Engine engine(shared_device(), p);
  engine.set_field(floor);
  Particle resting;
  resting.position = {0.1, -0.2, -h.z + 0.5};
  resting.velocity = {0, 0, 0};
  resting.radius = 0.5;
  engine.add_particles({resting});
  engine.run_steps(50);
  const double before = engine.read_particles()[0].position.z;
  CHECK(before == doctest::Approx(-h.z + 0.5).epsilon(0.01));
  engine.set_field(new_floor);
  engine.run_steps(5);
  const Particle after = engine.read_particles()[0];
  CHECK(after.position.z >= -raised.z + 0.5 - 0.01);
  CHECK(engine.flagged_particles().empty());
}

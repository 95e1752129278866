// A small end-to-end run of every engine kernel (births, removal, steps in a
// field, neighbour lists, history), sized to run under oclgrind in CI
// (tests/CMakeLists.txt: the oclgrind.* tests) as well as on PoCL.
#include <doctest/doctest.h>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"

using namespace pfill;
using namespace pfill::test;

TEST_CASE("engine small run: every kernel on a few dozen particles") {
  Device device;
  MESSAGE("device: " << device.info().name << " on " << device.info().platform);
  EngineParams p = test_params();
  p.history_capacity = 8;
  const double R = 2.5;
  Engine engine(device, p);
  engine.set_field(sphere_grid(R, 0.25));
  const auto ps = random_particles(30, 0.5, R, 1.0, 1.0, 21, [R](const Vec3& x) { return sphere_distance(x, R); });
  engine.add_particles(std::vector<Particle>(ps.begin(), ps.end() - 2));  // bulk upload
  engine.run_steps(3);
  engine.add_particle(ps[ps.size() - 2]);  // single births
  engine.add_particle(ps.back());
  engine.run_steps(5);
  engine.remove_particles({0, 7});
  engine.run_steps(12);  // more than the history capacity
  const auto history = engine.read_history();
  REQUIRE(history.size() == 20);
  CHECK(history.back().particles == ps.size() - 2);
  CHECK(history.back().cell_overflow == 0);
  const auto lists = engine.neighbour_lists();
  CHECK(lists.size() == ps.size() - 2);
  for (const Particle& q : engine.read_particles()) CHECK(sphere_distance(q.position, R) < -0.45);
  CHECK(engine.flagged_particles().empty());
}

// The neighbour grid in a box mostly outside the object: cells a sphere
// cannot reach have no slots (CellGrid::set_domain, reachable_cells), and
// the lists must miss nothing for it. Small, so that it runs under
// oclgrind too (tests/CMakeLists.txt); there it found the field gather's
// bounds given as min(int8, int), whose lanes oclgrind filled with garbage
// now and then (kernels/field.cl, 2026-12-05).
#include <doctest/doctest.h>

#include <algorithm>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/engine/reference.hpp"

using namespace pfill;
using namespace pfill::test;

TEST_CASE("engine in a wide box: the lists are complete, and a sphere far outside is reported") {
  Device device;
  EngineParams p = test_params();
  const double R = 2.5;
  const ScalarGrid wide = sampled_grid(2.5 * R, 0.25, [R](const Vec3& x) { return sphere_distance(x, R); });
  Engine engine(device, p);
  ReferenceEngine ref(p);
  engine.set_field(wide);
  const auto ps = random_particles(40, 0.5, R, 0.9, 1.0, 5, [R](const Vec3& x) { return sphere_distance(x, R); });
  engine.add_particles(ps);
  ref.add_particles(ps);
  const ListsCompared lists = compare_lists(engine.neighbour_lists(), ref.neighbour_lists());
  CHECK(lists.differ == 0);
  CHECK(lists.pairs > ps.size());  // dense enough to miss something
  engine.run_steps(2);
  CHECK(engine.read_history().back().cell_overflow == 0);
  // A sphere where none can be (a cell from the ball: no slots there) is
  // reported as neighbours lost, not passed over in silence.
  std::vector<Particle> with_stray = ps;
  with_stray.push_back(ps.front());
  with_stray.back().position = Vec3(2.3, 2.3, 2.3) * R;  // in the box's corner
  Engine strayed(device, p);
  strayed.set_field(wide);
  strayed.add_particles(with_stray);
  strayed.run_steps(1);  // a fresh engine builds its lists from the cells
  CHECK(strayed.read_history().back().cell_overflow == 1);
}

// Which cells of the neighbour grid get slots (src/engine/reachable_cells):
// every cell a sphere of the object can be in, few others.
#include <doctest/doctest.h>

#include <cmath>

#include "engine/reachable_cells.hpp"
#include "engine_fixtures.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

// Distance from the ball (centre 0, radius R) to the nearest point of the box [lo, lo + edge]^3.
double box_to_ball(const Vec3& lo, double edge, double R) {
  double d2 = 0;
  for (double c : {lo.x, lo.y, lo.z}) {
    const double gap = c > 0 ? c : (c + edge < 0 ? -(c + edge) : 0);
    d2 += gap * gap;
  }
  return std::sqrt(d2) - R;
}

}  // namespace

TEST_CASE("reachable cells: every cell within a cell of the object, and not the far corners of a wide box") {
  const double R = 4, cell = 1.5;
  for (double spacing : {0.25, 0.7}) {  // fine and coarse against the cells
    const ScalarGrid field = sampled_grid(2.5 * R, spacing, [R](const Vec3& x) { return sphere_distance(x, R); });
    int dims[3];
    for (int a = 0; a < 3; ++a)
      dims[a] = static_cast<int>(std::ceil((field.upper()[a] - field.origin[a]) / cell));
    const std::vector<uint8_t> reach = reachable_cells(field, field.origin, cell, dims);
    REQUIRE(reach.size() == static_cast<size_t>(dims[0]) * dims[1] * dims[2]);
    size_t flagged = 0, missed = 0, far = 0;
    for (int k = 0; k < dims[2]; ++k)
      for (int j = 0; j < dims[1]; ++j)
        for (int i = 0; i < dims[0]; ++i) {
          const bool on = reach[static_cast<size_t>(i) + dims[0] * (j + static_cast<size_t>(dims[1]) * k)];
          const double gap = box_to_ball(field.origin + Vec3(i, j, k) * cell, cell, R);
          flagged += on;
          if (!on && gap <= cell) ++missed;             // a sphere a cell outside could be there
          if (on && gap > (1 + std::sqrt(3.0)) * cell) ++far;  // past a cell's dilation of "within a cell"
        }
    INFO("spacing " << spacing << ": " << flagged << " of " << reach.size() << " cells");
    CHECK(missed == 0);
    CHECK(far == 0);
    CHECK(flagged < reach.size() / 2);  // the ball is 6% of the box
  }
}

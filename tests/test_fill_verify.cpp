// The fill's exact check (src/fill/fill_verify.*): holes the field hid
// take a sphere each where one fits by exact distances, the holes one
// search finds far apart in one round.
#include <doctest/doctest.h>

#include <optional>
#include <vector>

#include "fill/fill_verify.hpp"
#include "pfill/boundary.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

TEST_CASE("exact check: holes far apart in a lattice each take a sphere where one was, without overlap") {
  const double r = 0.1, a = 2.02 * r;  // (a lattice's largest gap between its centres holds no sphere)
  const Mesh cube = make_cube(1.0, 2);
  const Boundary boundary(cube);
  const std::vector<Vec3> taken = {Vec3(-2, -2, -2) * a, Vec3(2, 2, 2) * a, Vec3(2, -2, 0) * a, Vec3(-3, 3, 1) * a};
  ParticleSet holed;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int k = -4; k <= 4; ++k) {
        const Vec3 p = Vec3(i, j, k) * a;
        bool gone = false;
        for (const Vec3& t : taken) gone = gone || length(p - t) < 1e-9;
        if (gone) continue;
        holed.positions.push_back(p);
        holed.radii.push_back(r);
        holed.ids.push_back(holed.ids.size() + 1);
      }
  REQUIRE(holed.size() == 729 - taken.size());
  FillOptions o;
  FillResult result;
  uint64_t next_id = 1000;
  verify_fill(boundary, cube, 8.0, r, std::nullopt, {}, o, holed, ParticleShare{}, next_id, result);
  CHECK(result.holes_filled == static_cast<int>(taken.size()));
  REQUIRE(result.particles.size() == 729);
  for (const Vec3& t : taken) {
    double nearest = 1e9;
    for (const Vec3& p : result.particles.positions) nearest = std::min(nearest, length(p - t));
    INFO("hole at " << t.x << " " << t.y << " " << t.z);
    CHECK(nearest < 0.01 * r);
  }
  CHECK(result.metrics.min_distance >= 1.0);  // none overlaps
  CHECK(result.metrics.contained_share == 1.0);
  CHECK(result.metrics.largest_hole < 1.0);  // no room for another
}

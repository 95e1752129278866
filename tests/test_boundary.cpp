// Boundary: inside/outside, closest point and signed distance against
// analytic answers on generated shapes.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "pfill/boundary.hpp"
#include "pfill/error.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

std::vector<Vec3> random_points(size_t n, double half, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-half, half);
  std::vector<Vec3> points(n);
  for (Vec3& p : points) p = {u(rng), u(rng), u(rng)};
  return points;
}

double max_abs(const Vec3& p) { return std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}); }

// Signed distance to the cube [-h, h]^3 and its gradient.
double cube_distance(const Vec3& p, double h) {
  const Vec3 q(std::fabs(p.x) - h, std::fabs(p.y) - h, std::fabs(p.z) - h);
  const Vec3 out = max(q, Vec3{});
  return length(out) + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

// Distance from the origin to the nearest face plane of a sphere mesh: points
// with radius in [inner, 1] are where tessellation decides the answer.
double inner_radius(const Mesh& mesh) {
  double inner = HUGE_VAL;
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    inner = std::min(inner, std::fabs(dot(normalize(cross(b - a, c - a)), a)));
  }
  return inner;
}

Vec3 reconstruct(const Mesh& mesh, const ClosestPoint& c) {
  const Triangle& t = mesh.triangles[c.triangle];
  return mesh.positions[t[0]] * (1 - c.u - c.v) + mesh.positions[t[1]] * c.u + mesh.positions[t[2]] * c.v;
}

// Checks closest() on a cube of half size 1 against the analytic answer.
void check_cube_closest(const Boundary& boundary, uint32_t seed) {
  int checked_normals = 0;
  for (const Vec3& p : random_points(3000, 2.0, seed)) {
    const ClosestPoint c = boundary.closest(p);
    const double exact = cube_distance(p, 1.0);
    CHECK(std::fabs(c.distance - std::fabs(exact)) < 1e-9);
    CHECK(std::fabs(max_abs(c.point) - 1.0) < 1e-12);
    CHECK(length(reconstruct(boundary.mesh(), c) - c.point) < 1e-12);
    CHECK(std::fabs(length(c.normal) - 1.0) < 1e-9);
    CHECK(boundary.signed_distance(p) == doctest::Approx(exact).epsilon(1e-9));
    // Expected outward normal: the gradient of the cube's signed distance,
    // where it is defined (away from the inner medial planes).
    Vec3 expected;
    if (exact > 1e-6) {
      expected = (p - min(max(p, Vec3(-1, -1, -1)), Vec3(1, 1, 1))) / exact;
    } else {
      std::array<double, 3> a{std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)};
      const int axis = static_cast<int>(std::max_element(a.begin(), a.end()) - a.begin());
      std::array<double, 3> sorted = a;
      std::sort(sorted.begin(), sorted.end());
      if (sorted[2] - sorted[1] < 1e-6) continue;
      expected[axis] = p[axis] > 0 ? 1 : -1;
    }
    CHECK(dot(c.normal, expected) > 1 - 1e-9);
    ++checked_normals;
  }
  CHECK(checked_normals > 2500);
}

}  // namespace

TEST_CASE("inside() matches the analytic sphere away from the tessellation") {
  const Mesh sphere = make_icosphere(1.0, 3);
  const Boundary boundary(sphere);
  const double inner = inner_radius(sphere);
  REQUIRE(inner > 0.98);
  int checked = 0;
  for (const Vec3& p : random_points(4000, 1.3, 1)) {
    const double r = length(p);
    if (r > inner - 1e-9 && r < 1 + 1e-9) continue;
    CHECK(boundary.inside(p) == (r < 1));
    ++checked;
  }
  CHECK(checked > 3800);
  CHECK(boundary.inside(Vec3{0, 0, 0}));
  CHECK(!boundary.inside(Vec3{5, -3, 2}));
}

TEST_CASE("inside() matches the analytic cube") {
  const Boundary boundary(make_cube(1.0, 3));
  for (const Vec3& p : random_points(4000, 1.5, 2)) CHECK(boundary.inside(p) == (max_abs(p) < 1));
  // Points on the axes and diagonals, where axis-aligned rays would hit
  // edges and vertices of the subdivided faces.
  for (double t : {-0.9, -0.5, 0.0, 0.25, 0.75, 0.999}) {
    CHECK(boundary.inside(Vec3{t, 0, 0}));
    CHECK(boundary.inside(Vec3{0, t, 0}));
    CHECK(boundary.inside(Vec3{0, 0, t}));
    CHECK(boundary.inside(Vec3{t, t, t}));
    CHECK(!boundary.inside(Vec3{1.1 + std::fabs(t), t, 0}));
  }
}

TEST_CASE("inside() matches the analytic torus, its hole included") {
  const double R = 1.0, r = 0.4;
  const Boundary boundary(make_torus(R, r, 48, 24));
  // Vertices lie on the torus; flat triangles deviate from it by < 0.004.
  const double tessellation = 0.01;
  int checked = 0;
  for (const Vec3& p : random_points(4000, 1.6, 3)) {
    const double ring = std::hypot(p.x, p.y) - R;
    const double tube = std::hypot(ring, p.z) - r;
    if (std::fabs(tube) < tessellation) continue;
    CHECK(boundary.inside(p) == (tube < 0));
    ++checked;
  }
  CHECK(checked > 3800);
  // The hole's axis is outside all along; the ring's core circle is inside.
  for (double z = -1.0; z <= 1.0; z += 0.125) CHECK(!boundary.inside(Vec3{0, 0, z}));
  for (double a = 0; a < 6.28; a += 0.3) CHECK(boundary.inside(Vec3{R * std::cos(a), R * std::sin(a), 0.0}));
}

TEST_CASE("rays through edges and vertices are counted once") {
  // A cube of 12 triangles: every face diagonal is an edge, and each parity
  // direction is aimed exactly at vertices, edge midpoints and face centres.
  const Boundary boundary(make_cube(1.0, 1));
  std::vector<Vec3> targets;
  for (int x : {-1, 1})
    for (int y : {-1, 1})
      for (int z : {-1, 1}) targets.push_back({double(x), double(y), double(z)});  // vertices
  for (int a = 0; a < 3; ++a)
    for (int s : {-1, 1})
      for (int t : {-1, 1}) {
        Vec3 m;
        m[(a + 1) % 3] = s;
        m[(a + 2) % 3] = t;
        targets.push_back(m);  // edge midpoints
      }
  for (int a = 0; a < 3; ++a)
    for (int s : {-1, 1}) {
      Vec3 c;
      c[a] = s;
      targets.push_back(c);  // face centres: on a face diagonal
    }
  int inside_cases = 0, outside_cases = 0;
  for (const Vec3& d : boundary.parity_directions())
    for (const Vec3& target : targets)
      for (double back : {0.3, 0.5, 3.0}) {
        const Vec3 origin = target - d * back;
        const double m = max_abs(origin);
        if (m < 1 - 1e-6) {
          CHECK(boundary.crossings(origin, d) == 1);
          CHECK(boundary.inside(origin));
          ++inside_cases;
        } else if (m > 1 + 1e-6) {
          CHECK(boundary.crossings(origin, d) % 2 == 0);
          CHECK(!boundary.inside(origin));
          ++outside_cases;
        }
      }
  CHECK(inside_cases > 50);
  CHECK(outside_cases > 50);
  // Rays that only touch the cube along an edge or at a vertex.
  CHECK(boundary.crossings(Vec3{2, 0, 0.1}, Vec3{-1, 1, 0}) % 2 == 0);
  CHECK(boundary.crossings(Vec3{3, -1, -1}, Vec3{-1, 1, 1}) % 2 == 0);
  // Straight through two opposite vertices and two opposite edges.
  CHECK(boundary.crossings(Vec3{-3, -3, -3}, Vec3{1, 1, 1}) == 2);
  CHECK(boundary.crossings(Vec3{-3, -3, 0}, Vec3{1, 1, 0}) == 2);
  CHECK(boundary.crossings(Vec3{0, 0, 0}, Vec3{1, 1, 1}) == 1);
  CHECK(boundary.crossings(Vec3{0, 0, 0}, Vec3{1, 0, 0}) == 1);
}

TEST_CASE("closest() and signed_distance() match the analytic cube exactly") {
  const Boundary boundary(make_cube(1.0, 2));
  CHECK(!boundary.inward_oriented());
  CHECK(boundary.closed());
  CHECK(boundary.signed_volume() == doctest::Approx(8.0));
  check_cube_closest(boundary, 4);
}

TEST_CASE("an inside-out cube: inside() and outward normals unchanged") {
  const Boundary boundary(make_inside_out_cube(1.0, 2));
  CHECK(boundary.inward_oriented());
  CHECK(boundary.signed_volume() == doctest::Approx(-8.0));
  for (const Vec3& p : random_points(1000, 1.5, 5)) CHECK(boundary.inside(p) == (max_abs(p) < 1));
  check_cube_closest(boundary, 6);
  for (const Vec3& p : random_points(1000, 1.5, 7))
    CHECK(boundary.fast_signed_distance(p) == doctest::Approx(cube_distance(p, 1.0)).epsilon(1e-9));
}

TEST_CASE("closest() matches the analytic sphere within the tessellation") {
  const Mesh sphere = make_icosphere(1.0, 4);
  const Boundary boundary(sphere);
  const double tessellation = 1 - inner_radius(sphere);
  for (const Vec3& p : random_points(3000, 1.5, 8)) {
    const double r = length(p);
    const ClosestPoint c = boundary.closest(p);
    CHECK(std::fabs(c.distance - std::fabs(r - 1)) <= tessellation + 1e-12);
    CHECK(length(reconstruct(sphere, c) - c.point) < 1e-12);
    CHECK(std::fabs(length(p - c.point) - c.distance) < 1e-12);
    CHECK(c.u >= -1e-12);
    CHECK(c.v >= -1e-12);
    CHECK(c.u + c.v <= 1 + 1e-12);
    if (r > 0.2) CHECK(dot(c.normal, p / r) > 0.99);
    const double sd = boundary.signed_distance(p);
    CHECK(std::fabs(sd - (r - 1)) <= tessellation + 1e-12);
    CHECK(boundary.fast_signed_distance(p) == doctest::Approx(sd).epsilon(1e-12));
  }
}

TEST_CASE("closest_within() finds the point only inside the radius") {
  const Boundary boundary(make_torus(1.0, 0.4, 32, 16));
  for (const Vec3& p : random_points(500, 1.6, 9)) {
    const ClosestPoint c = boundary.closest(p);
    const auto near = boundary.closest_within(p, c.distance * 1.01 + 1e-9);
    REQUIRE(near.has_value());
    CHECK(near->distance == c.distance);
    CHECK(near->triangle == c.triangle);
    if (c.distance > 1e-3) CHECK(!boundary.closest_within(p, c.distance * 0.99).has_value());
    bool used_parity = true;
    CHECK(boundary.fast_signed_distance(p, c.distance * 2 + 1e-9, &used_parity) ==
          doctest::Approx(boundary.signed_distance(p)).epsilon(1e-12));
    CHECK(!used_parity);  // closed and consistently oriented: pseudonormals decide
  }
}

TEST_CASE("batched queries equal the single ones") {
  const Boundary boundary(make_torus(1.0, 0.4, 32, 16));
  const std::vector<Vec3> points = random_points(2000, 1.6, 10);
  const auto inside = boundary.inside(points);
  const auto closest = boundary.closest(points);
  const auto signed_distance = boundary.signed_distance(points);
  REQUIRE(inside.size() == points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    CHECK(inside[i] == boundary.inside(points[i]));
    const ClosestPoint c = boundary.closest(points[i]);
    CHECK(closest[i].distance == c.distance);
    CHECK(closest[i].triangle == c.triangle);
    CHECK(closest[i].point == c.point);
    CHECK(signed_distance[i] == boundary.signed_distance(points[i]));
  }
}

TEST_CASE("an open cube: the vote stays right away from the missing face") {
  // With the +z face gone, rays leaving through the opening see no wall. A
  // point inside is still voted inside while most of its rays meet a wall:
  // everywhere below z = 0 for the default 5 rays. Close under the opening
  // the vote turns to outside; nothing crashes and distances stay exact.
  const Boundary boundary(make_open_cube(1.0, 2));
  CHECK(!boundary.closed());
  int below = 0;
  for (const Vec3& p : random_points(3000, 1.5, 11)) {
    if (max_abs(p) > 1) {
      if (p.z < 1) CHECK(!boundary.inside(p));
      continue;
    }
    if (p.z < 0) {
      CHECK(boundary.inside(p));
      ++below;
    }
    // Exact distance to the five remaining faces.
    const double d = std::min({1 - std::fabs(p.x), 1 - std::fabs(p.y), 1 + p.z});
    CHECK(boundary.closest(p).distance == doctest::Approx(d).epsilon(1e-9));
  }
  CHECK(below > 350);
  // fast_signed_distance falls back on the vote next to the open rim.
  bool used_parity = false;
  boundary.fast_signed_distance(Vec3{0.999, 0.0, 0.999}, HUGE_VAL, &used_parity);
  CHECK(used_parity);
}

TEST_CASE("bad input gives a clear error") {
  CHECK_THROWS_AS(Boundary(make_cube(), BoundaryOptions{4}), Error);
  CHECK_THROWS_AS(Boundary(make_cube(), BoundaryOptions{0}), Error);
  Mesh empty;
  empty.source = "empty.obj";
  CHECK_THROWS_WITH_AS(Boundary{empty}, doctest::Contains("empty.obj"), Error);
  Mesh bad = make_cube();
  bad.triangles[3][1] = 99;
  CHECK_THROWS_AS(Boundary{bad}, Error);
  const Boundary boundary(make_cube());
  CHECK_THROWS_AS(boundary.crossings(Vec3{}, Vec3{}), Error);
}

TEST_CASE("a Boundary moves and keeps answering") {
  Boundary first(make_icosphere(2.0, 2));
  Boundary second = std::move(first);
  CHECK(second.inside(Vec3{0.5, 0.5, 0.5}));
  CHECK(second.closest(Vec3{0, 0, 5}).distance == doctest::Approx(3.0));
}

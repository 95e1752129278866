// Mesh diagnostics and operations on shapes generated in code.
#include <doctest/doctest.h>

#include <cmath>

#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {
}

TEST_CASE("cube: exact volume, area, closed, genus 0") {
  for (int n : {1, 3}) {
    const MeshDiagnostics d = diagnose(make_cube(1.0, n));
    CHECK(d.triangles == static_cast<size_t>(12 * n * n));
    CHECK(d.vertices == static_cast<size_t>(6 * n * n + 2));
    CHECK(d.signed_volume == doctest::Approx(8.0).epsilon(1e-12));
    CHECK(d.surface_area == doctest::Approx(24.0).epsilon(1e-12));
    CHECK(d.watertight());
    CHECK(d.boundary_loops == 0);
    CHECK(d.misoriented_edges == 0);
    CHECK(d.degenerate_triangles == 0);
    CHECK(d.components == 1);
    REQUIRE(d.genus.has_value());
    CHECK(*d.genus == 0);
    CHECK(d.bounds.lo.x == -1.0);
    CHECK(d.bounds.hi.z == 1.0);
  }
}

TEST_CASE("icosphere: volume and area approach the sphere's within the tessellation error") {
  double previous_error = 1.0;
  for (int s = 2; s <= 5; ++s) {
    const MeshDiagnostics d = diagnose(make_icosphere(2.0, s));
    const double exact_v = 4.0 / 3.0 * kPi * 8.0, exact_a = 4.0 * kPi * 4.0;
    const double err_v = (exact_v - d.signed_volume) / exact_v;
    const double err_a = (exact_a - d.surface_area) / exact_a;
    // An inscribed polyhedron: always smaller, error shrinks ~4x per level.
    CHECK(err_v > 0);
    CHECK(err_a > 0);
    CHECK(err_v < 0.15 / std::pow(4.0, s - 1));
    CHECK(err_a < 0.15 / std::pow(4.0, s - 1));
    CHECK(err_v < previous_error);
    previous_error = err_v;
    CHECK(d.watertight());
    CHECK(*d.genus == 0);
  }
}

TEST_CASE("torus: genus 1, volume and area near 2 pi^2 R r^2 and 4 pi^2 R r") {
  const double R = 1.0, r = 0.3;
  const MeshDiagnostics d = diagnose(make_torus(R, r, 128, 64));
  REQUIRE(d.genus.has_value());
  CHECK(*d.genus == 1);
  CHECK(d.watertight());
  CHECK(d.signed_volume == doctest::Approx(2 * kPi * kPi * R * r * r).epsilon(0.01));
  CHECK(d.surface_area == doctest::Approx(4 * kPi * kPi * R * r).epsilon(0.01));
}

TEST_CASE("two disjoint shapes: two components, genus summed") {
  Mesh a = make_torus(1.0, 0.3, 32, 16);
  const Mesh b = make_cube(0.5, 2);
  const uint32_t offset = static_cast<uint32_t>(a.positions.size());
  for (const Vec3& p : b.positions) a.positions.push_back(p + Vec3(5, 0, 0));
  for (const Triangle& t : b.triangles) a.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const MeshDiagnostics d = diagnose(a);
  CHECK(d.components == 2);
  CHECK(*d.genus == 1);
}

TEST_CASE("open cube: boundary edges, one hole, volume still estimated") {
  const MeshDiagnostics d = diagnose(make_open_cube(1.0, 2));
  CHECK_FALSE(d.watertight());
  CHECK(d.boundary_edges == 8);
  CHECK(d.boundary_loops == 1);
  CHECK_FALSE(d.genus.has_value());
  // The hole is planar, so the fan that closes it restores the exact volume.
  CHECK(d.signed_volume == doctest::Approx(8.0).epsilon(1e-12));
}

TEST_CASE("inside-out cube: negative volume") {
  const MeshDiagnostics d = diagnose(make_inside_out_cube(1.0, 2));
  CHECK(d.inside_out());
  CHECK(d.signed_volume == doctest::Approx(-8.0).epsilon(1e-12));
  CHECK(d.volume() == doctest::Approx(8.0).epsilon(1e-12));
  CHECK(d.watertight());
}

TEST_CASE("one flipped triangle is reported as misoriented edges") {
  Mesh m = make_cube(1.0, 2);
  std::swap(m.triangles[0][1], m.triangles[0][2]);
  CHECK(diagnose(m).misoriented_edges == 3);
}

TEST_CASE("non-manifold edge and degenerate triangle are counted") {
  Mesh m = make_cube(1.0, 1);
  const Triangle fin{m.triangles[0][0], m.triangles[0][1], static_cast<uint32_t>(m.positions.size())};
  m.positions.push_back({3, 3, 3});
  m.triangles.push_back(fin);
  m.triangles.push_back({0, 0, 1});
  const MeshDiagnostics d = diagnose(m);
  CHECK(d.non_manifold_edges >= 1);
  CHECK(d.degenerate_triangles == 1);
  CHECK_FALSE(d.watertight());
}

TEST_CASE("weld_vertices merges exact and near duplicates, keeps distinct ones") {
  Mesh m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  m.triangles = {{0, 1, 2}, {3, 5, 4}};
  CHECK(weld_vertices(m) == 2);
  CHECK(m.positions.size() == 4);
  CHECK(m.triangles[1][0] == m.triangles[0][1]);
  CHECK(m.triangles[1][2] == m.triangles[0][2]);

  Mesh near;
  near.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1 + 1e-9, 0, 0}, {0, 1 - 1e-9, 0}, {1, 1, 0}};
  near.triangles = {{0, 1, 2}, {3, 5, 4}};
  Mesh exact = near;
  CHECK(weld_vertices(exact) == 0);
  CHECK(weld_vertices(near, 1e-6) == 2);
  CHECK(near.positions.size() == 4);
}

TEST_CASE("validate names the problem") {
  Mesh m = make_cube();
  m.source = "thing.obj";
  m.triangles[3][1] = 999;
  CHECK_THROWS_WITH_AS(validate(m), doctest::Contains("thing.obj: triangle 3 uses vertex index 999"), Error);
  m = make_cube();
  m.positions[2].y = std::nan("");
  CHECK_THROWS_WITH_AS(validate(m), doctest::Contains("NaN"), Error);
  Mesh empty;
  CHECK_THROWS_WITH_AS(validate(empty), doctest::Contains("no triangles"), Error);
}

TEST_CASE("flip_orientation twice is the identity and flips corner attributes") {
  const Mesh original = make_cube(1.0, 2);
  Mesh m = original;
  flip_orientation(m);
  CHECK(diagnose(m).inside_out());
  CHECK(m.corner_uvs[1] == original.corner_uvs[2]);
  flip_orientation(m);
  CHECK(m.triangles == original.triangles);
  CHECK(m.corner_uvs == original.corner_uvs);
}

TEST_CASE("built-in shapes are closed and named; unknown names list the choices") {
  for (const std::string& name : builtin_shape_names()) {
    const Mesh m = make_builtin(name);
    const MeshDiagnostics d = diagnose(m);
    CHECK(d.watertight());
    CHECK(d.signed_volume > 0);
    CHECK(m.source.find(name) != std::string::npos);
  }
  CHECK_THROWS_WITH_AS(make_builtin("teapot"), doctest::Contains("torus"), Error);
}

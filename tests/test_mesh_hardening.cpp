// Real-world mesh trouble that loads and measures right (issue 21): small
// meshes keep their vertices, overlapping parts are a union (inside, volume,
// distances), repeated faces count once, NaNs and malformed numbers name the
// OBJ vertex, coordinates beyond what Embree can take are one clear error,
// and messages never echo a file's bulk or its control bytes.
#include <doctest/doctest.h>

#include <cmath>

#include "bad_meshes.hpp"
#include "load_error.hpp"
#include "mesh_writers.hpp"
#include "pfill/boundary.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/sdf.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {


}  // namespace

TEST_CASE("a mesh a millionth of a unit across keeps every vertex, in OBJ, PLY, OFF and STL") {
  TempDir dir("tiny");
  const Mesh sphere = make_icosphere(1.0, 3);
  const Mesh tiny = moved(sphere, {}, 1e-6);
  for (const char* name : {"tiny.obj", "tiny.ply", "tiny.off", "tiny.stl"}) {
    const std::string path = dir.file(name);
    if (std::string(name).find(".obj") != std::string::npos) write_obj(tiny, path);
    if (std::string(name).find(".ply") != std::string::npos) write_ply_binary(tiny, path);
    if (std::string(name).find(".off") != std::string::npos) write_off(tiny, path);
    if (std::string(name).find(".stl") != std::string::npos) write_stl_binary(tiny, path);
    CAPTURE(name);
    const Mesh m = load_mesh(path);
    CHECK(m.vertex_count() == sphere.vertex_count());
    CHECK(m.triangle_count() == sphere.triangle_count());
    const MeshDiagnostics d = diagnose(m);
    CHECK(d.watertight());
    CHECK(d.non_manifold_edges == 0);
    CHECK(d.volume() == doctest::Approx(diagnose(sphere).volume() * 1e-18).epsilon(1e-4));
  }
}

TEST_CASE("overlapping parts: info says so and gives the union's volume") {
  const MeshDiagnostics d = diagnose(overlapping_cubes());
  CHECK(d.components == 2);
  CHECK(d.watertight());
  CHECK(d.overlapping());
  CHECK(std::fabs(d.signed_volume) == doctest::Approx(2.0));  // the parts' sum
  CHECK(d.volume() == doctest::Approx(1.875).epsilon(0.005));  // the union's
  // Two apart, or a single closed part: no overlap, the exact volume.
  const Mesh cube = moved(make_cube(0.5, 2), {0.5, 0.5, 0.5});
  const MeshDiagnostics apart = diagnose(merged(cube, moved(cube, {3, 0, 0})));
  CHECK_FALSE(apart.overlapping());
  CHECK(apart.volume() == doctest::Approx(2.0));
  CHECK_FALSE(diagnose(make_torus()).overlapping());
  // Inside-out, the sweep counts it outward all the same.
  Mesh inverted = overlapping_cubes();
  flip_orientation(inverted);
  CHECK(diagnose(inverted).overlapping());
  CHECK(diagnose(inverted).volume() == doctest::Approx(1.875).epsilon(0.005));
}

TEST_CASE("overlapping parts: inside is the union, and distances ignore the inner walls") {
  const Boundary b(overlapping_cubes());
  CHECK(b.overlapping());
  CHECK(b.union_of_parts());
  // Winding number 2 (in both cubes): parity would call it outside.
  CHECK(b.inside({0.75, 0.75, 0.75}));
  CHECK(b.inside({0.25, 0.25, 0.25}));
  CHECK(b.inside({1.25, 1.25, 1.25}));
  CHECK_FALSE(b.inside({1.25, 0.25, 0.25}));
  CHECK_FALSE(b.inside({2, 2, 2}));
  // (0.9, 0.9, 0.9) lies 0.1 from the first cube's faces, but those are
  // inside the second cube: the union's depth there is 0.4.
  CHECK(b.signed_distance({0.9, 0.9, 0.9}) == doctest::Approx(-0.4));
  CHECK(b.fast_signed_distance({0.9, 0.9, 0.9}) == doctest::Approx(-0.4));
  CHECK(b.signed_distance({1.6, 1.0, 1.0}) == doctest::Approx(0.1));
  CHECK(b.closest({0.9, 0.9, 0.9}).distance == doctest::Approx(0.4));
  // The field the fill samples is negative all through the overlap.
  const ScalarGrid field = build_signed_distance_field(b, SdfOptions(0.05));
  for (double t = 0.55; t < 0.96; t += 0.05) CHECK(sample(field, {t, t, t}) < -0.04);
}

TEST_CASE("a surface through itself: inside by winding number, signs agree with it") {
  const Mesh m = self_intersecting_cubes();
  CHECK(diagnose(m).components == 1);
  CHECK(diagnose(m).overlapping());
  const Boundary b(m);
  CHECK(b.overlapping());
  CHECK_FALSE(b.union_of_parts());
  for (const Vec3& p : {Vec3{0.75, 0.75, 0.75}, Vec3{0.9, 0.8, 0.7}, Vec3{0.2, 0.2, 0.2}, Vec3{1.3, 1.3, 1.3}}) {
    CAPTURE(p.x);
    CHECK(b.inside(p));
    CHECK(b.fast_signed_distance(p) < 0);
    CHECK(b.signed_distance(p) < 0);
  }
}

TEST_CASE("repeated faces count once: same winding dropped, opposite pair removed") {
  Mesh m = make_cube(1.0, 1);
  const size_t n = m.triangle_count();
  m.triangles.push_back(m.triangles[0]);                                                  // the same again
  m.triangles.push_back({m.triangles[1][1], m.triangles[1][2], m.triangles[1][0]});       // rotated: the same
  m.triangles.push_back({m.triangles[2][0], m.triangles[2][2], m.triangles[2][1]});       // reversed
  CHECK(remove_duplicate_triangles(m) == 4);
  CHECK(m.triangle_count() == n - 1);  // the reversed pair went altogether
  // Loaded from a file with doubled faces, the cube is clean and closed.
  TempDir dir("dup");
  Mesh doubled = make_cube(1.0, 2);
  const size_t faces = doubled.triangle_count();
  for (size_t t = 0; t < faces; ++t) doubled.triangles.push_back(doubled.triangles[t]);
  write_obj(doubled, dir.file("doubled.obj"));
  const Mesh loaded = load_mesh(dir.file("doubled.obj"));
  CHECK(loaded.triangle_count() == faces);
  CHECK(diagnose(loaded).watertight());
  CHECK(Boundary(loaded).inside({0.1, 0.2, 0.3}));
}

TEST_CASE("OBJ: a NaN names its OBJ vertex and line; '0/881192' is not a coordinate") {
  TempDir dir("objnum");
  const Mesh sphere = make_icosphere(1.0, 2);
  write_obj(sphere, dir.file("ok.obj"));
  std::string text;
  {
    const std::vector<uint8_t> bytes = read_bytes(dir.file("ok.obj"));
    text.assign(bytes.begin(), bytes.end());
  }
  auto with_vertex = [&](int number, const std::string& line) {
    std::string out, rest = text;
    int v = 0;
    size_t start = 0;
    while (start < rest.size()) {
      size_t end = rest.find('\n', start);
      std::string l = rest.substr(start, end - start);
      if (l.rfind("v ", 0) == 0 && ++v == number) l = line;
      out += l + "\n";
      start = end + 1;
    }
    return out;
  };
  write_text(dir.file("nan.obj"), with_vertex(101, "v nan 0 0"));
  std::string message = load_error(dir.file("nan.obj"));
  CAPTURE(message);
  CHECK(message.find("vertex 101 (line 102)") != std::string::npos);
  CHECK(message.find("NaN") != std::string::npos);
  write_text(dir.file("slash.obj"), with_vertex(5, "v 0/881192 0.5 0.5"));
  message = load_error(dir.file("slash.obj"));
  CHECK(message.find("vertex 5") != std::string::npos);
  CHECK(message.find("'0/881192' is not a number") != std::string::npos);
}

TEST_CASE("coordinates beyond 1e15 are one clear error, in meshes and particle files") {
  TempDir dir("huge");
  write_obj(moved(make_icosphere(1.0, 2), {}, 2e18), dir.file("huge.obj"));
  CHECK(load_error(dir.file("huge.obj")).find("beyond the +-1e15") != std::string::npos);
  write_stl_binary(moved(make_icosphere(1.0, 2), {}, 2e18), dir.file("huge.stl"));
  CHECK(load_error(dir.file("huge.stl")).find("beyond the +-1e15") != std::string::npos);
  Mesh m = make_cube();
  m.positions[0].x = 1.9e18;
  CHECK_THROWS_AS(Boundary{m}, Error);
  write_text(dir.file("far.csv"), "x,y,z,radius\n1.9e18,0,0,0.1\n");
  try {
    read_particles(dir.file("far.csv"));
    FAIL("a particle at 1.9e18 was accepted");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find("beyond the +-1e15") != std::string::npos);
  }
  // A huge but representable mesh loads.
  write_obj(moved(make_icosphere(1.0, 2), {}, 1e12), dir.file("big.obj"));
  CHECK(load_error(dir.file("big.obj")).empty());
}

TEST_CASE("an OBJ far from the origin keeps its shape (read in double, not assimp's float)") {
  TempDir dir("far");
  const Mesh sphere = make_icosphere(1.0, 3);
  write_obj(moved(sphere, {1e6, -2e6, 3e5}), dir.file("far.obj"));
  const Mesh m = load_mesh(dir.file("far.obj"));
  CHECK(m.vertex_count() == sphere.vertex_count());
  CHECK(diagnose(m).volume() == doctest::Approx(diagnose(sphere).volume()).epsilon(1e-5));
  CHECK(m.bounds().centre().x == doctest::Approx(1e6));
}

TEST_CASE("messages quote a few dozen bytes of a corrupt file and escape its control bytes") {
  TempDir dir("quote");
  // An ASCII STL with one keyword corrupted: assimp quotes what follows.
  std::string stl = "solid x\n";
  for (int i = 0; i < 20000; ++i)
    stl += "facet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n";
  stl += "endsolid x\n";
  stl[8] = 'x';
  write_text(dir.file("bad.stl"), stl);
  std::string message = load_error(dir.file("bad.stl"));
  CAPTURE(message);
  CHECK(message.size() < 700);
  write_text(dir.file("ctl.csv"), "x,y,z,radius\n1,\x1b[31mred,0,0.1\n");
  try {
    read_particles(dir.file("ctl.csv"));
  } catch (const Error& e) {
    message = e.what();
  }
  CHECK(message.find('\x1b') == std::string::npos);
  CHECK(message.find("\\x1B[31m") != std::string::npos);
  CHECK(excerpt(std::string(1000, 'a')).size() < 80);
}

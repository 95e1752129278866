// Bad mesh files: every reader must throw pfill::Error naming the file and
// the problem, and truncated or corrupted copies of valid files must give an
// error or a valid mesh, never a crash.
#include <doctest/doctest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <limits>
#include <random>

#include "load_error.hpp"
#include "mesh_writers.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

void check_error(const std::string& path, const std::string& problem) {
  const std::string message = load_error(path);
  CAPTURE(message);
  CHECK(message.find(path) != std::string::npos);
  CHECK(message.find(problem) != std::string::npos);
}

// A one-triangle glTF whose primitive is in `mode` with `indices` over 3 vertices.
void write_small_gltf(const std::string& path, int mode, const std::vector<uint32_t>& indices,
                      float first_x = 0.0f) {
  GltfBuilder b;
  const int pos = b.add_positions({{first_x, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  tinygltf::Node node;
  node.mesh = b.add_mesh("bad", {triangle_primitive(pos, b.add_indices<uint16_t>(indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT)),
                                 triangle_primitive(pos, -1),
                                 triangle_primitive(pos, -1, mode)});
  b.set_scene({b.add_node(node)});
  REQUIRE(b.save(path, path.size() > 4 && path.substr(path.size() - 4) == ".glb"));
}

}  // namespace

TEST_CASE("a missing file names the file, for every reader") {
  TempDir dir("missing");
  for (const char* name : {"none.obj", "none.stl", "none.glb", "none.gltf", "none.smf", "none.ply"})
    check_error(dir.file(name), "cannot open");
}

TEST_CASE("an empty file is an error, for every reader") {
  TempDir dir("empty");
  for (const char* name : {"empty.obj", "empty.stl", "empty.glb", "empty.gltf", "empty.smf", "empty.off"}) {
    write_text(dir.file(name), "");
    check_error(dir.file(name), "empty");
  }
}

TEST_CASE("a file without triangles is an error") {
  TempDir dir("notri");
  write_text(dir.file("points.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  check_error(dir.file("points.obj"), "no triangles");
  write_text(dir.file("points.smf"), "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  check_error(dir.file("points.smf"), "no triangles");
  write_text(dir.file("comments.smf"), "# nothing\n\n");
  check_error(dir.file("comments.smf"), "no triangles");
  GltfBuilder b;  // a node without a mesh
  tinygltf::Node empty;
  empty.name = "empty";
  b.set_scene({b.add_node(empty)});
  REQUIRE(b.save(dir.file("nomesh.gltf"), false));
  check_error(dir.file("nomesh.gltf"), "no triangles");
  write_text(dir.file("lines.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
  check_error(dir.file("lines.obj"), "no triangles");
}

TEST_CASE("an index out of range is an error in OBJ, OFF, PLY, glTF and SMF") {
  TempDir dir("range");
  write_text(dir.file("range.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  check_error(dir.file("range.obj"), "out of range");
  write_text(dir.file("range.off"), "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 5\n");
  check_error(dir.file("range.off"), "out of range");
  write_text(dir.file("range.ply"),
             "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  check_error(dir.file("range.ply"), "out of range");
  write_small_gltf(dir.file("range.glb"), TINYGLTF_MODE_TRIANGLES, {0, 1, 3});
  check_error(dir.file("range.glb"), "index 3 out of range");
  write_text(dir.file("range.smf"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n");
  check_error(dir.file("range.smf"), "out of range");
}

TEST_CASE("NaN and infinite coordinates are errors") {
  TempDir dir("nan");
  write_text(dir.file("nan.obj"), "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  check_error(dir.file("nan.obj"), "NaN");
  write_text(dir.file("inf.obj"), "v 0 0 0\nv 1 inf 0\nv 0 1 0\nf 1 2 3\n");
  check_error(dir.file("inf.obj"), "infinite");
  write_text(dir.file("nan.smf"), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  check_error(dir.file("nan.smf"), "NaN");
  write_small_gltf(dir.file("nan.gltf"), TINYGLTF_MODE_TRIANGLES, {0, 1, 2}, std::numeric_limits<float>::quiet_NaN());
  check_error(dir.file("nan.gltf"), "NaN");
  Mesh m = make_cube();
  m.positions[3].y = std::numeric_limits<double>::infinity();
  write_stl_binary(m, dir.file("inf.stl"));
  check_error(dir.file("inf.stl"), "infinite");
}

TEST_CASE("glTF points and lines are rejected naming the primitive and the mode") {
  TempDir dir("mode");
  write_small_gltf(dir.file("lines.glb"), TINYGLTF_MODE_LINE, {0, 1, 2});
  check_error(dir.file("lines.glb"), "primitive 2 of mesh 'bad' is LINES; pfill needs triangles");
  write_small_gltf(dir.file("points.gltf"), TINYGLTF_MODE_POINTS, {0, 1, 2});
  check_error(dir.file("points.gltf"), "is POINTS");
}

TEST_CASE("unknown extensions and unreadable textures are errors") {
  TempDir dir("other");
  write_text(dir.file("mesh.xyz123"), "1 2 3\n");
  check_error(dir.file("mesh.xyz123"), "unknown mesh format");
  write_text(dir.file("noext"), "v 0 0 0\n");
  check_error(dir.file("noext"), "unknown mesh format");
  // An OBJ whose material's texture is not an image.
  write_text(dir.file("tex.png"), "this is not a PNG");
  write_text(dir.file("t.mtl"), "newmtl m\nmap_Kd tex.png\n");
  write_text(dir.file("t.obj"), "mtllib t.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nusemtl m\nf 1/1 2/1 3/1\n");
  check_error(dir.file("t.obj"), "cannot be decoded");
  // A GLB cut in half.
  write_small_gltf(dir.file("whole.glb"), TINYGLTF_MODE_TRIANGLES, {0, 1, 2});
  std::vector<uint8_t> bytes = read_bytes(dir.file("whole.glb"));
  bytes.resize(bytes.size() / 2);
  write_bytes(dir.file("half.glb"), bytes);
  check_error(dir.file("half.glb"), "half.glb");
}

TEST_CASE("fuzz: truncated and corrupted files give pfill::Error or a valid mesh, never a crash") {
  TempDir dir("fuzz");
  const Mesh cube = make_cube(1.0, 2);
  Mesh coloured = make_torus(1.0, 0.4, 12, 6);
  std::vector<Rgba> colours(coloured.vertex_count(), Rgba{0.2f, 0.4f, 0.6f, 1.0f});
  std::vector<std::string> seeds;
  auto add = [&](const std::string& name) { seeds.push_back(dir.file(name)); return dir.file(name); };
  write_obj(cube, add("seed.obj"));
  write_stl_ascii(cube, add("seed_ascii.stl"));
  write_stl_binary(cube, add("seed_binary.stl"));
  write_ply_ascii(cube, add("seed_ascii.ply"));
  write_ply_binary(cube, add("seed_binary.ply"));
  write_off(cube, add("seed.off"));
  write_smf(coloured, add("seed.smf"), colours);
  REQUIRE(write_gltf(cube, add("seed.gltf"), false));
  REQUIRE(write_gltf(cube, add("seed.glb"), true));
  const std::string spot = std::string(PFILL_SHARED_MESHES) + "/spot.glb";
  if (std::filesystem::exists(spot)) seeds.push_back(spot);

  std::mt19937 random(20261125);
  const int variants = 200;
  size_t loaded = 0, rejected = 0;
  const auto start = std::chrono::steady_clock::now();
  for (const std::string& seed : seeds) {
    const std::vector<uint8_t> original = read_bytes(seed);
    REQUIRE(original.size() > 16);
    REQUIRE_NOTHROW(load_mesh(seed));  // the valid file itself loads
    const std::string extension = seed.substr(seed.find_last_of('.'));
    for (int v = 0; v < variants; ++v) {
      std::vector<uint8_t> bytes = original;
      const int kind = v % 4;
      if (kind == 0) {  // cut short anywhere
        bytes.resize(std::uniform_int_distribution<size_t>(0, bytes.size() - 1)(random));
      } else {  // overwrite 1..16 bytes with random ones, or with digits and signs (kind 2), or cut and corrupt (kind 3)
        const int hits = std::uniform_int_distribution<int>(1, 16)(random);
        for (int h = 0; h < hits; ++h) {
          const size_t at = std::uniform_int_distribution<size_t>(0, bytes.size() - 1)(random);
          const char digits[] = "0123456789-+.e \n";
          bytes[at] = kind == 2 ? static_cast<uint8_t>(digits[random() % (sizeof digits - 1)])
                                : static_cast<uint8_t>(random());
        }
        if (kind == 3) bytes.resize(bytes.size() - std::uniform_int_distribution<size_t>(0, bytes.size() / 4)(random));
      }
      const std::string path = dir.file("variant" + extension);
      write_bytes(path, bytes);
      CAPTURE(seed);
      CAPTURE(v);
      try {
        const Mesh m = load_mesh(path);
        CHECK_NOTHROW(validate(m));
        CHECK(m.triangle_count() > 0);
        ++loaded;
      } catch (const Error& e) {
        const std::string message = e.what();
        CHECK(message.find(path) != std::string::npos);
        CHECK(std::none_of(message.begin(), message.end(), [](char c) { return c == '\n' || c == '\r' || c == '\0'; }));
        ++rejected;
      } catch (const std::exception& e) {
        FAIL("not a pfill::Error: " << e.what());
      }
    }
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const size_t total = seeds.size() * variants;
  MESSAGE(total << " corrupted files: " << loaded << " loaded, " << rejected << " rejected, in "
                                   << seconds << " s");
  CHECK(loaded + rejected == total);
  CHECK(rejected > 0);
}

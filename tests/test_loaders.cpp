// Mesh readers on files written by the tests themselves (glTF/GLB with node
// transforms, every index type, strides and colours; OBJ, STL, PLY, OFF
// through assimp; SMF) and on the shared real meshes when present.
#include <doctest/doctest.h>

#include "skip.hpp"

#include <cmath>
#include <filesystem>
#include <map>
#include <set>

#include "mesh_writers.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

float srgb(float linear) {
  return linear <= 0.0031308f ? 12.92f * linear : 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

bool has_point(const Mesh& m, const Vec3& p, double tolerance) {
  for (const Vec3& q : m.positions)
    if (length(q - p) <= tolerance) return true;
  return false;
}

// Every undirected edge used by exactly two triangles.
bool is_closed(const Mesh& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const Triangle& t : m.triangles)
    for (int k = 0; k < 3; ++k) ++edges[std::minmax(t[k], t[(k + 1) % 3])];
  for (const auto& e : edges)
    if (e.second != 2) return false;
  return !edges.empty();
}

std::vector<uint32_t> flat_indices(const Mesh& m, size_t first, size_t count) {
  std::vector<uint32_t> out;
  for (size_t t = first; t < first + count; ++t) out.insert(out.end(), m.triangles[t].begin(), m.triangles[t].end());
  return out;
}

// A quaternion turning 90 degrees about z: (x, y, z) -> (-y, x, z).
const std::vector<double> kQuarterTurnZ = {0, 0, std::sqrt(0.5), std::sqrt(0.5)};

// Linear vertex colours of the cube's 8 vertices for the float COLOR_0 primitive.
std::array<float, 3> linear_colour(uint32_t v) {
  return {0.1f * static_cast<float>(v % 3), 0.5f, 0.05f * static_cast<float>(v)};
}

}  // namespace

TEST_CASE("glTF: node transforms, every index type, byte strides and COLOR_0, as .gltf and .glb") {
  const Mesh cube = make_cube(1.0, 1);  // 8 vertices, 12 triangles
  REQUIRE(cube.vertex_count() == 8);
  REQUIRE(cube.triangle_count() == 12);
  GltfBuilder b;
  const int positions = b.add_positions(cube.positions);

  auto p0 = triangle_primitive(positions, b.add_indices<uint8_t>(flat_indices(cube, 0, 3), TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE));
  auto p1 = triangle_primitive(positions, b.add_indices<uint16_t>(flat_indices(cube, 3, 3), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
  auto p2 = triangle_primitive(positions, b.add_indices<uint32_t>(flat_indices(cube, 6, 3), TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT));
  {  // float VEC3 colours, one per cube vertex
    std::vector<uint8_t> bytes;
    for (uint32_t v = 0; v < 8; ++v)
      for (float c : linear_colour(v)) append_raw(bytes, c);
    p2.attributes["COLOR_0"] =
        b.add_accessor(b.add_view(bytes), 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 8);
  }
  tinygltf::Primitive p3;  // non-indexed; position and normalized-ubyte colour interleaved, stride 16
  {
    std::vector<uint8_t> bytes;
    for (uint32_t v : flat_indices(cube, 9, 3)) {
      for (int k = 0; k < 3; ++k) append_raw(bytes, static_cast<float>(cube.positions[v][k]));
      for (uint8_t c : {uint8_t(255), uint8_t(0), uint8_t(51), uint8_t(255)}) append_raw(bytes, c);
    }
    const int view = b.add_view(bytes, 16);
    p3.attributes["POSITION"] = b.add_accessor(view, 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, 9);
    p3.attributes["COLOR_0"] =
        b.add_accessor(view, 12, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, 9, true);
    p3.mode = TINYGLTF_MODE_TRIANGLES;
  }
  const int first_mesh = b.add_mesh("pieces", {p0, p1, p2, p3});
  const int whole_cube = b.add_mesh(
      "whole", {triangle_primitive(positions, b.add_indices<uint32_t>(flat_indices(cube, 0, 12),
                                                                      TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))});

  tinygltf::Node child;  // quarter turn about z under a parent that scales by 2 and moves
  child.rotation = kQuarterTurnZ;
  child.mesh = first_mesh;
  tinygltf::Node parent;
  parent.translation = {1, 2, 3};
  parent.scale = {2, 2, 2};
  parent.children = {b.add_node(child)};
  tinygltf::Node mirror;  // a mirrored copy: winding must flip to stay outward
  mirror.matrix = {-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 0, 0, 1};
  mirror.mesh = whole_cube;
  b.set_scene({b.add_node(parent), b.add_node(mirror)});

  TempDir dir("gltf");
  for (const bool binary : {false, true}) {
    const std::string path = dir.file(binary ? "pieces.glb" : "pieces.gltf");
    REQUIRE(b.save(path, binary));
    CAPTURE(path);
    const Mesh m = load_mesh(path);
    CHECK(m.source == path);
    CHECK(m.triangle_count() == 24);
    CHECK(m.vertex_count() == 16);  // welded: 8 per cube
    for (const Vec3& p : cube.positions) {
      const Vec3 turned{-p.y, p.x, p.z};
      CHECK(has_point(m, turned * 2.0 + Vec3{1, 2, 3}, 1e-6));
      CHECK(has_point(m, Vec3{-p.x + 10, p.y, p.z}, 1e-6));
    }
    // 64 (scaled cube) + 8 (mirrored cube, orientation kept).
    CHECK(signed_volume(m) == doctest::Approx(72.0).epsilon(1e-9));
    CHECK(is_closed(m));

    REQUIRE(m.has_colours());
    for (size_t t = 0; t < 6; ++t)
      for (int k = 0; k < 3; ++k) CHECK(m.corner_colours[3 * t + k][0] == 1.0f);  // no COLOR_0: white
    for (size_t t = 6; t < 9; ++t)
      for (int k = 0; k < 3; ++k) {
        const auto lin = linear_colour(cube.triangles[t][k]);
        for (int c = 0; c < 3; ++c) CHECK(m.corner_colours[3 * t + k][c] == doctest::Approx(srgb(lin[c])).epsilon(1e-5));
        CHECK(m.corner_colours[3 * t + k][3] == 1.0f);
      }
    for (size_t t = 9; t < 12; ++t)
      for (int k = 0; k < 3; ++k) {
        CHECK(m.corner_colours[3 * t + k][0] == doctest::Approx(1.0));
        CHECK(m.corner_colours[3 * t + k][1] == doctest::Approx(0.0));
        CHECK(m.corner_colours[3 * t + k][2] == doctest::Approx(srgb(0.2f)).epsilon(1e-5));
      }
    CHECK_FALSE(m.has_uvs());
    CHECK(m.materials.empty());
  }
}

TEST_CASE("glTF: strips and fans are triangulated with consistent winding") {
  // A unit square in z = 0 as a 4-vertex strip and as a 4-vertex fan.
  GltfBuilder b;
  const int strip_pos = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}});
  const int fan_pos = b.add_positions({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  tinygltf::Node node;
  node.mesh = b.add_mesh("square", {triangle_primitive(strip_pos, -1, TINYGLTF_MODE_TRIANGLE_STRIP),
                                    triangle_primitive(fan_pos, -1, TINYGLTF_MODE_TRIANGLE_FAN)});
  b.set_scene({b.add_node(node)});
  TempDir dir("strip");
  const std::string path = dir.file("square.glb");
  REQUIRE(b.save(path, true));
  const Mesh m = load_gltf(path);
  REQUIRE(m.triangle_count() == 4);
  double area = 0;
  for (const Triangle& t : m.triangles) {
    const Vec3 n = cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]);
    CHECK(n.z > 0);  // every triangle faces +z
    area += 0.5 * length(n);
  }
  CHECK(area == doctest::Approx(2.0));
}

TEST_CASE("glTF: base colour texture, sampler, factor and TEXCOORD_0") {
  GltfBuilder b;
  const Mesh cube = make_cube(1.0, 1);
  const int pos = b.add_positions(cube.positions);
  std::vector<uint8_t> uv_bytes;
  for (size_t v = 0; v < cube.positions.size(); ++v) {
    append_raw(uv_bytes, 0.125f * static_cast<float>(v));
    append_raw(uv_bytes, 0.75f);
  }
  tinygltf::Primitive prim = triangle_primitive(
      pos, b.add_indices<uint16_t>(flat_indices(cube, 0, 12), TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT));
  prim.attributes["TEXCOORD_0"] =
      b.add_accessor(b.add_view(uv_bytes), 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, 8);
  prim.material = 0;

  tinygltf::Model& model = b.model();
  tinygltf::Image image;  // 2x1: red, green; tinygltf encodes it as PNG
  image.width = 2;
  image.height = 1;
  image.component = 4;
  image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.image = {255, 0, 0, 255, 0, 255, 0, 255};
  image.mimeType = "image/png";
  image.name = "swatch";
  model.images.push_back(image);
  tinygltf::Sampler sampler;
  sampler.wrapS = TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE;
  sampler.wrapT = TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT;
  model.samplers.push_back(sampler);
  tinygltf::Texture texture;
  texture.source = 0;
  texture.sampler = 0;
  model.textures.push_back(texture);
  tinygltf::Material material;
  material.pbrMetallicRoughness.baseColorFactor = {0.5, 0.25, 1.0, 1.0};
  material.pbrMetallicRoughness.baseColorTexture.index = 0;
  model.materials.push_back(material);

  tinygltf::Node node;
  node.mesh = b.add_mesh("textured", {prim});
  b.set_scene({b.add_node(node)});
  TempDir dir("texture");
  const std::string path = dir.file("textured.glb");
  REQUIRE(b.save(path, true));

  const Mesh m = load_mesh(path);
  REQUIRE(m.textures.size() == 1);
  const Texture& t = m.textures[0];
  CHECK(t.width == 2);
  CHECK(t.height == 1);
  CHECK(t.rgba == std::vector<uint8_t>{255, 0, 0, 255, 0, 255, 0, 255});
  CHECK(t.wrap_s == WrapMode::ClampToEdge);
  CHECK(t.wrap_t == WrapMode::MirroredRepeat);
  REQUIRE(m.materials.size() == 1);
  CHECK(m.materials[0].texture == 0);
  CHECK(m.materials[0].base_colour_factor[1] == doctest::Approx(0.25));
  CHECK(m.triangle_materials == std::vector<uint32_t>(12, 0));
  REQUIRE(m.has_uvs());
  for (size_t tr = 0; tr < 12; ++tr)
    for (int k = 0; k < 3; ++k) {
      CHECK(m.corner_uvs[3 * tr + k][0] == 0.125f * static_cast<float>(cube.triangles[tr][k]));
      CHECK(m.corner_uvs[3 * tr + k][1] == 0.75f);
    }
}

TEST_CASE("OBJ, STL, PLY and OFF through assimp keep counts and volume") {
  struct Writer {
    const char* name;
    void (*write)(const Mesh&, const std::string&);
  };
  const Writer writers[] = {{"cube.obj", write_obj},       {"ascii.stl", write_stl_ascii},
                            {"binary.stl", write_stl_binary}, {"ascii.ply", write_ply_ascii},
                            {"binary.ply", write_ply_binary}, {"shape.off", write_off}};
  TempDir dir("assimp");
  for (const Mesh& shape : {make_cube(1.0, 3), make_torus(1.0, 0.4, 32, 16)}) {
    const double expected_volume = signed_volume(rounded_to_float(shape));  // assimp stores floats
    for (const Writer& w : writers) {
      const std::string path = dir.file(std::to_string(shape.triangle_count()) + "_" + w.name);
      w.write(shape, path);
      CAPTURE(path);
      const Mesh m = load_mesh(path);
      CHECK(m.vertex_count() == shape.vertex_count());
      CHECK(m.triangle_count() == shape.triangle_count());
      CHECK(std::abs(signed_volume(m) - expected_volume) < 1e-6);
      CHECK(is_closed(m));
    }
  }
}

TEST_CASE("OBJ with a diffuse texture map: texture and UVs through assimp") {
  TempDir dir("objtex");
  // A 1x2 BMP written by hand (stb_image decodes it like PNG or JPEG).
  std::vector<uint8_t> bmp = {'B', 'M'};
  const uint32_t pixels_at = 54, size = 54 + 8;  // 1 wide, 2 high, 24-bit rows padded to 4 bytes
  append_raw(bmp, size);
  append_raw(bmp, uint32_t(0));
  append_raw(bmp, pixels_at);
  append_raw(bmp, uint32_t(40));
  append_raw(bmp, int32_t(1));
  append_raw(bmp, int32_t(2));
  append_raw(bmp, uint16_t(1));
  append_raw(bmp, uint16_t(24));
  for (int i = 0; i < 6; ++i) append_raw(bmp, uint32_t(0));
  for (uint8_t c : {uint8_t(255), uint8_t(0), uint8_t(0), uint8_t(0)}) bmp.push_back(c);  // bottom row: blue (BGR)
  for (uint8_t c : {uint8_t(0), uint8_t(0), uint8_t(255), uint8_t(0)}) bmp.push_back(c);  // top row: red
  write_bytes(dir.file("tex.bmp"), bmp);
  write_text(dir.file("tri.mtl"), "newmtl paint\nKd 1 1 1\nmap_Kd tex.bmp\n");
  write_text(dir.file("tri.obj"),
             "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
             "usemtl paint\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/3\nf 2/2 3/3 4/1\n");
  const Mesh m = load_mesh(dir.file("tri.obj"));
  CHECK(m.triangle_count() == 4);
  REQUIRE(m.textures.size() == 1);
  CHECK(m.textures[0].width == 1);
  CHECK(m.textures[0].height == 2);
  // Row 0 is the top row (red), as pfill::Texture says.
  CHECK(m.textures[0].rgba == std::vector<uint8_t>{255, 0, 0, 255, 0, 0, 255, 255});
  REQUIRE(m.has_uvs());
  // OBJ's v = 0 is the bottom; flipped so that v = 0 is the top.
  CHECK(m.corner_uvs[0][1] == doctest::Approx(1.0));
  CHECK(m.corner_uvs[1][1] == doctest::Approx(0.0));
  REQUIRE(m.materials.size() == 1);
  CHECK(m.materials[0].texture == 0);
}

TEST_CASE("SMF: vertices, polygons, comments and per-vertex colours") {
  TempDir dir("smf");
  SUBCASE("written from a torus, with colours in [0, 1]") {
    const Mesh torus = make_torus(1.0, 0.4, 24, 12);
    std::vector<Rgba> colours;
    for (size_t v = 0; v < torus.vertex_count(); ++v)
      colours.push_back({static_cast<float>(v % 7) / 7.0f, 0.25f, 1.0f, 1.0f});
    const std::string path = dir.file("torus.smf");
    write_smf(torus, path, colours);
    const Mesh m = load_mesh(path);
    CHECK(m.vertex_count() == torus.vertex_count());
    CHECK(m.triangle_count() == torus.triangle_count());
    CHECK(signed_volume(m) == doctest::Approx(signed_volume(torus)).epsilon(1e-12));
    REQUIRE(m.has_colours());
    for (size_t t = 0; t < torus.triangle_count(); ++t)
      for (int k = 0; k < 3; ++k) {
        const Rgba& c = colours[torus.triangles[t][k]];
        CHECK(m.corner_colours[3 * t + k][0] == doctest::Approx(c[0]).epsilon(1e-6));
        CHECK(m.corner_colours[3 * t + k][1] == doctest::Approx(0.25));
      }
  }
  SUBCASE("a quad becomes a fan, 0..255 colours are detected, unknown commands ignored") {
    const std::string path = dir.file("quad.smf");
    write_text(path,
               "# a tetrahedron with one quad split off\nbegin\n\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
               "bind c vertex\nc 255 0 0\nc 0 255 0\nc 0 0 255\nc 255 255 255\n"
               "n 0 0 1   # normals are ignored\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\nend\n");
    const Mesh m = load_smf(path);
    CHECK(m.triangle_count() == 4);
    CHECK(signed_volume(m) == doctest::Approx(1.0 / 6.0));
    REQUIRE(m.has_colours());
    CHECK(m.corner_colours[1] == Rgba{0, 0, 1, 1});  // corner 1 of "f 1 3 2": vertex 3
    CHECK(m.corner_colours[2] == Rgba{0, 1, 0, 1});

    const std::string pentagon = dir.file("pentagon.smf");
    write_text(pentagon, "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\nf 1 2 3 4 5\n");
    CHECK(load_smf(pentagon).triangle_count() == 3);
  }
}

TEST_CASE("SMF: a malformed line is an error naming the file and the line") {
  TempDir dir("smfbad");
  const std::string path = dir.file("bad.smf");
  write_text(path, "v 0 0 0\nv 1 0 0\n# comment\nv 0 1 zero\nf 1 2 3\n");
  CHECK_THROWS_WITH_AS(load_mesh(path), doctest::Contains((path + ":4: malformed number 'zero'").c_str()), Error);
  write_text(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n");
  CHECK_THROWS_WITH_AS(load_mesh(path), doctest::Contains((path + ":5: vertex index 4 out of range").c_str()), Error);
  write_text(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n");
  CHECK_THROWS_WITH_AS(load_mesh(path), doctest::Contains((path + ":4: face needs at least 3").c_str()), Error);
}

TEST_CASE("shared meshes: spot.glb welds closed, spot_textured.glb has a texture, the bunny loads") {
  const std::string folder = PFILL_SHARED_MESHES;
  if (!std::filesystem::exists(folder + "/spot.glb")) {
    PFILL_SKIP(folder << " is not present");
  }
  const Mesh spot = load_mesh(folder + "/spot.glb");
  CHECK(spot.triangle_count() == 5856);
  CHECK(is_closed(spot));
  CHECK(signed_volume(spot) > 0);

  const Mesh textured = load_mesh(folder + "/spot_textured.glb");
  CHECK(textured.triangle_count() == 5856);
  CHECK(is_closed(textured));
  REQUIRE(textured.textures.size() >= 1);
  CHECK(textured.textures[0].width > 0);
  CHECK(textured.textures[0].rgba.size() ==
        static_cast<size_t>(textured.textures[0].width) * textured.textures[0].height * 4);
  CHECK(textured.has_uvs());
  REQUIRE(!textured.materials.empty());
  CHECK(textured.materials[0].texture == 0);

  const Mesh bunny = load_mesh(folder + "/stanford-bunny.obj");
  CHECK(bunny.triangle_count() == 69451);
  CHECK_FALSE(is_closed(bunny));  // the scan's open bottom
}

TEST_CASE("weld tolerance joins vertices that differ by less than the fraction of the diagonal") {
  TempDir dir("weld");
  const std::string path = dir.file("gap.smf");
  // Two triangles sharing an edge whose copies differ by 1e-9.
  write_text(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1.000000001 0 0\nv 0 1.000000001 0\nv 1 1 0\nf 1 2 3\nf 4 6 5\n");
  CHECK(load_mesh(path).vertex_count() == 6);
  LoadOptions loose;
  loose.weld_tolerance = 1e-6;
  CHECK(load_mesh(path, loose).vertex_count() == 4);
}

// Colour transfer: the mode option, sRGB and the depth map, corner colours
// against their analytic interpolation, texture sampling with every wrap mode,
// SMF and OBJ files end to end, fallbacks and errors, Spot's texture.
#include <doctest/doctest.h>

#include "skip.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "mesh_writers.hpp"
#include "pfill/boundary.hpp"
#include "pfill/colour.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/render.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

// The reference sRGB encoding, written out here (IEC 61966-2-1).
double reference_encode(double linear) {
  linear = std::clamp(linear, 0.0, 1.0);
  return linear <= 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}
double reference_decode(double encoded) {
  return encoded <= 0.04045 ? encoded / 12.92 : std::pow((encoded + 0.055) / 1.055, 2.4);
}
Rgb8 reference_rgb8(const Vec3& linear) {
  Rgb8 c;
  for (int k = 0; k < 3; ++k) c[k] = static_cast<uint8_t>(std::lround(255 * reference_encode(linear[k])));
  return c;
}

// Largest per-channel difference.
int colour_difference(const Rgb8& a, const Rgb8& b) {
  int d = 0;
  for (int k = 0; k < 3; ++k) d = std::max(d, std::abs(int(a[k]) - int(b[k])));
  return d;
}

// Linear colour as a function of position on the cube [-1, 1]^3: linear in
// position, so barycentric interpolation (in linear light) reproduces it
// exactly at every surface point.
Vec3 linear_colour_at(const Vec3& p) { return (p + Vec3(1, 1, 1)) * 0.5; }

// sRGB-encoded corner colours of that function.
void paint_corners(Mesh& mesh) {
  mesh.corner_colours.clear();
  for (const Triangle& t : mesh.triangles)
    for (uint32_t v : t) {
      const Vec3 c = linear_colour_at(mesh.positions[v]);
      mesh.corner_colours.push_back({static_cast<float>(reference_encode(c.x)),
                                     static_cast<float>(reference_encode(c.y)),
                                     static_cast<float>(reference_encode(c.z)), 1.0f});
    }
}

// The closest point on the surface of the cube [-1, 1]^3 to an inside point.
Vec3 cube_closest(Vec3 p) {
  int axis = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(p[k]) > std::fabs(p[axis])) axis = k;
  p[axis] = p[axis] < 0 ? -1 : 1;
  return p;
}

std::vector<Vec3> random_points_in_cube(size_t n, double extent, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-extent, extent);
  std::vector<Vec3> points(n);
  for (Vec3& p : points) p = {u(rng), u(rng), u(rng)};
  return points;
}

// A 2x2 texture, row 0 at the top: A B / C D.
const Rgb8 kA{255, 0, 0}, kB{0, 255, 0}, kC{0, 0, 255}, kD{255, 255, 0};
Texture four_texels(WrapMode wrap_s = WrapMode::Repeat, WrapMode wrap_t = WrapMode::Repeat) {
  Texture t;
  t.width = 2;
  t.height = 2;
  t.rgba.reserve(16);
  for (const Rgb8& c : {kA, kB, kC, kD}) {
    for (uint8_t channel : c) t.rgba.push_back(channel);
    t.rgba.push_back(255);
  }
  t.wrap_s = wrap_s;
  t.wrap_t = wrap_t;
  t.name = "four texels";
  return t;
}

// make_cube with `texture` as the base colour texture of its one material.
Mesh textured_cube(const Texture& texture, Rgba factor = {1, 1, 1, 1}) {
  Mesh cube = make_cube(1.0, 1);
  cube.textures = {texture};
  Material m;
  m.texture = 0;
  m.base_colour_factor = factor;
  cube.materials = {m};
  return cube;
}

// A point just inside the +z face whose closest point has face UV (s, t);
// make_cube's +z face has UV = ((x + 1) / 2, (y + 1) / 2).
Vec3 below_top_face(double s, double t) { return {2 * s - 1, 2 * t - 1, 0.95}; }

Rgb8 transfer_one(const Boundary& boundary, const Vec3& p) {
  return transfer_colours(boundary, {p}, {}).colours.at(0);
}

}  // namespace

TEST_CASE("colour option: surface, depth, none, #RRGGBB and bad text") {
  CHECK(parse_colour_option("surface").mode == ColourMode::Surface);
  CHECK(parse_colour_option("Depth").mode == ColourMode::Depth);
  CHECK(parse_colour_option("none").mode == ColourMode::None);
  const ColourOptions orange = parse_colour_option("#ff8800");
  CHECK(orange.mode == ColourMode::Constant);
  CHECK(orange.constant == Rgb8{255, 136, 0});
  CHECK(parse_colour_option("#0A0b0C").constant == Rgb8{10, 11, 12});
  for (const char* bad : {"", "blue", "#12345", "#1234567", "#12345g", "ff8800", "surfaces"}) {
    CAPTURE(bad);
    try {
      parse_colour_option(bad);
      FAIL("no error for a bad colour option");
    } catch (const Error& e) {
      const std::string message = e.what();
      CHECK(message.find("#RRGGBB") != std::string::npos);
    }
  }
  CHECK(colour_mode_name(ColourMode::Depth) == "depth");
}

TEST_CASE("default mode: surface for meshes with colour, none otherwise") {
  Mesh cube = make_cube(1.0, 1);
  CHECK_FALSE(has_surface_colour(cube));
  CHECK(default_colour_mode(cube) == ColourMode::None);
  cube.materials = {Material{}};  // a white material without texture is no colour
  CHECK(default_colour_mode(cube) == ColourMode::None);
  cube.materials[0].base_colour_factor = {1, 0, 0, 1};
  CHECK(default_colour_mode(cube) == ColourMode::Surface);
  CHECK(default_colour_mode(textured_cube(four_texels())) == ColourMode::Surface);
  Mesh painted = make_cube(1.0, 1);
  paint_corners(painted);
  CHECK(default_colour_mode(painted) == ColourMode::Surface);
}

TEST_CASE("sRGB transfer functions and 8-bit encoding") {
  for (int i = 0; i <= 100; ++i) {
    const double x = i / 100.0;
    CHECK(linear_to_srgb(static_cast<float>(x)) == doctest::Approx(reference_encode(x)).epsilon(1e-5));
    CHECK(srgb_to_linear(static_cast<float>(x)) == doctest::Approx(reference_decode(x)).epsilon(1e-5));
    CHECK(srgb_to_linear(linear_to_srgb(static_cast<float>(x))) == doctest::Approx(x).epsilon(1e-4));
  }
  CHECK(encode_srgb8({0.5f, 0.0f, 1.0f, 1.0f}) == Rgb8{188, 0, 255});
  CHECK(encode_srgb8({-1.0f, 2.0f, 0.21586f, 1.0f}) == Rgb8{0, 255, 128});
}

TEST_CASE("depth colour map: viridis ends, lightness grows monotonically") {
  CHECK(depth_colour(0.0) == Rgb8{68, 1, 84});
  CHECK(depth_colour(1.0) == Rgb8{253, 231, 37});
  CHECK(depth_colour(-3.0) == depth_colour(0.0));
  CHECK(depth_colour(7.0) == depth_colour(1.0));
  auto luminance = [](const Rgb8& c) {
    return 0.2126 * reference_decode(c[0] / 255.0) + 0.7152 * reference_decode(c[1] / 255.0) +
           0.0722 * reference_decode(c[2] / 255.0);
  };
  double previous = -1;
  for (int i = 0; i <= 200; ++i) {
    const double l = luminance(depth_colour(i / 200.0));
    CHECK(l >= previous - 1e-3);  // 8-bit rounding only
    previous = l;
  }
  CHECK(luminance(depth_colour(1.0)) > 10 * luminance(depth_colour(0.0)));
}

TEST_CASE("corner colours: particles take the linear-light interpolation at their closest points") {
  Mesh cube = make_cube(1.0, 3);
  paint_corners(cube);
  const Boundary boundary(cube);
  const std::vector<Vec3> points = random_points_in_cube(2000, 0.98, 7);
  const ColourTransfer result = transfer_colours(boundary, points, {ColourMode::Surface, {}});
  CHECK(result.applied == ColourMode::Surface);
  CHECK(result.note.empty());
  REQUIRE(result.colours.size() == points.size());
  int worst = 0;
  for (size_t i = 0; i < points.size(); ++i)
    worst = std::max(worst, colour_difference(result.colours[i], reference_rgb8(linear_colour_at(cube_closest(points[i])))));
  CHECK(worst <= 1);
  // Interpolating the encoded values instead would be off by far more: the
  // test tells the two apart.
  const Vec3 mid_edge_point{0.0, 0.0, 0.97};  // closest point (0, 0, 1): linear (0.5, 0.5, 1)
  CHECK(transfer_one(boundary, mid_edge_point) == Rgb8{188, 188, 255});
}

TEST_CASE("texture: bilinear, v = 0 at the top, every wrap mode on both axes") {
  const Texture texture = four_texels();
  // Texel centres give the texels; row 0 (t < 0.5) is the top row.
  CHECK(encode_srgb8(sample_texture(texture, 0.25, 0.25)) == kA);
  CHECK(encode_srgb8(sample_texture(texture, 0.75, 0.25)) == kB);
  CHECK(encode_srgb8(sample_texture(texture, 0.25, 0.75)) == kC);
  CHECK(encode_srgb8(sample_texture(texture, 0.75, 0.75)) == kD);
  // Half way between A and B, filtered in linear light: (0.5, 0.5, 0).
  CHECK(encode_srgb8(sample_texture(texture, 0.5, 0.25)) == Rgb8{188, 188, 0});
  // Centre: the mean of the four in linear light.
  const Rgba centre = sample_texture(texture, 0.5, 0.5);
  CHECK(centre[0] == doctest::Approx(0.5));
  CHECK(centre[1] == doctest::Approx(0.5));
  CHECK(centre[2] == doctest::Approx(0.25));

  // Texel index that each wrap mode gives for the texel centres beyond [0, 1]
  // of a 2-texel axis (coordinate -> index -2, -1, 2, 3).
  struct Case { double coordinate; int repeat, clamp, mirror; };
  const Case cases[] = {{-0.75, 0, 0, 1}, {-0.25, 1, 0, 0}, {1.25, 0, 1, 1}, {1.75, 1, 1, 0}, {0.25, 0, 0, 0}};
  const WrapMode modes[] = {WrapMode::Repeat, WrapMode::ClampToEdge, WrapMode::MirroredRepeat};
  for (int m = 0; m < 3; ++m)
    for (const Case& c : cases) {
      CAPTURE(m);
      CAPTURE(c.coordinate);
      const int index = m == 0 ? c.repeat : (m == 1 ? c.clamp : c.mirror);
      // s axis (t inside the top row), then t axis (s inside the left column).
      CHECK(encode_srgb8(sample_texture(four_texels(modes[m], WrapMode::Repeat), c.coordinate, 0.25)) ==
            (index == 0 ? kA : kB));
      CHECK(encode_srgb8(sample_texture(four_texels(WrapMode::Repeat, modes[m]), 0.25, c.coordinate)) ==
            (index == 0 ? kA : kC));
    }
  // Far-out and non-finite coordinates stay in range.
  CHECK(encode_srgb8(sample_texture(four_texels(WrapMode::ClampToEdge, WrapMode::ClampToEdge), 1e15, -1e15)) == kB);
  CHECK(encode_srgb8(sample_texture(four_texels(), 1e12 + 0.25, 0.25)) == kA);
  sample_texture(four_texels(), std::nan(""), HUGE_VAL);

  Texture broken = four_texels();
  broken.rgba.pop_back();
  CHECK_THROWS_AS(sample_texture(broken, 0.5, 0.5), Error);
}

TEST_CASE("texture on a cube: particles take the texel at their closest point's UV, wrap modes included") {
  SUBCASE("UVs 0..1 on every face") {
    const Boundary boundary(textured_cube(four_texels()));
    CHECK(transfer_one(boundary, below_top_face(0.25, 0.25)) == kA);
    CHECK(transfer_one(boundary, below_top_face(0.75, 0.25)) == kB);
    CHECK(transfer_one(boundary, below_top_face(0.25, 0.75)) == kC);
    CHECK(transfer_one(boundary, below_top_face(0.75, 0.75)) == kD);
    CHECK(transfer_one(boundary, below_top_face(0.5, 0.25)) == Rgb8{188, 188, 0});
  }
  SUBCASE("UVs running from -1 to 2") {
    // uv' = 3 uv - 1, so face UV (s + 1) / 3 lands on s.
    const WrapMode modes[] = {WrapMode::Repeat, WrapMode::ClampToEdge, WrapMode::MirroredRepeat};
    const double coordinate[] = {-0.75, -0.25, 1.25, 1.75};
    const int expected[3][4] = {{0, 1, 0, 1}, {0, 0, 1, 1}, {1, 0, 1, 0}};
    for (int m = 0; m < 3; ++m) {
      Mesh cube = textured_cube(four_texels(modes[m], modes[m]));
      for (Uv& uv : cube.corner_uvs) uv = {3 * uv[0] - 1, 3 * uv[1] - 1};
      const Boundary boundary(cube);
      const double top_row = (0.25 + 1) / 3;
      for (int i = 0; i < 4; ++i) {
        CAPTURE(m);
        CAPTURE(coordinate[i]);
        const double face = (coordinate[i] + 1) / 3;
        CHECK(transfer_one(boundary, below_top_face(face, top_row)) == (expected[m][i] == 0 ? kA : kB));
        CHECK(transfer_one(boundary, below_top_face(top_row, face)) == (expected[m][i] == 0 ? kA : kC));
      }
    }
  }
}

TEST_CASE("corner colours, texture and material factor multiply") {
  Mesh cube = textured_cube(four_texels(), {0.5f, 1.0f, 0.25f, 1.0f});
  cube.corner_colours.assign(3 * cube.triangle_count(), {0.5f, 1.0f, 1.0f, 1.0f});  // sRGB 0.5 red
  const Boundary boundary(cube);
  const double grey = reference_decode(0.5);
  // Texel D (255, 255, 0) x factor x corner colour.
  CHECK(colour_difference(transfer_one(boundary, below_top_face(0.75, 0.75)),
                          reference_rgb8({1.0 * 0.5 * grey, 1.0 * 1.0, 0.0})) <= 1);
  // Texel C (0, 0, 255).
  CHECK(colour_difference(transfer_one(boundary, below_top_face(0.25, 0.75)), reference_rgb8({0, 0, 0.25})) <= 1);
}

TEST_CASE("a material without texture colours by its factor and triangles pick their own material") {
  Mesh cube = make_cube(1.0, 1);
  Material red, blue;
  red.base_colour_factor = {1, 0, 0, 1};
  blue.base_colour_factor = {0, 0, 0.5f, 1};
  cube.materials = {red, blue};
  cube.triangle_materials.assign(cube.triangle_count(), 0);
  const Boundary probe(cube);
  const uint32_t top_triangle = probe.closest(below_top_face(0.75, 0.25)).triangle;
  cube.triangle_materials[top_triangle] = 1;
  const Boundary boundary(cube);
  CHECK(transfer_one(boundary, below_top_face(0.75, 0.25)) == reference_rgb8({0, 0, 0.5}));
  CHECK(transfer_one(boundary, Vec3(0.95, 0.1, 0.2)) == Rgb8{255, 0, 0});
}

TEST_CASE("SMF colours are read and transferred") {
  Mesh cube = make_cube(1.0, 2);
  std::vector<Rgba> vertex_colours;
  for (const Vec3& p : cube.positions) {
    const Vec3 c = linear_colour_at(p);
    vertex_colours.push_back({static_cast<float>(reference_encode(c.x)), static_cast<float>(reference_encode(c.y)),
                              static_cast<float>(reference_encode(c.z)), 1.0f});
  }
  TempDir dir("colour_smf");
  const std::string path = dir.file("painted.smf");
  write_smf(cube, path, vertex_colours);
  const Mesh loaded = load_mesh(path);
  REQUIRE(loaded.has_colours());
  CHECK(default_colour_mode(loaded) == ColourMode::Surface);
  const Boundary boundary(loaded);
  const std::vector<Vec3> points = random_points_in_cube(500, 0.97, 11);
  const ColourTransfer result = transfer_colours(boundary, points, {});
  REQUIRE(result.colours.size() == points.size());
  int worst = 0;
  for (size_t i = 0; i < points.size(); ++i)
    worst = std::max(worst, colour_difference(result.colours[i], reference_rgb8(linear_colour_at(cube_closest(points[i])))));
  CHECK(worst <= 1);
}

TEST_CASE("OBJ with map_Kd: assimp's UVs come out with v = 0 at the top, as glTF's") {
  // The cube written as OBJ with vt = (s, 1 - t) (OBJ's v = 0 is the bottom)
  // and the four-texel texture as PNG: it must colour like the in-memory cube.
  const Mesh cube = make_cube(1.0, 1);
  TempDir dir("colour_obj");
  Image image;
  image.width = 2;
  image.height = 2;
  for (const Rgb8& c : {kA, kB, kC, kD})
    for (uint8_t channel : c) image.rgb.push_back(channel);
  write_png(image, dir.file("tex.png"));
  write_text(dir.file("cube.mtl"), "newmtl paint\nKd 1 1 1\nmap_Kd tex.png\n");
  std::string obj = "mtllib cube.mtl\nusemtl paint\n";
  for (const Vec3& p : cube.positions) obj += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
  for (const Uv& uv : cube.corner_uvs) obj += "vt " + num(uv[0]) + " " + num(1.0 - uv[1]) + "\n";
  for (size_t t = 0; t < cube.triangle_count(); ++t) {
    obj += "f";
    for (int k = 0; k < 3; ++k)
      obj += " " + std::to_string(cube.triangles[t][k] + 1) + "/" + std::to_string(3 * t + k + 1);
    obj += "\n";
  }
  write_text(dir.file("cube.obj"), obj);
  const Mesh loaded = load_mesh(dir.file("cube.obj"));
  REQUIRE(loaded.textures.size() == 1);
  const Boundary boundary(loaded);
  CHECK(transfer_one(boundary, below_top_face(0.25, 0.25)) == kA);
  CHECK(transfer_one(boundary, below_top_face(0.75, 0.25)) == kB);
  CHECK(transfer_one(boundary, below_top_face(0.25, 0.75)) == kC);
  CHECK(transfer_one(boundary, below_top_face(0.75, 0.75)) == kD);
  CHECK(transfer_one(boundary, Vec3(-0.5, 0.95, -0.5)) ==
        transfer_one(Boundary(textured_cube(four_texels())), Vec3(-0.5, 0.95, -0.5)));
}

TEST_CASE("bad input: texture without UVs, a texture that cannot be decoded") {
  Mesh cube = textured_cube(four_texels());
  cube.corner_uvs.clear();
  cube.source = "uvless.glb";
  const Boundary boundary(cube);
  try {
    transfer_colours(boundary, {Vec3(0, 0, 0.5)}, {});
    FAIL("no error for a texture without UVs");
  } catch (const Error& e) {
    const std::string message = e.what();
    CHECK(message.find("uvless.glb") != std::string::npos);
    CHECK(message.find("UV") != std::string::npos);
  }
  // Depth and constant colours do not need UVs.
  CHECK(transfer_colours(boundary, {Vec3(0, 0, 0.5)}, {ColourMode::Depth, {}}).colours.size() == 1);

  TempDir dir("colour_badtex");
  write_text(dir.file("tex.png"), "this is not a PNG");
  write_text(dir.file("tri.mtl"), "newmtl paint\nmap_Kd tex.png\n");
  write_text(dir.file("tri.obj"),
             "mtllib tri.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
             "usemtl paint\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/3\nf 2/2 3/3 4/1\n");
  try {
    load_mesh(dir.file("tri.obj"));
    FAIL("no error for a texture that cannot be decoded");
  } catch (const Error& e) {
    const std::string message = e.what();
    CHECK(message.find("tri.obj") != std::string::npos);
    CHECK(message.find("tex.png") != std::string::npos);
  }
}

TEST_CASE("depth: colours grow lighter from the surface inward (and fallback, constant, none)") {
  const Boundary boundary(make_cube(1.0, 2));
  std::vector<Vec3> line;
  for (int i = 0; i <= 40; ++i) line.push_back({0.999 - i * 0.0249, 0.1, -0.05});  // from the +x face inward
  const ColourTransfer depth = transfer_colours(boundary, line, {ColourMode::Depth, {}});
  REQUIRE(depth.colours.size() == line.size());
  CHECK(depth.applied == ColourMode::Depth);
  CHECK(colour_difference(depth.colours.front(), depth_colour(0.0)) <= 2);
  CHECK(depth.colours.back() == depth_colour(1.0));
  for (size_t i = 1; i < line.size(); ++i) {
    // The +x face is the closest up to depth 0.9, the +y face beyond.
    const double fraction = std::min(1 - line[i].x, 0.9) / 0.9;
    CHECK(colour_difference(depth.colours[i], depth_colour(fraction)) <= 1);
  }

  // Surface on an uncoloured mesh: depth, and a note that says so.
  const ColourTransfer fallback = transfer_colours(boundary, line, {ColourMode::Surface, {}});
  CHECK(fallback.applied == ColourMode::Depth);
  CHECK(fallback.note.find("cube") != std::string::npos);
  CHECK(fallback.colours == depth.colours);

  const ColourTransfer constant = transfer_colours(boundary, line, {ColourMode::Constant, {1, 2, 3}});
  CHECK(constant.colours == std::vector<Rgb8>(line.size(), Rgb8{1, 2, 3}));
  CHECK(transfer_colours(boundary, line, {ColourMode::None, {}}).colours.empty());
  CHECK(transfer_colours(boundary, {}, {ColourMode::Depth, {}}).colours.empty());

  ParticleSet particles;
  particles.positions = line;
  particles.radii.assign(line.size(), 0.01);
  CHECK(colour_particles(boundary, particles, {ColourMode::Constant, {9, 9, 9}}).empty());
  CHECK(particles.colours.size() == line.size());
  colour_particles(boundary, particles, {ColourMode::None, {}});
  CHECK_FALSE(particles.has_colours());
  CHECK_THROWS_AS(transfer_colours(boundary, {Vec3(std::nan(""), 0, 0)}, {}), Error);
}

TEST_CASE("shared mesh: points inside Spot take the colours of her texture") {
  const std::string path = std::string(PFILL_SHARED_MESHES) + "/spot_textured.glb";
  if (!std::filesystem::exists(path)) {
    PFILL_SKIP(path << " not found");
  }
  const Mesh spot = load_mesh(path);
  const Boundary boundary(spot);
  // Points just inside the surface: on a coarse grid, kept where the depth is
  // small, so each sees the texture right above it.
  const Box3 box = spot.bounds();
  const double step = box.diagonal() / 60;
  std::vector<Vec3> grid;
  for (double z = box.lo.z; z <= box.hi.z; z += step)
    for (double y = box.lo.y; y <= box.hi.y; y += step)
      for (double x = box.lo.x; x <= box.hi.x; x += step) grid.push_back({x, y, z});
  const std::vector<double> sd = boundary.signed_distance(grid);
  std::vector<Vec3> points;
  for (size_t i = 0; i < grid.size(); ++i)
    if (sd[i] < 0 && sd[i] > -1.5 * step) points.push_back(grid[i]);
  REQUIRE(points.size() > 500);
  const ColourTransfer result = transfer_colours(boundary, points, {});
  CHECK(result.applied == ColourMode::Surface);
  REQUIRE(result.colours.size() == points.size());
  std::set<Rgb8> distinct(result.colours.begin(), result.colours.end());
  CHECK(distinct.size() > 50);
  // The texture is mostly cream (about 253, 236, 228) with dark grey patches
  // (about 64, 64, 64): both must show, cream the most.
  size_t cream = 0, dark = 0;
  for (const Rgb8& c : result.colours) {
    cream += c[0] > 230 && c[1] > 205 && c[2] > 195 && c[0] >= c[2];
    dark += c[0] < 110 && c[1] < 110 && c[2] < 110;
  }
  CHECK(cream > points.size() / 2);
  CHECK(dark > points.size() / 50);
  // Each colour is the texture at the closest point's UV: bilinear filtering
  // mixes the texels around it, so every channel lies between the least and
  // the greatest of the 3x3 texels about the nearest one.
  const std::vector<ClosestPoint> closest = boundary.closest(points);
  const Texture& texture = spot.textures.at(0);
  for (size_t i = 0; i < points.size(); i += 37) {
    const ClosestPoint& c = closest[i];
    const Uv* uv = &spot.corner_uvs[3 * c.triangle];
    const double s = (1 - c.u - c.v) * uv[0][0] + c.u * uv[1][0] + c.v * uv[2][0];
    const double t = (1 - c.u - c.v) * uv[0][1] + c.u * uv[1][1] + c.v * uv[2][1];
    const int x = static_cast<int>(std::floor(s * texture.width));
    const int y = static_cast<int>(std::floor(t * texture.height));
    for (int k = 0; k < 3; ++k) {
      int lo = 255, hi = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int xx = std::clamp(x + dx, 0, texture.width - 1), yy = std::clamp(y + dy, 0, texture.height - 1);
          const int value = texture.rgba[4 * (static_cast<size_t>(yy) * texture.width + xx) + k];
          lo = std::min(lo, value);
          hi = std::max(hi, value);
        }
      CAPTURE(i);
      CHECK(int(result.colours[i][k]) >= lo - 1);
      CHECK(int(result.colours[i][k]) <= hi + 1);
    }
  }
}

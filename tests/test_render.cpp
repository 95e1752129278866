// The preview renderer: what lands on which pixel, cuts, the shell, PNG
// output (decoded with stb_image) and its errors.
#include <doctest/doctest.h>

#include <cmath>

#include "particle_fixtures.hpp"
#include "pfill/error.hpp"
#include "pfill/render.hpp"
#include "pfill/shapes.hpp"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

using namespace pfill;
namespace fs = std::filesystem;

namespace {

RenderOptions small_options(int w = 96, int h = 72) {
  RenderOptions options;
  options.width = w;
  options.height = h;
  options.ambient_occlusion_rays = 2;
  return options;
}

// Pixels that differ from their row's background.
size_t foreground_pixels(const Image& image, const RenderOptions& options) {
  size_t count = 0;
  for (int y = 0; y < image.height; ++y) {
    const Rgb8 background = background_at(options, y, image.height);
    for (int x = 0; x < image.width; ++x) count += image.at(x, y) != background;
  }
  return count;
}

ParticleSet one_sphere(const Vec3& centre, double radius) {
  ParticleSet set;
  set.positions.push_back(centre);
  set.radii.push_back(radius);
  return set;
}

}  // namespace

TEST_CASE("one sphere at the centre of the view lights the centre pixel, not the corners") {
  const RenderOptions options = small_options();
  const Image image = render(one_sphere(Vec3(0.3, -0.2, 0.1), 0.5), nullptr, options);
  REQUIRE(image.width == 96);
  REQUIRE(image.height == 72);
  REQUIRE(image.rgb.size() == 96u * 72u * 3u);
  const Rgb8 centre = image.at(48, 36);
  CHECK(centre != background_at(options, 36, 72));
  // Default colour is orange: red channel dominates blue on a lit sphere.
  CHECK(centre[0] > centre[2]);
  CHECK(image.at(0, 0) == background_at(options, 0, 72));
  CHECK(image.at(95, 0) == background_at(options, 0, 72));
  CHECK(image.at(0, 71) == background_at(options, 71, 72));
  CHECK(image.at(95, 71) == background_at(options, 71, 72));
  // Framed tightly: the sphere covers a good part of the picture.
  const size_t covered = foreground_pixels(image, options);
  CHECK(covered > 96 * 72 / 6);
  CHECK(covered < 96 * 72);
}

TEST_CASE("particle colours reach the picture") {
  ParticleSet set = one_sphere(Vec3(0, 0, 0), 1.0);
  set.colours.push_back({20, 40, 230});
  const Image image = render(set, nullptr, small_options());
  const Rgb8 centre = image.at(48, 36);
  CHECK(centre[2] > centre[0] + 40);
}

TEST_CASE("an empty scene is all background") {
  const RenderOptions options = small_options(40, 30);
  const Image image = render(ParticleSet{}, nullptr, options);
  CHECK(foreground_pixels(image, options) == 0);
  CHECK(image.at(0, 0) == options.background_top);
  CHECK(image.at(0, 29) == options.background_bottom);
}

TEST_CASE("a cut removes the spheres whose centres lie on its positive side") {
  // Two spheres side by side along x, seen from the front.
  ParticleSet set = one_sphere(Vec3(-1, 0, 0), 0.5);
  set.positions.push_back(Vec3(1, 0, 0));
  set.radii.push_back(0.5);
  RenderOptions options = small_options(120, 60);
  options.view = View::Front;
  options.camera = frame_camera(set.bounds(), View::Front, 2.0);  // one camera for all three
  const Image both = render(set, nullptr, options);
  options.cut = parse_cut("x");  // default: the centre, x = 0
  const Image left = render(set, nullptr, options);
  options.cut = parse_cut("x=-5");
  const Image none = render(set, nullptr, options);
  const size_t n_both = foreground_pixels(both, options), n_left = foreground_pixels(left, options);
  CHECK(n_both > 0);
  CHECK(std::abs(double(n_left) - 0.5 * double(n_both)) < 0.05 * double(n_both));
  CHECK(foreground_pixels(none, options) == 0);
  // The left sphere stays where it was, the right one is gone.
  CHECK(left.at(30, 30) == both.at(30, 30));
  CHECK(both.at(90, 30) != background_at(options, 30, 60));
  CHECK(left.at(90, 30) == background_at(options, 30, 60));
}

TEST_CASE("the shell is faint and translucent, and the cut clips it") {
  const Mesh shell = make_icosphere(1.0, 3);
  const ParticleSet inside = one_sphere(Vec3(0, 0, 0), 0.4);
  RenderOptions options = small_options(80, 80);
  options.view = View::Front;
  const Image with_shell = render(inside, &shell, options);
  const Image without = render(inside, nullptr, options);
  options.camera = frame_camera(scene_bounds(inside, &shell), View::Front, 1.0);
  const Image without_same_camera = render(inside, nullptr, options);
  // The shell tints the background inside its outline, but only faintly.
  const Rgb8 background = background_at(options, 40, 80);
  const Rgb8 through = with_shell.at(40 - 28, 40);  // inside the shell, beside the particle
  CHECK(through != background);
  for (int k = 0; k < 3; ++k) CHECK(std::abs(int(through[k]) - int(background[k])) < 60);
  // The particle is still visible through it.
  CHECK(with_shell.at(40, 40) != background);
  CHECK(with_shell.at(40, 40)[0] > with_shell.at(40, 40)[2]);
  CHECK(foreground_pixels(without, options) > 0);
  // Cutting at z = 0 keeps the sphere (centre on the plane) and the back half of the shell.
  options.cut = parse_cut("z=0");
  const Image cut = render(inside, &shell, options);
  CHECK(cut.at(40, 40) != background);
  CHECK(foreground_pixels(cut, options) > foreground_pixels(without_same_camera, options));
  // Beside the particle, the ray now crosses one shell layer instead of two: a fainter tint.
  options.cut.reset();
  const Image uncut = render(inside, &shell, options);
  auto tint = [&](const Image& image) {
    int sum = 0;
    for (int k = 0; k < 3; ++k) sum += std::abs(int(image.at(40 - 28, 40)[k]) - int(background[k]));
    return sum;
  };
  CHECK(tint(cut) > 0);
  CHECK(tint(cut) < tint(uncut));
  options.cut = parse_cut("z=0");
  options.cut = parse_cut("z=-2");  // everything cut away
  CHECK(foreground_pixels(render(inside, &shell, options), options) == 0);
}

TEST_CASE("views, cuts and sizes are parsed, and bad ones rejected") {
  CHECK(parse_view("front") == View::Front);
  CHECK(parse_view("iso") == View::Iso);
  CHECK(parse_view("three-quarter") == View::ThreeQuarter);
  CHECK_THROWS_AS(parse_view("back"), Error);
  CHECK(parse_cut("y").axis == 1);
  CHECK_FALSE(parse_cut("y").value.has_value());
  CHECK(*parse_cut("z=-0.25").value == -0.25);
  CHECK_THROWS_AS(parse_cut("w"), Error);
  CHECK_THROWS_AS(parse_cut("x=abc"), Error);
  CHECK_THROWS_AS(parse_cut("x="), Error);
  RenderOptions options = small_options(0, 10);
  CHECK_THROWS_AS(render(ParticleSet{}, nullptr, options), Error);
}

TEST_CASE("every view frames the whole scene, tightly") {
  ParticleSet set;  // spheres at the eight corners of a box
  for (int corner = 0; corner < 8; ++corner) {
    set.positions.emplace_back(corner & 1 ? 2.0 : -2.0, corner & 2 ? 1.0 : -1.0, corner & 4 ? 0.5 : -0.5);
    set.radii.push_back(0.3);
  }
  for (View view : {View::ThreeQuarter, View::Front, View::Side, View::Top, View::Iso}) {
    RenderOptions options = small_options(64, 48);
    options.view = view;
    const Image image = render(set, nullptr, options);
    int lo_x = 64, hi_x = -1, lo_y = 48, hi_y = -1;
    for (int y = 0; y < 48; ++y)
      for (int x = 0; x < 64; ++x)
        if (image.at(x, y) != background_at(options, y, 48)) {
          lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x);
          lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
        }
    CAPTURE(int(view));
    CHECK(lo_x > 0);  // nothing touches the border
    CHECK(lo_y > 0);
    CHECK(hi_x < 63);
    CHECK(hi_y < 47);
    // ... and fills much of it in one direction (oblique views frame the
    // box, whose empty corners reach further than the spheres).
    CHECK((hi_x - lo_x > 0.6 * 64 || hi_y - lo_y > 0.6 * 48));
  }
}

TEST_CASE("write_png decodes to the stated size, and an unwritable path gives a clear error and no file") {
  test::ScratchDir dir("png");
  RenderOptions options = small_options(50, 30);
  const Image image = render(one_sphere(Vec3(0, 0, 0), 1), nullptr, options);
  write_png(image, dir / "a.png");
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load((dir / "a.png").c_str(), &w, &h, &channels, 3);
  REQUIRE(pixels != nullptr);
  CHECK(w == 50);
  CHECK(h == 30);
  CHECK(std::equal(image.rgb.begin(), image.rgb.end(), pixels));
  stbi_image_free(pixels);

  const fs::path missing = dir.path() / "no" / "b.png";
  try {
    write_png(image, missing);
    FAIL("expected an error");
  } catch (const Error& e) {
    CHECK(std::string(e.what()).find(missing.string()) != std::string::npos);
  }
  CHECK_FALSE(fs::exists(missing));
  CHECK_THROWS_AS(write_png(image, "/proc/pfill_test.png"), Error);
  CHECK(dir.file_count() == 1);
}

// The wall field stored as a 3D image (EngineParams::field_image) against
// the default buffer: same system, same steps, same positions; and the
// image limits as clear errors. Skips when the device has no images.
#include <doctest/doctest.h>

#include "skip.hpp"

#include <cmath>

#include "engine_fixtures.hpp"
#include "pfill/device/device.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/error.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

bool has_images(Device& d) { return d.device().getInfo<CL_DEVICE_IMAGE_SUPPORT>() != CL_FALSE; }

EngineParams wall_params(double cutoff_sigma, bool image) {
  EngineParams p;
  p.radius = 0.5;
  p.cutoff_sigma = cutoff_sigma;
  p.restitution = 0.7;
  p.wall_restitution = 0.8;
  p.damping = 0.1;
  p.field_image = image;
  return p;
}

}  // namespace

TEST_CASE("engine: the field as a 3D image gives the buffer path's positions (sphere, 100 steps)") {
  Device& device = shared_device();
  if (!has_images(device)) {
    PFILL_SKIP("device '" << device.info().name << "' has no image support");
  }
  const double R = 4.0;
  const ScalarGrid field = sphere_grid(R, 0.125);
  for (double cutoff : {0.0, 2.5}) {
    const auto start =
        random_particles(300, 0.5, R, 0.9, 2.0, 3u, [R](const Vec3& x) { return sphere_distance(x, R); });
    std::vector<Particle> got[2];
    size_t flagged[2] = {0, 0};
    for (int image = 0; image < 2; ++image) {
      Engine engine(device, wall_params(cutoff, image == 1));
      engine.set_field(field);
      engine.add_particles(start);
      engine.run_steps(100);
      got[image] = engine.read_particles();
      flagged[image] = engine.flagged_particles().size();
      const auto h = engine.read_history();
      REQUIRE(h.size() == 100);
      CHECK(h.back().particles == start.size());
    }
    INFO("cutoff " << cutoff << ", n " << start.size());
    REQUIRE(got[0].size() == got[1].size());
    // Same corners, same trilinear formula in float: only the compiler's
    // rounding choices (fma contraction) may differ. Measured on PoCL: 0.
    double dx = 0, dv = 0;
    for (size_t i = 0; i < got[0].size(); ++i) {
      dx = std::max(dx, length(got[0][i].position - got[1][i].position));
      dv = std::max(dv, length(got[0][i].velocity - got[1][i].velocity));
    }
    MESSAGE("cutoff " << cutoff << ": image vs buffer after 100 steps, max |dx| " << dx << ", max |dv| " << dv);
    CHECK(dx < 1e-4);
    CHECK(dv < 1e-2);
    // No particle leaves: both keep every centre inside the sphere (by its radius, to the grid's accuracy).
    CHECK(flagged[1] == 0);
    double worst = -1e30;
    for (const Particle& p : got[1]) worst = std::max(worst, sphere_distance(p.position, R) + p.radius);
    CHECK(worst < 0.01);
  }
}

TEST_CASE("engine: the image field also runs without a field (domain only), and bad sizes are clear errors") {
  Device& device = shared_device();
  if (!has_images(device)) {
    PFILL_SKIP("device '" << device.info().name << "' has no image support");
  }
  EngineParams p = wall_params(0.0, true);
  p.domain.add({-3, -3, -3});
  p.domain.add({3, 3, 3});
  Engine engine(device, p);
  std::vector<Particle> two(2);
  two[0].position = {-0.45, 0, 0};
  two[1].position = {0.45, 0, 0};
  two[0].radius = two[1].radius = 0.5;
  engine.add_particles(two);
  engine.run_steps(10);
  const auto ps = engine.read_particles();
  CHECK(ps[0].position.x < -0.45);  // pushed apart, no wall in the way
  CHECK(ps[1].position.x > 0.45);

  const size_t max_width = device.device().getInfo<CL_DEVICE_IMAGE3D_MAX_WIDTH>();
  if (max_width < (1u << 20)) {
    ScalarGrid wide;
    wide.dims = {static_cast<int>(max_width) + 1, 2, 2};
    wide.spacing = 0.01;
    wide.values.assign(static_cast<size_t>(wide.dims[0]) * 4, -1.0f);
    Engine limited(device, wall_params(0.0, true));
    CHECK_THROWS_WITH_AS(limited.set_field(wide), doctest::Contains("3D image limit"), Error);
  }
}

// Fills of generated bad meshes (issue 21), a few hundred particles each:
// every one ends in a fill whose metrics are checked, with a warning that
// names what is wrong with the mesh, or in one clear error; none runs away.
// Also: the options that would make a fill endless or empty are refused.
#include <doctest/doctest.h>

#include <algorithm>
#include <string>

#include "bad_meshes.hpp"
#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/mesh_diagnostics.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

FillOptions small_fill(size_t count) {
  FillOptions o;
  o.count = count;
  o.seed = 3;
  o.colour = ColourOptions{ColourMode::None, {}};
  return o;
}

void check_fill(const FillResult& r, double min_packing) {
  INFO("particles " << r.particles.size() << " of ~" << r.expected << ", packing " << r.metrics.packing_fraction
                    << ", lost outside " << r.lost_outside << ", pass 1 steps " << r.passes.at(0).steps);
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_overlap <= 0.05 + 1e-9);
  CHECK(r.metrics.packing_fraction >= min_packing);
  CHECK(r.particles.size() * 10 >= r.expected * 7);
  // Births only where particles can stay: few leave, and pass 1 ends by
  // itself, not on its step budget.
  CHECK(r.lost_outside <= r.expected / 10);
  CHECK(r.stop_signal != "budget");
}

bool warns(const FillResult& r, const std::string& words) {
  return std::any_of(r.warnings.begin(), r.warnings.end(),
                     [&](const std::string& w) { return w.find(words) != std::string::npos; });
}

}  // namespace

TEST_CASE("overlapping parts fill as their union") {
  const FillResult r = fill(overlapping_cubes(), small_fill(300));
  check_fill(r, 0.50);
  CHECK(warns(r, "intersect"));
  // The union's volume (1.875), not the parts' sum (2), sizes the fill.
  CHECK(r.metrics.mesh_volume == doctest::Approx(1.875).epsilon(0.005));
  // Spheres fill the overlap too: some lie in both cubes.
  CHECK(std::any_of(r.particles.positions.begin(), r.particles.positions.end(), [](const Vec3& p) {
    return p.x > 0.6 && p.x < 0.9 && p.y > 0.6 && p.y < 0.9 && p.z > 0.6 && p.z < 0.9;
  }));
}

TEST_CASE("a self-intersecting surface fills in bounded time, with a warning") {
  const FillResult r = fill(self_intersecting_cubes(), small_fill(300));
  check_fill(r, 0.45);
  CHECK(warns(r, "intersects itself"));
}

TEST_CASE("far from the origin: the physics runs in local coordinates, the result comes back") {
  const Vec3 far{1e6, -3e6, 2e5};
  const FillResult r = fill(moved(make_icosphere(1.0, 3), far), small_fill(300));
  check_fill(r, 0.52);
  Box3 box;
  for (const Vec3& p : r.particles.positions) box.add(p);
  CHECK(length(box.centre() - far) < 0.2);
  CHECK(box.size().x < 2.0);
  for (const BirthSite& s : r.sites) CHECK(length(s.position - far) < 1.0);
}

TEST_CASE("tiny and huge meshes fill like a unit one") {
  const MeshDiagnostics unit = diagnose(make_icosphere(1.0, 3));
  const double unit_radius = fill_radius_for_count(unit.volume(), unit.surface_area, 250);
  for (double scale : {1e-6, 1e6}) {
    CAPTURE(scale);
    const FillResult r = fill(moved(make_icosphere(1.0, 3), {}, scale), small_fill(250));
    check_fill(r, 0.52);
    CHECK(r.radius == doctest::Approx(scale * unit_radius).epsilon(1e-6));
  }
}

TEST_CASE("inside-out and doubled-face meshes fill after a repair") {
  Mesh inverted = make_cube(1.0, 2);
  flip_orientation(inverted);
  const FillResult r = fill(inverted, small_fill(250));
  check_fill(r, 0.45);
  CHECK(warns(r, "inside-out"));
  Mesh doubled = make_cube(1.0, 2);
  const size_t n = doubled.triangle_count();
  for (size_t t = 0; t < n; ++t) doubled.triangles.push_back(doubled.triangles[t]);
  check_fill(fill(doubled, small_fill(250)), 0.45);
}

TEST_CASE("an open mesh: a checked fill with a warning, or one clear error") {
  try {
    const FillResult r = fill(make_open_cube(1.0, 2), small_fill(250));
    CHECK(r.metrics.contained_share == 1.0);
    CHECK(warns(r, "open"));
  } catch (const Error& e) {
    const std::string message = e.what();
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("options that would make a fill endless or empty are refused before it starts") {
  auto refused = [](FillOptions o, const std::string& words) {
    o.count = 200;
    try {
      fill(make_cube(), o);
      FAIL("accepted: " << words);
    } catch (const Error& e) {
      CHECK(std::string(e.what()).find(words) != std::string::npos);
    }
  };
  FillOptions o;
  o.birth_clearance = 0.1;
  refused(o, "birth_clearance must");
  o = {};
  o.patience = 0;
  refused(o, "patience must");
  o = {};
  o.hole_rounds = -1;
  refused(o, "hole_rounds must");
  o = {};
  o.site_depth = 2;
  refused(o, "site_depth must");
  o = {};
  o.time_step = 1e-9;
  refused(o, "time_step must");
  o = {};
  o.max_step = 1e-9;
  refused(o, "max_step must");
}

TEST_CASE("a radius too large for the mesh: the real depth, and the way out for -r") {
  FillOptions o;
  o.radius = 5;
  try {
    fill(make_icosphere(1.0, 3), o);
    FAIL("a radius of 5 fitted a unit ball");
  } catch (const Error& e) {
    const std::string message = e.what();
    CAPTURE(message);
    const size_t at = message.find("the deepest point is about ");
    REQUIRE(at != std::string::npos);
    const double depth = std::stod(message.substr(at + 27));
    CHECK(depth > 0.9);
    CHECK(depth < 1.01);
    CHECK(message.find("choose a radius below") != std::string::npos);
    CHECK(message.find("count") == std::string::npos);
  }
}

TEST_CASE("a stray vertex far from the rest: one line naming it, at once") {
  Mesh m = make_icosphere(1.0, 3);
  m.positions[7] = {1e9, 0, 0};
  try {
    fill(m, small_fill(300));
    FAIL("a mesh 1e9 across with a unit volume was filled");
  } catch (const Error& e) {
    const std::string message = e.what();
    CAPTURE(message);
    CHECK(message.find("the vertex at (1e+09, 0, 0) a stray?") != std::string::npos);
    CHECK(message.find("spacing") == std::string::npos);
  }
}

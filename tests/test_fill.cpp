// Whole fills of shapes generated in code, small enough for PoCL in CI:
// containment, overlaps and packing checked exactly; each stopping signal
// on a scenario that triggers it; reproducibility; bad input.
#include <doctest/doctest.h>

#include <filesystem>

#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

FillOptions small_fill(size_t count, uint64_t seed = 1) {
  FillOptions o;
  o.count = count;
  o.seed = seed;
  o.colour = ColourOptions{ColourMode::None, {}};
  return o;
}

void check_quality(const FillResult& r, double min_packing, double max_packing) {
  INFO("particles " << r.metrics.count << ", packing " << r.metrics.packing_fraction << ", max overlap "
                    << r.metrics.max_overlap << ", max penetration " << r.metrics.max_penetration);
  CHECK(r.metrics.count == r.particles.size());
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_penetration <= 0.01);
  CHECK(r.metrics.max_overlap <= 0.05 + 1e-9);
  CHECK(r.metrics.packing_fraction >= min_packing);
  CHECK(r.metrics.packing_fraction <= max_packing);
  CHECK(r.metrics.mean_coordination > 3.0);
  CHECK_FALSE(r.stop_signal.empty());
  REQUIRE(r.passes.size() == 4);
  CHECK(r.passes[0].name == "pass 1");
  CHECK(r.passes[3].name == "finish");
  // Lists rebuilt: on pass 1's first step at least (the engine starts
  // without lists), never on more steps than a pass has; the finish's
  // engine is not counted.
  CHECK(r.passes[0].list_rebuilds >= 1);
  for (size_t k = 0; k < 3; ++k) CHECK(r.passes[k].list_rebuilds <= static_cast<int64_t>(r.passes[k].steps));
  CHECK(r.passes[3].list_rebuilds == -1);
}

}  // namespace

TEST_CASE("fill a sphere: every sphere inside, overlaps under 5% r, dense") {
  const FillResult r = fill(make_icosphere(1.0, 4), small_fill(400));
  check_quality(r, 0.50, 0.70);
  CHECK(r.particles.size() > 300);
  // The report's schedule with two sites asked: a ball has one deep core,
  // no room for a second site.
  FillOptions two = small_fill(400);
  two.sites = 2;
  const FillResult r2 = fill(make_icosphere(1.0, 4), two);
  check_quality(r2, 0.50, 0.70);
  CHECK(r2.sites.size() == 1);
}

TEST_CASE("fill a cube") {
  const FillResult r = fill(make_cube(1.0, 2), small_fill(400));
  check_quality(r, 0.48, 0.70);
  // Its peak memory: the process's, so at least the field the fill held;
  // in the report too.
#if defined(__linux__) || defined(__APPLE__)
  CHECK(r.peak_memory >= r.field_bytes);
  CHECK(r.field_bytes > 0);
#endif
  CHECK(fill_report_json(r, "cube", 1, "cube.ply")["peak_memory_bytes"] == r.peak_memory);
  // Its time: the field, the set-up, the passes and the verify, each once, within the whole.
  CHECK(r.setup_seconds > 0);
  CHECK(r.verify_seconds > 0);
  double parts = r.field_seconds + r.setup_seconds + r.verify_seconds;
  for (const PassStats& p : r.passes) parts += p.seconds;
  CHECK(parts <= r.seconds + 1e-6);
  CHECK(parts > 0.8 * r.seconds);
  CHECK(fill_report_json(r, "cube", 1, "cube.ply")["setup_seconds"] == r.setup_seconds);
  CHECK(fill_report_json(r, "cube", 1, "cube.ply")["verify_seconds"] == r.verify_seconds);
}

TEST_CASE("fill a torus with the report's schedule: two sites spread round the ring") {
  FillOptions o = small_fill(300);
  o.sites = 2;
  const FillResult r = fill(make_torus(1.0, 0.45, 64, 32), o);
  check_quality(r, 0.45, 0.70);
  REQUIRE(r.sites.size() == 2);
  // Farthest-point sampling puts the second site across the ring.
  CHECK(length(r.sites[0].position - r.sites[1].position) > 1.5);
}

TEST_CASE("renumbering the particles along the cells every 64 steps: fills as good, tests still fire") {
  FillOptions o = small_fill(400);
  o.sort_every = 64;
  const FillResult r = fill(make_icosphere(1.0, 4), o);
  check_quality(r, 0.50, 0.70);
  // The report's kinetic-energy test removes the newest particle, which
  // the fill follows through the renumberings.
  FillOptions k = small_fill(200);
  k.sort_every = 64;
  k.stop = StopCriterion::KineticEnergy;
  k.birth_every = 40;
  k.ke = {3, 50, 2};
  k.patience = 100000;
  const FillResult rk = fill(make_icosphere(1.0, 3), k);
  CHECK(rk.stop_signal == "ke");
  CHECK(rk.ke_events == 2);
  CHECK(rk.metrics.contained_share == 1.0);
}

TEST_CASE("the same seed gives the same particles; another seed gives others") {
  const Mesh sphere = make_icosphere(1.0, 3);
  const FillResult a = fill(sphere, small_fill(150, 7));
  const FillResult b = fill(sphere, small_fill(150, 7));
  const FillResult c = fill(sphere, small_fill(150, 8));
  REQUIRE(a.particles.size() == b.particles.size());
  CHECK(a.particles.positions == b.particles.positions);
  CHECK(a.particles.radii == b.particles.radii);
  CHECK(a.particles.positions != c.particles.positions);
}

TEST_CASE("the kinetic-energy test ends pass 1 when told to and it fires") {
  FillOptions o = small_fill(200);
  o.stop = StopCriterion::KineticEnergy;
  o.birth_every = 40;           // quiet stretches between births, so rises can be seen
  o.ke = {3, 50, 2};            // a short run of rises is an instability
  o.patience = 100000;  // the fallback must not end it first
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  CHECK(r.stop_signal == "ke");
  CHECK(r.ke_events == 2);
  CHECK(r.metrics.contained_share == 1.0);
}

TEST_CASE("the collision-count test ends pass 1 when told to and it fires") {
  FillOptions o = small_fill(200);
  o.stop = StopCriterion::Collisions;
  o.collisions = {5, 20, 1};  // five steps of a steady count; one failed removal is overfull
  o.patience = 100000;
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  CHECK(r.stop_signal == "collisions");
  CHECK(r.metrics.contained_share == 1.0);
}

TEST_CASE("with the report's tests chosen but silent, blocked sites still end the fill") {
  FillOptions o = small_fill(150);
  o.stop = StopCriterion::KineticEnergy;
  o.ke = {1000000, 10, 1};  // can never fire
  o.patience = 500;
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  CHECK(r.stop_signal == "blocked");
  CHECK(r.stop_reason.find("did not fire") != std::string::npos);
}

TEST_CASE("a filled inside-out cube is re-oriented and filled like the cube") {
  // (250: at 200, seed 1, the radius that now gives about 200 had pass 1's
  // two sites blocked early, 182 spheres at 0.50, loose; seeds 2, 3 gave 198 at 0.54)
  const FillResult r = fill(make_inside_out_cube(1.0, 2), small_fill(250));
  check_quality(r, 0.45, 0.70);
  REQUIRE_FALSE(r.warnings.empty());
  CHECK(r.warnings[0].find("inside-out") != std::string::npos);
}

TEST_CASE("fill output written as PLY reads back as the same particles") {
  const FillResult r = fill(make_icosphere(1.0, 3), small_fill(100));
  const auto path = std::filesystem::temp_directory_path() / "pfill_test_fill.ply";
  write_particles(r.particles, path);
  const ParticleSet back = read_particles(path);
  std::filesystem::remove(path);
  REQUIRE(back.size() == r.particles.size());
  for (size_t i = 0; i < back.size(); ++i) {
    CHECK(back.positions[i].x == doctest::Approx(r.particles.positions[i].x).epsilon(1e-6));
    CHECK(back.radii[i] == doctest::Approx(r.particles.radii[i]).epsilon(1e-6));
  }
}

TEST_CASE("bad fills give one clear line") {
  const Mesh sphere = make_icosphere(1.0, 2);
  FillOptions o;
  o.radius = 2.0;
  CHECK_THROWS_WITH_AS(fill(sphere, o), doctest::Contains("no particle of radius 2 fits: the deepest point is"),
                       Error);
  o = FillOptions{};
  o.count = 1'000'000'000;
  CHECK_THROWS_WITH_AS(fill(sphere, o), doctest::Contains("more than pfill handles"), Error);
  o = FillOptions{};
  o.radius = 1e-5;
  CHECK_THROWS_WITH_AS(fill(sphere, o), doctest::Contains("more than pfill handles"), Error);
  o = small_fill(100);
  o.birth = Vec3{3, 0, 0};
  CHECK_THROWS_WITH_AS(fill(sphere, o), doctest::Contains("outside the mesh"), Error);
  o = small_fill(100);
  o.rest_distance = 0.5;
  CHECK_THROWS_WITH_AS(fill(sphere, o), doctest::Contains("rest_distance must"), Error);
  o = FillOptions{};
  CHECK_THROWS_WITH_AS(fill(sphere, o), doctest::Contains("give a count or a particle radius"), Error);
  Mesh empty;
  empty.source = "nothing.obj";
  CHECK_THROWS_WITH_AS(fill(empty, small_fill(10)), doctest::Contains("nothing.obj"), Error);
}

TEST_CASE("a rest distance of 1.5 contact distances gives sparse spheres, still about the count asked for") {
  FillOptions o = small_fill(400);
  o.rest_distance = 1.5;
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  INFO("particles " << r.particles.size() << ", packing " << r.metrics.packing_fraction);
  CHECK(r.particles.size() >= 300);
  CHECK(r.particles.size() <= 560);  // small objects overshoot: 495 measured on PoCL
  CHECK(r.metrics.overlapping_pairs == 0);
  CHECK(r.metrics.contained_share == 1.0);
  // (0.61 / 1.5^3 = 0.18): the spacing, not the spheres, fills the volume.
  CHECK(r.metrics.packing_fraction < 0.3);
  CHECK(r.metrics.packing_fraction > 0.12);
}

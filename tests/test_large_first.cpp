// Rare large spheres placed before pass 1 (src/fill/large_first.hpp), and
// the count rule's inclusions (pfill/count_rule.hpp) that size them.
#include <doctest/doctest.h>

#include <cmath>

#include "fill/large_first.hpp"
#include "pfill/boundary.hpp"
#include "pfill/count_rule.hpp"
#include "pfill/radius_distribution.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

// A ball of radius 1 as a signed distance field (negative inside).
ScalarGrid ball_field() {
  return sampled_grid(1.1, 0.02, [](const Vec3& p) { return length(p) - 1.0; });
}

// Each placed sphere `s.wall_gap` inside (by `depth`, the unit ball's by default) and apart.
template <class Depth>
void check_placement(const LargePlacement& p, const LargeFirstSettings& s, const Depth& depth) {
  for (size_t i = 0; i < p.centres.size(); ++i) {
    CHECK(depth(p.centres[i]) >= p.radii[i] + s.wall_gap - 1e-9);
    for (size_t j = i + 1; j < p.centres.size(); ++j)
      CHECK(length(p.centres[i] - p.centres[j]) >= p.radii[i] + p.radii[j] + s.pair_gap - 1e-9);
  }
}

void check_placement(const LargePlacement& p, const LargeFirstSettings& s) {
  check_placement(p, s, [](const Vec3& c) { return 1.0 - length(c); });
}

}  // namespace

TEST_CASE("large spheres placed first: all that fit, clear of the wall and of each other") {
  LargeFirstSettings s;
  s.wall_gap = 0.01;
  s.pair_gap = 0.02;
  const ScalarGrid f = ball_field();
  // Four of 0.4 fit in a ball of 1 (centres 0.82 apart in a core of
  // radius 0.59, whose inscribed tetrahedron has side 0.96): all placed.
  const LargePlacement four = place_large_first(f, {0.4, 0.4, 0.4, 0.4}, s);
  CHECK(four.centres.size() == 4);
  check_placement(four, s);
  // Three of 0.48 do not (a core of radius 0.51 holds no triangle of side
  // 0.98; its largest has 0.88): two, and a smaller one after them fits.
  const LargePlacement three = place_large_first(f, {0.48, 0.48, 0.48, 0.2}, s);
  CHECK(three.centres.size() == 3);
  CHECK(three.radii.back() == 0.2);
  check_placement(three, s);
  // Too large for the ball: none.
  CHECK(place_large_first(f, {1.2}, s).centres.empty());
}

// Where no process builds a field (the LAMMPS engine's sites from the
// mesh): the candidates from the mesh's exact depths, held by one process
// here (split over ranks: tests/test_lammps_sites.cpp).
TEST_CASE("large spheres placed first on candidates from the mesh: the same rule, clear of the wall") {
  LargeFirstSettings s;
  s.wall_gap = 0.01;
  s.pair_gap = 0.02;
  const Mesh ball = make_icosphere(1.0, 5);
  const Boundary boundary(ball);
  const HeldCandidates held = mesh_candidates(boundary, ball.bounds(), 0.03, 0.2, BirthView{});
  REQUIRE(held.points.size() > 1000);
  for (size_t k = 1; k < held.points.size(); ++k) CHECK(held.points[k - 1].order < held.points[k].order);
  for (const LargeCandidate& c : held.points) {
    CHECK(c.depth >= 0.2);
    CHECK(c.depth == doctest::Approx(-boundary.signed_distance(c.point)).epsilon(1e-9));
  }
  ProcessGroup one;
  auto depth = [&](const Vec3& c) { return -boundary.signed_distance(c); };
  const LargePlacement four = place_large_first(held, {0.4, 0.4, 0.4, 0.4}, s, one);
  CHECK(four.centres.size() == 4);
  check_placement(four, s, depth);
  const LargePlacement three = place_large_first(held, {0.48, 0.48, 0.48, 0.2}, s, one);
  CHECK(three.centres.size() == 3);
  CHECK(three.radii.back() == 0.2);
  check_placement(three, s, depth);
  CHECK(place_large_first(held, {1.2}, s, one).centres.empty());
  // A first sphere too large is skipped, the others placed.
  CHECK(place_large_first(held, {1.2, 0.3}, s, one).radii == std::vector<double>{0.3});
}

TEST_CASE("count rule: rare large spheres are inclusions, common mixes are not") {
  const Inclusions big = inclusions_of(RadiusDistribution::parse("discrete:1:0.5,10:0.5", FractionBasis::Volume));
  CHECK(big.number_share == doctest::Approx(1.0 / 1001));
  CHECK(big.volume_share == doctest::Approx(0.5));
  CHECK(big.radius == doctest::Approx(10));
  CHECK(inclusions_of(RadiusDistribution::parse("discrete:1:0.5,2:0.5")).volume_share == 0);
  CHECK(inclusions_of(RadiusDistribution::parse("discrete:1:0.5,3:0.5", FractionBasis::Volume)).volume_share == 0);
  CHECK(inclusions_of(RadiusDistribution::parse("lognormal:1,0.2")).volume_share == 0);
  CHECK(inclusions_of(RadiusDistribution::parse("uniform:1,10")).volume_share == 0);

  // The scale gives the inclusions a whole number: a cube of side 2 at -n
  // 750 with 1:4, 30% of the volume large, expects 4.99 of them: 5.
  const auto mix = RadiusDistribution::parse("discrete:1:0.7,4:0.3", FractionBasis::Volume);
  const double s = fill_scale_for_count(8, 24, 750, mix);
  const double n = expected_fill_count(8, 24, mix.scaled(s), 0.001);
  CHECK(n == doctest::Approx(750).epsilon(0.02));
  CHECK(inclusions_of(mix).number_share * n == doctest::Approx(5).epsilon(1e-6));
  // A packing the small spheres can reach around them (at most ~0.7).
  const double packing = n * 4.0 / 3.0 * M_PI * mix.scaled(s).mean_cube() / 8;
  CHECK(packing > 0.55);
  CHECK(packing < 0.7);
}

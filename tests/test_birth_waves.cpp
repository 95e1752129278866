// The birth schedule that scales: sites spread over the whole inside (their
// number grows with the volume), the grid room test, the share-of-births
// end of pass 1, and whole fills of generated shapes with births in waves.
#include <doctest/doctest.h>

#include <algorithm>
#include <random>

#include "pfill/birth_sites.hpp"
#include "pfill/boundary.hpp"
#include "pfill/fill.hpp"
#include "pfill/grid.hpp"
#include "pfill/sdf.hpp"
#include "pfill/shapes.hpp"
#include "pfill/stop_tests.hpp"

using namespace pfill;

namespace {

ScalarGrid ball_field(double radius, double spacing) {
  return sampled_grid(radius, spacing, [radius](const Vec3& p) { return length(p) - radius; });
}

FillOptions wave_fill(size_t count, uint64_t seed = 1) {
  FillOptions o;
  o.count = count;
  o.seed = seed;
  o.sites = 0;  // waves, whatever the count
  o.colour = ColourOptions{ColourMode::None, {}};
  return o;
}

}  // namespace

TEST_CASE("spread sites: the deepest first, all deep enough, spaced, covering, as many as the volume") {
  const double spacing = 0.3, min_depth = 0.1;
  const ScalarGrid field = ball_field(1.0, 0.02);
  const std::vector<BirthSite> sites = spread_birth_sites(field, spacing, min_depth);
  REQUIRE(sites.size() > 10);
  CHECK(length(sites[0].position) < 0.03);  // the centre is the deepest point
  for (size_t a = 0; a < sites.size(); ++a) {
    CHECK(sites[a].depth >= min_depth);
    CHECK(sites[a].depth == doctest::Approx(1.0 - length(sites[a].position)).epsilon(0.01));
    for (size_t b = a + 1; b < sites.size(); ++b) CHECK(length(sites[a].position - sites[b].position) >= spacing);
  }
  // Every point deep enough lies near a site (the sub-lattice is spacing / 3).
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 200; ++k) {
    const Vec3 p{u(rng), u(rng), u(rng)};
    if (1 - length(p) < min_depth + 0.05) continue;
    double nearest = 1e9;
    for (const BirthSite& s : sites) nearest = std::min(nearest, length(s.position - p));
    CHECK(nearest < spacing + 0.1);
  }
  // Twice the size, eight times the volume: about eight times the sites.
  const std::vector<BirthSite> big = spread_birth_sites(ball_field(2.0, 0.02), spacing, min_depth);
  const double ratio = static_cast<double>(big.size()) / static_cast<double>(sites.size());
  INFO("sites " << sites.size() << " and " << big.size());
  CHECK(ratio > 6.5);
  CHECK(ratio < 10.5);
  // A field with no point deep enough has no site.
  CHECK(spread_birth_sites(field, spacing, 1.5).empty());
}

// spread_birth_sites as it was before its candidates were gathered in
// parallel and the chosen sites kept in a dense grid: a scan of every site.
std::vector<BirthSite> spread_sites_by_scan(const ScalarGrid& sdf, double spacing, double min_depth) {
  std::vector<std::pair<float, size_t>> candidates;
  const int stride = std::max(1, static_cast<int>(spacing / 3 / sdf.spacing));
  for (int k = 0; k < sdf.dims[2]; k += stride)
    for (int j = 0; j < sdf.dims[1]; j += stride)
      for (int i = 0; i < sdf.dims[0]; i += stride)
        if (-sdf.at(i, j, k) >= min_depth) candidates.emplace_back(-sdf.at(i, j, k), sdf.index(i, j, k));
  std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  std::vector<BirthSite> sites;
  const int nx = sdf.dims[0], ny = sdf.dims[1];
  for (const auto& [depth, index] : candidates) {
    const Vec3 p = sdf.point(static_cast<int>(index % nx), static_cast<int>((index / nx) % ny),
                             static_cast<int>(index / (static_cast<size_t>(nx) * ny)));
    if (std::none_of(sites.begin(), sites.end(),
                     [&](const BirthSite& s) { return dot(s.position - p, s.position - p) < spacing * spacing; }))
      sites.push_back({p, depth});
  }
  return sites;
}

TEST_CASE("spread sites are those of a scan of every chosen site, in the same order (a torus, two spacings)") {
  const Boundary torus(make_torus(1.0, 0.4, 48, 24));
  SdfOptions so(0.03);
  const ScalarGrid field = build_signed_distance_field(torus, so);
  for (double spacing : {0.09, 0.25}) {
    const std::vector<BirthSite> fast = spread_birth_sites(field, spacing, 0.05);
    const std::vector<BirthSite> scan = spread_sites_by_scan(field, spacing, 0.05);
    INFO("spacing " << spacing << ": " << fast.size() << " and " << scan.size() << " sites");
    REQUIRE(fast.size() == scan.size());
    REQUIRE(fast.size() > 20);
    for (size_t k = 0; k < fast.size(); ++k) {
      CHECK(fast[k].position.x == scan[k].position.x);
      CHECK(fast[k].position.y == scan[k].position.y);
      CHECK(fast[k].position.z == scan[k].position.z);
      CHECK(fast[k].depth == scan[k].depth);
    }
  }
}

TEST_CASE("the grid room test answers as the scan of every centre does") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec3> centres;
  for (int k = 0; k < 3000; ++k) centres.push_back({u(rng), u(rng), 0.5 * u(rng)});
  for (double clearance : {0.02, 0.05, 0.2}) {
    const RoomGrid grid(centres, clearance);
    int room = 0, none = 0;
    for (int k = 0; k < 2000; ++k) {
      const Vec3 site{1.3 * u(rng), 1.3 * u(rng), 1.3 * u(rng)};  // some outside the centres' box
      const bool expected = site_has_room(centres, site, clearance);
      CHECK(grid.has_room(site) == expected);
      (expected ? room : none) += 1;
    }
    CHECK(room > 0);
    CHECK(none > 0);
  }
  CHECK(RoomGrid({}, 0.1).has_room({0, 0, 0}));
}

TEST_CASE("blocked sites with a share: full when a window's births fall to that share of the count") {
  BlockedSitesTest t({10, 0.01});
  for (int k = 0; k < 9; ++k) CHECK(t.observe(k % 5 == 0 ? 1 : 0, 100) == StopVerdict::Continue);
  // A full window of 10 steps with 2 births; 1% of 100 particles is 1: not yet.
  CHECK(t.observe(0, 100) == StopVerdict::Continue);
  // Still 2 births in the window, now of 300 particles (3 allowed): full.
  CHECK(t.observe(1, 300) == StopVerdict::Overfull);
  BlockedSitesTest plain({10});  // no share: only a window without any birth
  for (int k = 0; k < 30; ++k) CHECK(plain.observe(k % 9 == 0 ? 1 : 0, 1000) == StopVerdict::Continue);
}

TEST_CASE("births in waves fill a sphere: inside, overlaps within the bound, about the count, many sites") {
  FillOptions o = wave_fill(1500);
  const FillResult r = fill(make_icosphere(1.0, 4), o);
  INFO("particles " << r.metrics.count << ", packing " << r.metrics.packing_fraction << ", sites " << r.sites.size()
                    << ", pass 1 " << r.passes[0].steps << " steps");
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_penetration <= 0.01);
  CHECK(r.metrics.max_overlap <= o.max_overlap + 1e-9);
  CHECK(r.metrics.count >= 1300);  // 1,500 asked; a small ball's wall keeps it below
  CHECK(r.metrics.count <= 1700);
  CHECK(r.metrics.packing_fraction > 0.55);
  CHECK(r.sites.size() >= 4);
  CHECK(r.stop_signal == "blocked");
}

TEST_CASE("room sites: the sparse start in fewer steps of pass 1, as many spheres, the same bounds") {
  FillOptions plain = wave_fill(1500);
  plain.room_spacing = 0;  // the sites alone
  const Mesh ball = make_icosphere(1.0, 4);
  const FillResult a = fill(ball, plain);
  const FillResult b = fill(ball, wave_fill(1500));  // room sites (the default)
  INFO("pass 1 " << a.passes[0].steps << " and " << b.passes[0].steps << " steps; " << a.metrics.count << " and "
                 << b.metrics.count << " spheres");
  CHECK(b.passes[0].steps < 0.9 * static_cast<double>(a.passes[0].steps));
  CHECK(static_cast<double>(b.metrics.count) >= 0.98 * static_cast<double>(a.metrics.count));
  for (const FillResult* r : {&a, &b}) {
    CHECK(r->metrics.contained_share == 1.0);
    CHECK(r->metrics.max_overlap <= plain.max_overlap + 1e-9);
  }
}

TEST_CASE("births in waves fill a torus and a cube, and the same seed gives the same particles") {
  const Mesh torus = make_torus(1.0, 0.45, 64, 32);
  const FillResult a = fill(torus, wave_fill(600, 4));
  const FillResult b = fill(torus, wave_fill(600, 4));
  INFO("particles " << a.metrics.count << ", packing " << a.metrics.packing_fraction);
  CHECK(a.metrics.contained_share == 1.0);
  CHECK(a.metrics.max_overlap <= 0.05 + 1e-9);
  CHECK(a.metrics.count >= 480);
  CHECK(a.metrics.count <= 720);
  REQUIRE(a.particles.size() == b.particles.size());
  CHECK(a.particles.positions == b.particles.positions);
  const FillResult c = fill(make_cube(1.0, 2), wave_fill(600, 4));
  CHECK(c.metrics.contained_share == 1.0);
  CHECK(c.metrics.max_overlap <= 0.05 + 1e-9);
  CHECK(c.metrics.count >= 480);
  CHECK(c.metrics.count <= 720);
}

TEST_CASE("--sites 1 --birth-every 1 still runs the report's single birth point") {
  FillOptions o = wave_fill(200);
  o.sites = 1;
  o.birth_every = 1;
  const FillResult r = fill(make_icosphere(1.0, 3), o);
  REQUIRE(r.sites.size() == 1);
  CHECK(r.sites[0].depth > 0.7);  // deep inside the ball (of radius 1)
  CHECK(r.metrics.contained_share == 1.0);
  CHECK(r.metrics.max_overlap <= 0.05 + 1e-9);
  CHECK(r.metrics.count >= 150);
}

// Packing metrics and the containment repair on configurations whose
// answers are known.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "pfill/mesh_diagnostics.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/shapes.hpp"
#include "pfill/voids.hpp"
#include "fill/centre_grid.hpp"
#include "fill/depth_test.hpp"

using namespace pfill;

namespace {

ParticleSet spheres(std::initializer_list<Vec3> centres, double r) {
  ParticleSet s;
  for (const Vec3& c : centres) {
    s.positions.push_back(c);
    s.radii.push_back(r);
  }
  return s;
}
}  // namespace

TEST_CASE("packing fraction, containment and overlap of a known pair in a cube") {
  const Mesh cube = make_cube(1.0, 2);
  const Boundary b(cube);
  // Two spheres of r = 0.2 overlapping by 0.04 (20% of r), well inside.
  const ParticleSet s = spheres({{0, 0, 0}, {0.36, 0, 0}}, 0.2);
  const PackingMetrics m = measure_packing(b, 8.0, s);
  CHECK(m.count == 2);
  CHECK(m.packing_fraction == doctest::Approx(2 * 4.0 / 3.0 * kPi * 0.008 / 8.0));
  CHECK(m.contained_share == 1.0);
  CHECK(m.max_penetration <= 0);
  CHECK(m.overlapping_pairs == 1);
  CHECK(m.max_overlap == doctest::Approx(0.2));
  CHECK(m.mean_overlap == doctest::Approx(0.2));
  CHECK(m.mean_coordination == doctest::Approx(1.0));
}

TEST_CASE("a sphere poking out of the surface is counted and measured") {
  const Boundary b(make_cube(1.0, 1));
  // Centre 0.1 from the +x face, r = 0.2: it pokes out by 0.1 = 50% of r.
  const ParticleSet s = spheres({{0.9, 0, 0}, {0, 0, 0}, {1.05, 0, 0}}, 0.2);
  const PackingMetrics m = measure_packing(b, 8.0, s);
  CHECK(m.contained_share == doctest::Approx(1.0 / 3.0));
  CHECK(m.centres_outside == 1);
  CHECK(m.max_penetration == doctest::Approx(1.25));  // (0.2 + 0.05) / 0.2
}

TEST_CASE("simple cubic lattice: coordination 6 inside, no overlaps, exact touching counts as contact") {
  ParticleSet s;
  const double r = 0.1;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        s.positions.push_back(Vec3(i, j, k) * (2 * r) - Vec3(0.4, 0.4, 0.4));
        s.radii.push_back(r);
      }
  const PackingMetrics m = measure_packing(Boundary(make_cube(1.0, 1)), 8.0, s);
  CHECK(m.overlapping_pairs == 0);
  // 3 * 5 * 5 * 4 bonds among 125 spheres.
  CHECK(m.mean_coordination == doctest::Approx(2.0 * 300 / 125));
  CHECK(find_overlaps(s).empty());
}

TEST_CASE("repair_containment moves crossing spheres inside and removes those with no room") {
  const Boundary b(make_cube(1.0, 2));
  ParticleSet s = spheres({{0.95, 0.1, 0.2}, {0, 0, 0}, {1.5, 0, 0}}, 0.2);
  s.colours = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}};
  const ContainmentRepair rep = repair_containment(b, s, 0.01, 0.05);
  // The first moves to x = 0.8; the third (centre outside) lands at x = 0.8
  // too, on the first one's spot: it overlaps and gives way.
  CHECK(rep.moved == 1);
  CHECK(rep.removed == 1);
  REQUIRE(s.size() == 2);
  CHECK(s.positions[0].x == doctest::Approx(0.8));
  CHECK(s.colours[0] == Rgb8{1, 2, 3});
  const PackingMetrics m = measure_packing(b, 8.0, s);
  CHECK(m.contained_share == 1.0);

  // A sphere bigger than the part: no place inside, removed.
  ParticleSet big = spheres({{0.5, 0, 0}}, 1.5);
  CHECK(repair_containment(b, big, 0.01, 0.05).removed == 1);
  CHECK(big.size() == 0);
}

TEST_CASE("find_holes finds the one hole of a lattice with a sphere taken out, and nothing in a full one") {
  const double r = 0.1;
  ParticleSet full;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) {
        full.positions.push_back(Vec3(i, j, k) * (2 * r));
        full.radii.push_back(r);
      }
  // A field of a box holding the lattice: every sample deep enough.
  ScalarGrid sdf;
  sdf.origin = {-0.6, -0.6, -0.6};
  sdf.spacing = r / 4;
  sdf.dims = {49, 49, 49};
  sdf.values.assign(49 * 49 * 49, -1.0f);
  const double clearance = 1.8 * r;  // more than the lattice's biggest gap, sqrt(3) r
  CHECK(find_holes(full, sdf, r, clearance, 100).empty());

  ParticleSet holed = full;
  const size_t centre = holed.positions.size() / 2;  // the sphere at the origin
  REQUIRE(length(holed.positions[centre]) < 1e-12);
  holed.positions.erase(holed.positions.begin() + centre);
  holed.radii.erase(holed.radii.begin() + centre);
  const std::vector<Vec3> voids = find_holes(holed, sdf, r, clearance, 100);
  REQUIRE(voids.size() == 1);
  CHECK(length(voids[0]) <= 0.2 * r + 1e-9);
  CHECK(find_holes(holed, sdf, r, clearance, 0).empty());
}

TEST_CASE("find_holes climbs to a hole between grid points and takes only holes a sphere fits in") {
  const double r = 0.1;
  ParticleSet full;
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) {
        full.positions.push_back(Vec3(i, j, k) * (2 * r) + Vec3(0.013, -0.021, 0.017));  // off the grid
        full.radii.push_back(r);
      }
  ScalarGrid sdf;  // coarse (0.33 r, as fills use), every sample deep enough
  sdf.origin = {-0.66, -0.66, -0.66};
  sdf.spacing = r / 3;
  sdf.dims = {41, 41, 41};
  sdf.values.assign(41 * 41 * 41, -1.0f);
  CHECK(find_holes(full, sdf, r, 1.9 * r, 100).empty());  // the lattice's gaps reach sqrt(3) r only
  ParticleSet holed = full;
  const size_t centre = holed.positions.size() / 2;
  const Vec3 taken = holed.positions[centre];
  holed.positions.erase(holed.positions.begin() + centre);
  holed.radii.erase(holed.radii.begin() + centre);
  // The hole's centre lies between grid points; the climb finds it to within
  // a hundredth or two of r, where a sphere nearly fits with no overlap (1.99 r).
  const std::vector<Vec3> holes = find_holes(holed, sdf, r, 1.99 * r, 100);
  REQUIRE(holes.size() == 1);
  CHECK(length(holes[0] - taken) < 0.02 * r);
}

TEST_CASE("CentreGrid finds every centre within a cell of a point: dense cells, hashed sparse sets, later inserts") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  auto cloud = [&](size_t n, double scale) {
    std::vector<Vec3> ps;
    for (size_t i = 0; i < n; ++i) ps.push_back(Vec3(u(rng), u(rng), u(rng)) * scale);
    return ps;
  };
  const double cell = 0.13;
  // 2,000 centres in a unit box (dense cells), 20 in a box 1,000 times wider (hashed).
  for (const std::vector<Vec3>& centres : {cloud(2000, 1.0), cloud(20, 1000.0)}) {
    CentreGrid grid(centres, cell);
    std::vector<Vec3> all = centres;
    const std::vector<Vec3> later = cloud(50, 1.2);  // inserted after construction, some outside the dense box
    for (const Vec3& p : later) {
      grid.insert(p, static_cast<uint32_t>(all.size()));
      all.push_back(p);
    }
    std::vector<Vec3> queries = cloud(300, 1.3);
    queries.insert(queries.end(), centres.begin(), centres.begin() + 10);
    for (const Vec3& q : queries) {
      std::vector<uint32_t> found;
      grid.for_near(q, [&](uint32_t id) { found.push_back(id); });
      std::vector<uint32_t> sorted = found;
      std::sort(sorted.begin(), sorted.end());
      CHECK(std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end());  // each once
      for (uint32_t id = 0; id < all.size(); ++id)
        if (length(all[id] - q) < cell) CHECK(std::binary_search(sorted.begin(), sorted.end(), id));
      // any_near stops at the first centre its test accepts, and says whether one did.
      const bool near = std::any_of(found.begin(), found.end(), [&](uint32_t id) { return length(all[id] - q) < 0.5 * cell; });
      int asked = 0;
      CHECK(grid.any_near(q, [&](uint32_t id) {
              ++asked;
              return length(all[id] - q) < 0.5 * cell;
            }) == near);
      CHECK(asked <= static_cast<int>(found.size()));
    }
  }
}

namespace {

/// Random sequential addition of spheres of radius r in [-0.5, 0.5]^3, 2r
/// apart: a loose packing (~0.3) with holes left between them.
ParticleSet loose_packing(double r) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  ParticleSet loose;
  for (int tries = 0; tries < 4000; ++tries) {
    const Vec3 p(u(rng), u(rng), u(rng));
    bool clear = true;
    for (const Vec3& q : loose.positions) clear = clear && length(p - q) >= 2 * r;
    if (!clear) continue;
    loose.positions.push_back(p);
    loose.radii.push_back(r);
  }
  return loose;
}

}  // namespace

TEST_CASE("find_holes in a random packing: every hole deep enough, clear of every centre and of the other holes") {
  const double r = 0.05;
  const ParticleSet loose = loose_packing(r);
  ScalarGrid sdf;  // a box [-0.6, 0.6]^3 at 0.33 r, sampled analytically
  sdf.spacing = r / 3;
  const int n = static_cast<int>(std::ceil(1.2 / sdf.spacing)) + 1;
  sdf.origin = {-0.6, -0.6, -0.6};
  sdf.dims = {n, n, n};
  sdf.values.resize(static_cast<size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const Vec3 p = sdf.point(i, j, k);
        sdf.values[sdf.index(i, j, k)] =
            static_cast<float>(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) - 0.55);
      }
  const double clearance = 1.9 * r;
  const std::vector<Vec3> holes = find_holes(loose, sdf, r, clearance, 1000);
  REQUIRE(holes.size() > 10);  // a random sequential packing (~0.3) is full of them
  for (size_t h = 0; h < holes.size(); ++h) {
    const Vec3& p = holes[h];
    CHECK(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}) <= 0.55 - r + 1e-6);
    double nearest = 1e9;
    for (const Vec3& q : loose.positions) nearest = std::min(nearest, length(p - q));
    CHECK(nearest >= clearance);
    for (size_t g = 0; g < h; ++g) CHECK(length(p - holes[g]) >= clearance);
  }
  CHECK(find_holes(loose, sdf, r, clearance, 5).size() == 5);
}

// The finish's holes with the wall from the mesh (FillOptions::wall_from_mesh):
// a grid without values lays out the search, the distance comes from a function.
TEST_CASE("find_holes by an exact distance: deep enough by it, as many as on a sampled grid of it") {
  const double r = 0.05;
  const ParticleSet loose = loose_packing(r);
  auto ball = [](const Vec3& p) { return length(p) - 0.52; };  // curved: the grid's interpolation misses it a little
  const ScalarGrid sdf = sampled_grid(0.6, 2 * r / 3, ball);
  ScalarGrid lattice = sdf;
  lattice.values.clear();  // the exact search must not read them
  const double clearance = 1.9 * r;
  const std::vector<Vec3> on_grid = find_holes(loose, sdf, r, clearance, 1000);
  const std::vector<Vec3> exact = find_holes(loose, lattice, ball, r, clearance, 1000);
  INFO(exact.size() << " holes by the exact distance, " << on_grid.size() << " on its grid");
  REQUIRE(exact.size() > 10);
  CHECK(std::abs(static_cast<double>(exact.size()) - static_cast<double>(on_grid.size())) <=
        0.1 * static_cast<double>(on_grid.size()));
  for (size_t h = 0; h < exact.size(); ++h) {
    CHECK(-ball(exact[h]) >= r - 1e-9);
    double nearest = 1e9;
    for (const Vec3& q : loose.positions) nearest = std::min(nearest, length(exact[h] - q));
    CHECK(nearest >= clearance);
    for (size_t g = 0; g < h; ++g) CHECK(length(exact[h] - exact[g]) >= clearance);
  }
  const Box3 half{{-0.6, -0.6, -0.6}, {0.0, 0.6, 0.6}};  // a process's sub-domain
  const std::vector<Vec3> in_half = find_holes(loose, lattice, ball, r, clearance, 1000, 0, nullptr, &half);
  CHECK(in_half.size() > exact.size() / 4);
  CHECK(in_half.size() < 3 * exact.size() / 4);
  for (const Vec3& p : in_half) CHECK(p.x <= 2 * clearance);  // (a climb may end a little outside it)
}

TEST_CASE("largest empty hole and closest centres of a lattice, full and with a sphere taken out") {
  const double r = 0.1;
  const Boundary b(make_cube(1.0, 2));
  // A lattice of spacing 2.02 r filling the cube [-1, 1]^3: its largest gap
  // is at the centre of a lattice cube, sqrt(3) 1.01 r from 8 centres (the
  // layer next to the wall holds none as wide).
  ParticleSet fills;
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int k = -4; k <= 4; ++k) {
        fills.positions.push_back(Vec3(i, j, k) * (2.02 * r));
        fills.radii.push_back(r);
      }
  const PackingMetrics m = measure_packing(b, 8.0, fills);
  CHECK(m.min_distance == doctest::Approx(1.01));
  CHECK(m.largest_hole == doctest::Approx(std::sqrt(3.0) * 1.01 - 1).epsilon(0.01));
  ParticleSet holed = fills;
  const size_t centre = holed.positions.size() / 2;
  REQUIRE(length(holed.positions[centre]) < 1e-12);
  holed.positions.erase(holed.positions.begin() + centre);
  holed.radii.erase(holed.radii.begin() + centre);
  // Where the sphere was: 2.02 r to the nearest centres, 1.02 r to their surfaces.
  CHECK(largest_hole_over_r(b, holed, r) == doctest::Approx(1.02).epsilon(0.005));
}

TEST_CASE("largest empty hole among spheres of radii 1:5: the large sphere's surface bounds it") {
  // Spheres of r on a lattice, and one of 5 r at the centre in place of
  // those it would overlap. The hole search keeps the sizes apart (a grid
  // per size level): a search that lost the large sphere would find a
  // hole of 2 r (the cap) inside it.
  const double r = 0.1, big = 5 * r;
  const Boundary b(make_cube(1.0, 2));
  ParticleSet mix;
  mix.positions.push_back(Vec3());
  mix.radii.push_back(big);
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      for (int k = -4; k <= 4; ++k) {
        const Vec3 c = Vec3(i, j, k) * (2.02 * r);
        if (length(c) < big + r) continue;
        mix.positions.push_back(c);
        mix.radii.push_back(r);
      }
  const Hole h = largest_hole(b, mix, r);
  double gap = 2 * r;  // the hole's gap by brute force, at the point it gave
  for (size_t i = 0; i < mix.size(); ++i) gap = std::min(gap, length(mix.positions[i] - h.centre) - mix.radii[i]);
  CHECK(h.gap_over_r == doctest::Approx(gap / r).epsilon(1e-9));
  CHECK(h.gap_over_r > std::sqrt(3.0) * 1.01 - 1 + 0.1);  // the shell around the large sphere: wider than the lattice's holes
  CHECK(h.gap_over_r < 2.0);
  CHECK(length(h.centre) > big);
  // pfill check's figure is the fill's: of the smallest radius.
  CHECK(measure_packing(b, 8.0, mix).largest_hole == doctest::Approx(h.gap_over_r));
}

TEST_CASE("the hole search's depth test answers as the exact signed distance does: closed, open and two-part meshes") {
  Mesh two = make_cube(0.5, 2);  // a cube and a ball that overlap: a union of parts
  two.corner_uvs.clear();
  const Mesh second = make_icosphere(0.6, 2);
  for (const Triangle& t : second.triangles)
    two.triangles.push_back({t[0] + static_cast<uint32_t>(two.positions.size()),
                             t[1] + static_cast<uint32_t>(two.positions.size()),
                             t[2] + static_cast<uint32_t>(two.positions.size())});
  for (const Vec3& v : second.positions) two.positions.push_back(v + Vec3(0.4, 0, 0));
  const Mesh meshes[] = {make_torus(1.0, 0.4, 48, 24), make_open_cube(1.0, 3), two};
  for (const Mesh& mesh : meshes) {
    const Boundary boundary(mesh);
    CHECK(boundary.union_of_parts() == (&mesh == &meshes[2]));
    CHECK(boundary.closed() == (&mesh != &meshes[1]));
    const double depth = 0.15, step = 0.037;
    const Vec3 origin(-1.7, -1.7, -1.1);
    DepthTest test(boundary, depth, origin, step);
    std::vector<Vec3> points;
    for (int k = 0; k < 60; ++k)
      for (int j = 0; j < 92; ++j)
        for (int i = 0; i < 92; ++i) points.push_back(origin + Vec3(i, j, k) * step);
    const std::vector<uint8_t> batch = test.deep(points);
    size_t deep = 0, wrong = 0, single_wrong = 0;
    for (size_t n = 0; n < points.size(); ++n) {
      const bool exact = boundary.fast_signed_distance(points[n]) <= -depth;
      deep += exact;
      wrong += (batch[n] != 0) != exact;
      single_wrong += test.deep(points[n]) != exact;
    }
    INFO(mesh.triangles.size() << " triangles: " << deep << " of " << points.size() << " points deep");
    CHECK(deep > 1000);
    CHECK(wrong == 0);
    CHECK(single_wrong == 0);
  }
}

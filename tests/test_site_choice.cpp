// Birth sites chosen per process (src/fill/site_choice.hpp, issue 31): one
// process's sweep is the plain deepest-first rule; processes that each
// decide their own region and tell each other what they decided near the
// borders (simulated here in one process, sweep for sweep) end with the
// same sites between them, whatever the split; the sites keep the
// spacing, lie at their exact depth, and cover every deep candidate.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "fill/mesh_sites.hpp"
#include "fill/site_choice.hpp"
#include "pfill/birth_sites.hpp"
#include "pfill/boundary.hpp"
#include "pfill/sdf.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

struct Deep {
  double depth;
  uint64_t lattice;
  Vec3 p;
};

// Every lattice point at least min_depth inside, by the unbounded exact
// query, deepest first (ties: lower index).
std::vector<Deep> deep_lattice(const Boundary& b, const SiteLattice& l) {
  std::vector<Deep> out;
  for (int64_t k = 0; k < l.points[2]; ++k)
    for (int64_t j = 0; j < l.points[1]; ++j)
      for (int64_t i = 0; i < l.points[0]; ++i) {
        const Vec3 p = l.point({i, j, k});
        const double depth = -b.fast_signed_distance(p);
        if (depth >= l.min_depth) out.push_back({depth, l.index({i, j, k}), p});
      }
  std::sort(out.begin(), out.end(), [](const Deep& a, const Deep& c) {
    return a.depth > c.depth || (a.depth == c.depth && a.lattice < c.lattice);
  });
  return out;
}

// The rule itself, plainly: deepest first, kept unless a kept one is within the spacing.
std::vector<KeyedSite> plain_rule(const Boundary& b, const SiteLattice& l) {
  std::vector<KeyedSite> kept;
  for (const Deep& d : deep_lattice(b, l)) {
    const bool near = std::any_of(kept.begin(), kept.end(), [&](const KeyedSite& s) {
      const Vec3 v = s.site.position - d.p;
      return dot(v, v) < l.spacing * l.spacing;  // (as the choice: lattice points a spacing apart sit on the bound)
    });
    if (!near) kept.push_back({{d.p, d.depth}, d.lattice});
  }
  std::sort(kept.begin(), kept.end(), [](const KeyedSite& a, const KeyedSite& c) { return a.key < c.key; });
  return kept;
}

// P processes, one per region, in lockstep: each sweeps, all hear all.
// Returns every process's sites, in key order; `sweeps` the sweeps it took.
std::vector<KeyedSite> split_rule(const Boundary& b, const SiteLattice& l, const std::vector<Box3>& regions, int& sweeps) {
  std::vector<std::unique_ptr<SiteChoice>> ps;
  for (size_t r = 0; r < regions.size(); ++r) ps.push_back(std::make_unique<SiteChoice>(b, l, regions, static_cast<int>(r)));
  sweeps = 0;
  for (;;) {
    ++sweeps;
    std::vector<uint64_t> told;
    for (auto& p : ps) {
      const std::vector<uint64_t> t = p->sweep();
      told.insert(told.end(), t.begin(), t.end());
    }
    size_t left = 0;
    for (auto& p : ps) {
      p->apply(told);
      left += p->undecided();
    }
    REQUIRE(sweeps < 1000);
    if (left == 0) break;
  }
  std::vector<KeyedSite> all;
  for (auto& p : ps) {
    const std::vector<KeyedSite> s = p->sites(0);
    all.insert(all.end(), s.begin(), s.end());
  }
  std::sort(all.begin(), all.end(), [](const KeyedSite& a, const KeyedSite& c) { return a.key < c.key; });
  return all;
}

void check_same(const std::vector<KeyedSite>& got, const std::vector<KeyedSite>& expected) {
  REQUIRE(got.size() == expected.size());
  for (size_t k = 0; k < got.size(); ++k) {
    CHECK(got[k].key == expected[k].key);
    CHECK(length(got[k].site.position - expected[k].site.position) == 0);
    CHECK(got[k].site.depth == expected[k].site.depth);
  }
}

Box3 box(const Vec3& lo, const Vec3& hi) {
  Box3 b;
  b.add(lo);
  b.add(hi);
  return b;
}

// The mesh's box cut at the given shares of x (and of y when `ys` is given).
std::vector<Box3> cuts(const Box3& bounds, const std::vector<double>& xs, const std::vector<double>& ys = {}) {
  std::vector<double> x{-1e9}, y{-1e9};
  for (double s : xs) x.push_back(bounds.lo.x + s * (bounds.hi.x - bounds.lo.x));
  for (double s : ys) y.push_back(bounds.lo.y + s * (bounds.hi.y - bounds.lo.y));
  x.push_back(1e9);
  y.push_back(1e9);
  std::vector<Box3> out;
  for (size_t j = 0; j + 1 < y.size(); ++j)
    for (size_t i = 0; i + 1 < x.size(); ++i) out.push_back(box({x[i], y[j], -1e9}, {x[i + 1], y[j + 1], 1e9}));
  return out;
}

std::vector<KeyedSite> one_process(const Boundary& b, const SiteLattice& l) {
  SiteChoice one(b, l, {}, 0);
  CHECK(one.sweep().empty());  // nothing to tell: no other region
  CHECK(one.undecided() == 0);
  return one.sites(0);
}

}  // namespace

TEST_CASE("site choice: one process's sweep is the plain deepest-first rule") {
  const Mesh torus = make_torus(1.0, 0.4, 48, 24);
  const Boundary boundary(torus);
  const SiteLattice l(torus.bounds(), 0.15, 0.05);
  const std::vector<KeyedSite> got = one_process(boundary, l);
  INFO(got.size() << " sites");
  REQUIRE(got.size() > 50);
  check_same(got, plain_rule(boundary, l));
  // Another key base shifts every key alike.
  SiteChoice again(boundary, l, {}, 0);
  again.sweep();
  const std::vector<KeyedSite> shifted = again.sites(uint64_t(1) << 62);
  REQUIRE(shifted.size() == got.size());
  for (size_t k = 0; k < got.size(); ++k) CHECK(shifted[k].key == got[k].key + (uint64_t(1) << 62));
}

TEST_CASE("site choice: processes that each decide their region and tell their borders end with one process's sites") {
  const Mesh torus = make_torus(1.0, 0.4, 48, 24);
  const Boundary boundary(torus);
  const SiteLattice l(torus.bounds(), 0.09, 0.03);
  const std::vector<KeyedSite> whole = one_process(boundary, l);
  REQUIRE(whole.size() > 500);
  int most = 0;
  for (const auto& regions : {cuts(torus.bounds(), {0.5}), cuts(torus.bounds(), {0.31, 0.77}),
                              cuts(torus.bounds(), {0.4}, {0.55}), cuts(torus.bounds(), {0.2, 0.4, 0.6, 0.8})}) {
    CAPTURE(regions.size());
    int sweeps = 0;
    check_same(split_rule(boundary, l, regions, sweeps), whole);
    most = std::max(most, sweeps);
  }
  CHECK(most > 1);  // the borders' news mattered
}

TEST_CASE("site choice: sites apart by the spacing, at their exact depth, and near every deep candidate") {
  const Mesh ball = make_icosphere(1.0, 4);
  const Boundary boundary(ball);
  const SiteLattice l(ball.bounds(), 0.25, 0.1);
  const std::vector<KeyedSite> sites = one_process(boundary, l);
  REQUIRE(sites.size() > 50);
  for (size_t i = 0; i < sites.size(); ++i) {
    CHECK(sites[i].site.depth >= l.min_depth);
    CHECK(sites[i].site.depth == doctest::Approx(-boundary.signed_distance(sites[i].site.position)).epsilon(1e-9));
    for (size_t j = i + 1; j < sites.size(); ++j) {
      const Vec3 v = sites[i].site.position - sites[j].site.position;
      CHECK(dot(v, v) >= l.spacing * l.spacing);
    }
  }
  const std::vector<Deep> deep = deep_lattice(boundary, l);
  CHECK(deep.size() > 10 * sites.size());
  size_t uncovered = 0;
  for (const Deep& d : deep)
    if (std::none_of(sites.begin(), sites.end(), [&](const KeyedSite& s) { return length(s.site.position - d.p) < l.spacing; }))
      ++uncovered;
  CHECK(uncovered == 0);
}

TEST_CASE("site choice: an object too thin for the depth has no site; a bad spacing is refused") {
  const Mesh slab = make_cube(0.05, 1);
  const Boundary boundary(slab);
  CHECK(one_process(boundary, SiteLattice(slab.bounds(), 0.02, 0.06)).empty());
  CHECK_FALSE(one_process(boundary, SiteLattice(slab.bounds(), 0.02, 0.01)).empty());
  CHECK_THROWS(SiteLattice(slab.bounds(), 0, 0.01));
}

// The report's few sites where no field is built (src/fill/mesh_sites.hpp):
// the rule of the field's choice on candidates with the mesh's depths.
// Round a torus, sites spread round the ring, the first the deepest
// candidate, their inscribed balls apart; the same rooms the field's
// choice finds, to within the candidates' spacing (split over ranks:
// tests/test_lammps_sites.cpp).
TEST_CASE("report's sites from the mesh: the deepest, then far apart round a torus, as on the field") {
  const Mesh torus = make_torus(1.0, 0.4);
  const Boundary boundary(torus);
  const double step = 0.04, min_depth = 0.1;
  const HeldCandidates held = mesh_candidates(boundary, torus.bounds(), step, min_depth, BirthView{});
  ProcessGroup one;
  const std::vector<BirthSite> sites = choose_birth_sites(held, 4, min_depth, 0.5, one);
  REQUIRE(sites.size() == 4);
  double deepest = 0;
  for (const LargeCandidate& c : held.points) deepest = std::max(deepest, c.depth);
  CHECK(sites[0].depth == deepest);
  for (size_t i = 0; i < sites.size(); ++i) {
    CHECK(sites[i].depth == doctest::Approx(-boundary.signed_distance(sites[i].position)).epsilon(1e-9));
    CHECK(sites[i].depth >= 0.5 * deepest);
    for (size_t j = i + 1; j < sites.size(); ++j)
      CHECK(length(sites[i].position - sites[j].position) >= sites[i].depth + sites[j].depth);
  }
  // The field's choice at a like spacing: the same rooms round the ring.
  SdfOptions o;
  o.spacing = step;
  const ScalarGrid field = build_signed_distance_field(boundary, o);
  const std::vector<BirthSite> on_field = choose_birth_sites(field, 4, min_depth, 0.5);
  REQUIRE(on_field.size() == sites.size());
  for (size_t i = 0; i < sites.size(); ++i) {
    INFO("site " << i);
    CHECK(std::fabs(sites[i].depth - on_field[i].depth) < 2 * step);
  }
  // The second across the ring from the first (its diameter 2), on both.
  CHECK(length(sites[1].position - sites[0].position) > 1.8);
  CHECK(length(on_field[1].position - on_field[0].position) > 1.8);
  // Too thin for the depth asked: none.
  CHECK(choose_birth_sites(held, 4, 0.5, 0.5, one).empty());
}

// The finish (src/fill/finish.cpp) on sets of spheres whose answers are
// known: overlaps resolved by moving spheres when there is room, deletions
// only when there is not, and counted; and whole fills at tight bounds.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>

#include "engine_fixtures.hpp"
#include "fill/finish.hpp"
#include "fill/near_region.hpp"
#include "pfill/fill.hpp"
#include "pfill/packing_metrics.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;
using pfill::test::shared_device;

namespace {

constexpr double kR = 0.1;
constexpr double kBall = 0.7;

/// The signed distance field of a ball of radius kBall, at r / 3.
ScalarGrid ball_field() {
  return sampled_grid(kBall + 3 * kR, kR / 3, [](const Vec3& p) { return length(p) - kBall; });
}

/// A simple cubic lattice of spacing `spacing` whose centres lie within
/// `extent` of the origin.
std::vector<Particle> lattice(double spacing, double extent) {
  std::vector<Particle> ps;
  const int n = static_cast<int>(extent / spacing) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 p = Vec3(i, j, k) * spacing + Vec3(0.003, -0.002, 0.001);
        if (length(p) > extent) continue;
        Particle q;
        q.position = p;
        q.radius = kR;
        ps.push_back(q);
      }
  return ps;
}

EngineParams base_params() {
  EngineParams p;
  p.radius = kR;
  p.max_radius = kR * (1 + 1e-6);
  return p;
}

double worst_overlap(const ParticleSet& s) {
  double worst = 0;
  for (const Overlap& o : find_overlaps(s)) worst = std::max(worst, o.fraction);
  return worst;
}

/// The finish at radius kR and `bound`; hole_rounds 0 leaves holes alone.
FinishSettings settings(double bound, int hole_rounds = FinishSettings{}.hole_rounds) {
  FinishSettings s;
  s.radius = kR;
  s.max_overlap = bound;
  s.hole_rounds = hole_rounds;
  return s;
}

}  // namespace

TEST_CASE("finish: overlapping spheres with room around them are moved apart, none deleted") {
  // Spacing 1.9 r: every neighbour overlaps by 10% of r; the lattice fills
  // the inner 0.6 of the ball, so there is room to spread.
  const std::vector<Particle> ps = lattice(1.9 * kR, 0.6 * kBall);
  REQUIRE(ps.size() > 30);
  const FinishSettings s = settings(0.001, 0);
  FinishStats stats;
  const ParticleSet out = finish_packing(shared_device(), base_params(), ball_field(), ps, s, stats);
  CHECK(stats.removed == 0);
  CHECK(out.size() == ps.size());
  CHECK(worst_overlap(out) <= 0.001);
  for (const Vec3& p : out.positions) CHECK(length(p) <= kBall - kR * (1 - 1e-3));
}

TEST_CASE("finish: an over-full ball forces deletions, which are counted, and the bound holds") {
  // Spacing 1.5 r throughout the ball: a packing of 0.9, about 1.6 times what fits.
  const std::vector<Particle> ps = lattice(1.5 * kR, kBall - kR);
  REQUIRE(ps.size() > 250);
  for (double bound : {0.0, 0.001, 0.05}) {
    CAPTURE(bound);
    const FinishSettings s = settings(bound);
    FinishStats stats;
    const ParticleSet out = finish_packing(shared_device(), base_params(), ball_field(), ps, s, stats);
    CHECK(stats.removed > 0);
    CHECK(out.size() + stats.removed == ps.size() + stats.inserted);
    CHECK(worst_overlap(out) <= std::max(bound, 1e-4));
    // What a ball of 7 r holds at random: packing 0.45-0.66 (the wall loosens it).
    const double phi = out.size() * std::pow(kR / kBall, 3);
    CHECK(phi > 0.45);
    CHECK(phi < 0.66);
    for (const Vec3& p : out.positions) CHECK(length(p) <= kBall - kR * (1 - 1e-3));
  }
}

TEST_CASE("finish: the relaxation's inner lists give the same spheres, bit for bit, as its full lists") {
  // An over-full ball (as below): relaxations, deletions and hole rounds,
  // with every pair the inner lists leave out checked by the result: a pair
  // missed would move some sphere, and every later step with it.
  const std::vector<Particle> ps = lattice(1.5 * kR, kBall - kR);
  FinishSettings s = settings(0.001);
  FinishStats inner_stats, full_stats;
  s.inner_lists = true;
  const ParticleSet inner = finish_packing(shared_device(), base_params(), ball_field(), ps, s, inner_stats);
  // Every pair loop on its whole list, as where a block's share of the
  // inner buffer has no room left (kernels built with PF_INNER_FULL_ROWS).
  FinishStats whole_stats;
  const ParticleSet whole = [&] {
    const test::ScopedClOptions full_rows("-DPF_INNER_FULL_ROWS=1");
    return finish_packing(shared_device(), base_params(), ball_field(), ps, s, whole_stats);
  }();
  s.inner_lists = false;
  const ParticleSet full = finish_packing(shared_device(), base_params(), ball_field(), ps, s, full_stats);
  CHECK(inner_stats.removed > 0);
  for (const auto* other : {&inner, &whole}) {
    CHECK((other == &inner ? inner_stats : whole_stats).steps == full_stats.steps);
    REQUIRE(other->size() == full.size());
    for (size_t i = 0; i < full.size(); ++i) {
      CAPTURE(i);
      CHECK(other->ids[i] == full.ids[i]);
      CHECK(other->positions[i].x == full.positions[i].x);
      CHECK(other->positions[i].y == full.positions[i].y);
      CHECK(other->positions[i].z == full.positions[i].z);
    }
  }
}

TEST_CASE("finish: FIRE reaches the bound on an over-full packing in fewer steps than the damped relaxation") {
  // Spacing 1.5 r throughout the ball (as above): a packing of 0.9, every
  // neighbour overlapping by half of r. Holes left alone: the relaxations
  // and deletions alone.
  const std::vector<Particle> ps = lattice(1.5 * kR, kBall - kR);
  REQUIRE(ps.size() > 250);
  FinishStats by_fire, by_damping;
  FinishSettings s = settings(0.001, 0);
  const ParticleSet fired = finish_packing(shared_device(), base_params(), ball_field(), ps, s, by_fire);
  s.fire = false;
  const ParticleSet damped = finish_packing(shared_device(), base_params(), ball_field(), ps, s, by_damping);
  INFO("FIRE: " << by_fire.steps << " steps, " << fired.size() << " spheres; damped: " << by_damping.steps
                << " steps, " << damped.size() << " spheres");
  CHECK(by_fire.steps < by_damping.steps);
  for (const ParticleSet* out : {&fired, &damped}) {
    CHECK(worst_overlap(*out) <= 0.001);
    for (const Vec3& p : out->positions) CHECK(length(p) <= kBall - kR * (1 - 1e-3));
  }
  CHECK(fired.size() + 5 >= damped.size());  // as many spheres kept, or nearly
}

TEST_CASE("finish: under FIRE, deleting all of the excess the overlaps imply at a stall takes fewer steps than half") {
  // The over-full ball (as above). FIRE stalls at the jammed state, where
  // the estimate falls short of what must go: half of it a round only
  // spreads the same deletions over more relaxations.
  const std::vector<Particle> ps = lattice(1.5 * kR, kBall - kR);
  REQUIRE(ps.size() > 250);
  FinishStats all, half;
  FinishSettings s = settings(0.001, 0);
  s.fire_removal_share = 1;
  const ParticleSet by_all = finish_packing(shared_device(), base_params(), ball_field(), ps, s, all);
  s.fire_removal_share = 0.5;
  const ParticleSet by_half = finish_packing(shared_device(), base_params(), ball_field(), ps, s, half);
  INFO("all: " << all.steps << " steps, " << all.rounds << " relaxations, " << by_all.size()
               << " spheres; half: " << half.steps << " steps, " << half.rounds << " relaxations, " << by_half.size()
               << " spheres");
  CHECK(all.steps < half.steps);
  CHECK(all.rounds < half.rounds);
  CHECK(by_all.size() + 3 >= by_half.size());  // as many spheres kept, or nearly
  CHECK(worst_overlap(by_all) <= 0.001);
  CHECK(all.forced == 0);
}

TEST_CASE("finish: a loose packing is compressed by holes taken below 2r, to a dense one within the bound") {
  // Spacing 2.5 r: a packing of 0.17 in the ball, with room everywhere
  // between the lattice points for spheres that overlap their neighbours.
  const std::vector<Particle> ps = lattice(2.5 * kR, kBall - kR);
  REQUIRE(ps.size() > 50);
  auto packing = [](const ParticleSet& s) { return s.size() * std::pow(kR / kBall, 3); };
  FinishStats plain_stats, compressed_stats;
  const ParticleSet plain =
      finish_packing(shared_device(), base_params(), ball_field(), ps, settings(0.001), plain_stats);
  FinishSettings s = settings(0.001);
  s.compress_clearance = 1.7;
  const ParticleSet compressed = finish_packing(shared_device(), base_params(), ball_field(), ps, s, compressed_stats);
  INFO("plain " << packing(plain) << ", compressed " << packing(compressed));
  CHECK(packing(compressed) > 0.5);  // a ball of 7 r packs 0.45-0.66 at random
  CHECK(packing(compressed) > packing(plain) + 0.03);
  CHECK(worst_overlap(compressed) <= 0.001);
  for (const Vec3& p : compressed.positions) CHECK(length(p) <= kBall - kR * (1 - 1e-3));
}

TEST_CASE("fill a sphere at a 0.1% bound and at none: bound met, every sphere inside, dense, no hole left") {
  for (double bound : {0.001, 0.0}) {
    CAPTURE(bound);
    FillOptions o;
    o.count = 250;
    o.max_overlap = bound;
    o.colour = ColourOptions{ColourMode::None, {}};
    const FillResult r = fill(make_icosphere(1.0, 4), o);
    const PackingMetrics& m = r.metrics;
    INFO("particles " << m.count << ", packing " << m.packing_fraction << ", max overlap " << m.max_overlap
                      << ", hole " << m.largest_hole);
    CHECK(m.max_overlap <= std::max(bound, 1e-4));
    CHECK(m.contained_share == 1.0);
    CHECK(m.max_penetration <= 0.01);
    CHECK(m.count >= 225);  // -n gives about N (the radius allows for the bound and the wall): 250 +- 10%
    CHECK(m.count <= 275);
    CHECK(m.largest_hole < 1.0);
    CHECK(m.min_distance >= 1 - 0.5 * std::max(bound, 1e-4));
  }
}

TEST_CASE("finish: each sphere keeps its id through the finish's renumbering along the cells") {
  // The lattice of the first case, ids in the reverse of the cells' order,
  // so that renumbering moves every sphere; no deletions, no holes.
  std::vector<Particle> ps = lattice(1.9 * kR, 0.6 * kBall);
  for (size_t i = 0; i < ps.size(); ++i) ps[i].id = 1000 + (ps.size() - i);
  std::reverse(ps.begin(), ps.end());
  const FinishSettings s = settings(0.001, 0);
  FinishStats stats;
  const ParticleSet out = finish_packing(shared_device(), base_params(), ball_field(), ps, s, stats);
  REQUIRE(stats.removed == 0);
  REQUIRE(out.ids.size() == ps.size());
  // Every id once, and each sphere ends nearer to where its own sphere
  // started than to any other start (the lattice spreads out a little as
  // its overlaps of 10% r are undone).
  std::vector<uint64_t> seen = out.ids;
  std::sort(seen.begin(), seen.end());
  CHECK(std::adjacent_find(seen.begin(), seen.end()) == seen.end());
  for (size_t k = 0; k < out.size(); ++k) {
    const uint64_t id = out.ids[k];
    REQUIRE(id > 1000);
    REQUIRE(id <= 1000 + ps.size());
    const Particle& start = ps[id - 1001];
    CHECK(start.id == id);
    size_t nearest = 0;
    for (size_t i = 1; i < ps.size(); ++i)
      if (length(out.positions[k] - ps[i].position) < length(out.positions[k] - ps[nearest].position)) nearest = i;
    CHECK(ps[nearest].id == id);
  }
}

TEST_CASE("the radius for a count allows for the bound and the wall") {
  // A unit ball: volume 4.19, surface 12.6; 4,000 spheres.
  const double v = 4.0 / 3.0 * 3.14159265358979, a = 4 * 3.14159265358979;
  const double tight = fill_radius_for_count(v, a, 4000, 0.001);
  // Packing 0.60-0.62 at the 0.1% bound (fills of a sphere: 0.604 at 2,000).
  const double packing = 4000 * std::pow(tight, 3);  // N r^3 / R^3
  CHECK(packing > 0.59);
  CHECK(packing < 0.63);
  // A looser bound packs denser: larger spheres for the same count.
  CHECK(fill_radius_for_count(v, a, 4000, 0.05) > tight * 1.01);
  // More wall (the same volume inside a larger surface) packs looser: smaller spheres.
  CHECK(fill_radius_for_count(v, 3 * a, 4000, 0.001) < tight * 0.99);
  // No count, no volume: no radius.
  CHECK(fill_radius_for_count(v, a, 0) == 0);
  CHECK(fill_radius_for_count(0, a, 4000) == 0);
}

TEST_CASE("finish: the spheres near a few places move, those around them are held, and come back by index") {
  const std::vector<Particle> ps = lattice(2 * kR, kBall - kR);
  const Vec3 place(0.1, 0, 0);
  const NearRegion region = region_near(ps, {place}, 2.5 * kR, 2 * kR);
  REQUIRE(!region.moving.empty());
  REQUIRE(!region.held.empty());
  std::vector<int> kind(ps.size(), 0);
  for (uint32_t i : region.moving) kind[i] = 1;
  for (uint32_t i : region.held) kind[i] = 2;
  for (size_t i = 0; i < ps.size(); ++i) {
    const double d = length(ps[i].position - place);
    CHECK(kind[i] == (d < 2.5 * kR ? 1 : d < 4.5 * kR ? 2 : 0));
  }
  // Held spheres get the mass; ids are the indices.
  const std::vector<Particle> part = region_particles(ps, region, 1e30);
  REQUIRE(part.size() == region.moving.size() + region.held.size());
  CHECK(part.front().id == region.moving.front());
  CHECK(part.back().mass == 1e30);
  CHECK(part.front().mass == ps[region.moving.front()].mass);
  // The first moving sphere moved, the second gone (the wall took it), a held one "moved" (ignored).
  // (The lattice's ids are all 0: region_particles' ids are indices.)
  REQUIRE(region.moving.size() >= 2);
  std::vector<Particle> moved = part;
  moved[0].position = moved[0].position + Vec3(0.01, 0, 0);
  moved.erase(moved.begin() + 1);
  moved.back().position = Vec3(9, 9, 9);
  const std::vector<Particle> out = with_moved(ps, region, moved);
  REQUIRE(out.size() == ps.size() - 1);
  const size_t first = region.moving[0];
  const Particle& back = out[ps.size() - region.moving.size()];  // the moved ones come last
  CHECK(back.position.x == doctest::Approx(ps[first].position.x + 0.01));
  CHECK(back.position.y == doctest::Approx(ps[first].position.y));
  CHECK(out[0].position.x == ps[0].position.x);  // the first sphere is far: as it was
  for (const Particle& p : out) CHECK(length(p.velocity) == 0);
  for (const Particle& p : out) CHECK(length(p.position - Vec3(9, 9, 9)) > 1);  // the held one as it was
  for (const Particle& p : out) CHECK(length(p.position - ps[region.moving[1]].position) > 1e-9);  // gone
}

TEST_CASE("finish: a held sphere (as good as infinite mass) stays put while its neighbour relaxes away from it") {
  Particle a, b;
  a.radius = b.radius = kR;
  a.position = Vec3(-0.9 * kR, 0, 0);
  b.position = Vec3(0.9 * kR, 0, 0);  // overlapping by 20% of r
  const NearRegion region{{1}, {0}};
  const std::vector<Particle> part = region_particles({a, b}, region, 1e30);
  Engine engine(shared_device(), base_params());
  engine.set_field(ball_field());
  engine.add_particles(part);
  engine.run_steps(300);
  const std::vector<Particle> after = engine.read_particles();
  REQUIRE(after.size() == 2);
  for (const Particle& p : after) {
    if (p.id == 0) CHECK(length(p.position - a.position) < 1e-6);  // held
    if (p.id == 1) CHECK(p.position.x > b.position.x + 0.1 * kR);   // pushed away
  }
}

TEST_CASE("finish: the last jams relaxed on their own meet the bound as relaxing all does") {
  // The over-full ball; every relaxation after the first of the spheres
  // within 3 r of a pair over the bound, those 3 r further held.
  const std::vector<Particle> ps = lattice(1.5 * kR, kBall - kR);
  FinishStats all, near;
  FinishSettings s = settings(0.001, 0);
  s.near_share = 0;
  const ParticleSet by_all = finish_packing(shared_device(), base_params(), ball_field(), ps, s, all);
  s.near_share = 1;
  s.near_min_spheres = 0;
  s.near_reach = 3;
  const ParticleSet by_near = finish_packing(shared_device(), base_params(), ball_field(), ps, s, near);
  INFO("all: " << all.steps << " steps, " << by_all.size() << " spheres; near: " << near.steps << " steps, "
               << by_near.size() << " spheres, " << near.near_rounds << " of " << near.rounds << " relaxations near");
  CHECK(all.near_rounds == 0);
  CHECK(near.near_rounds > 0);
  CHECK(near.near_rounds < near.rounds);  // the first is of all
  CHECK(worst_overlap(by_near) <= 0.001);
  CHECK(near.forced == 0);
  CHECK(by_near.size() + near.removed == ps.size() + near.inserted);
  CHECK(by_near.size() + 5 >= by_all.size());  // as many spheres kept, or nearly
  for (const Vec3& p : by_near.positions) CHECK(length(p) <= kBall - kR * (1 - 1e-3));
}

// Cell levels (EngineConstants::cell_levels, kernels/cells.cl): unequal
// spheres of radii 1:2 and more are put in nested grids by size, so that
// the neighbour search of the small ones reads small cells. On a 1:10 mix
// (a few large spheres among many small ones) every step form's lists
// equal a brute-force pair search, the test kernel's neighbours equal the
// pairs in reach, and every form agrees with the double reference. Each
// test loops over the step forms itself (the ctest variants do not run
// this file).
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "engine_fixtures.hpp"
#include "pfill/engine/engine.hpp"
#include "pfill/engine/reference.hpp"

using namespace pfill;
using namespace pfill::test;

namespace {

constexpr double kSmall = 0.25;  // EngineParams::radius
constexpr double kLarge = 10 * kSmall;

using Form = StepFormCase;
const auto& kForms = kStepForms;

EngineParams params_for(const Form& f, double cutoff_sigma) {
  EngineParams p;
  f.apply(p);
  p.radius = kSmall;
  p.max_radius = kLarge;
  p.cutoff_sigma = cutoff_sigma;
  p.restitution = 0.7;
  p.damping = 0.1;
  return p;
}

// `large` spheres of kLarge, then `small` of kSmall and a few of 2.2 and
// 4.5 kSmall (levels 1 and 2; none with `middle` false: the kernels then
// skip the empty levels), in a ball of radius R: centres inside by
// their own radius, pairwise at least 0.9 (r_i + r_j) apart, velocities
// uniform in [-speed, speed]^3. Deterministic for a seed.
std::vector<Particle> ten_to_one(size_t large, size_t small, double R, double speed, unsigned seed,
                                 bool middle = true) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(-R, R), vel(-speed, speed), u(0, 1);
  std::vector<Particle> out;
  for (size_t tries = 0; out.size() < large + small && tries < 400000; ++tries) {
    const double draw = u(rng);
    const double r = out.size() < large            ? kLarge
                     : middle && draw < 0.03 ? 2.2 * kSmall
                     : middle && draw < 0.05 ? 4.5 * kSmall
                                             : kSmall;
    const Vec3 x{pos(rng), pos(rng), pos(rng)};
    if (length(x) > R - r) continue;
    bool ok = true;
    for (const Particle& q : out)
      if (length(q.position - x) < 0.9 * (q.radius + r)) {
        ok = false;
        break;
      }
    if (!ok) continue;
    Particle p;
    p.position = x;
    p.velocity = {vel(rng), vel(rng), vel(rng)};
    p.radius = r;
    out.push_back(p);
  }
  return out;
}

// The pairs a list build takes (kernels/common.cl PF_LISTED): within the
// largest pair's reach and the pair's own, max(q max(rc, rest), r_i + r_j)
// plus the skin. `band`: the pairs within 1e-4 of their reach (rounding
// decides them either way).
void listed_by_brute_force(const std::vector<Particle>& ps, const EngineConstants& c, double radius,
                           std::set<std::pair<uint32_t, uint32_t>>& want,
                           std::set<std::pair<uint32_t, uint32_t>>& band) {
  const double reach_ref = std::max(c.cutoff, c.contact_distance);
  for (uint32_t i = 0; i < ps.size(); ++i)
    for (uint32_t j = i + 1; j < ps.size(); ++j) {
      const double rs = ps[i].radius + ps[j].radius;
      const double reach = std::min(c.list_reach, std::max(rs / (2 * radius) * reach_ref, rs) + c.skin);
      const double d = length(ps[i].position - ps[j].position);
      if (std::fabs(d - reach) < 1e-4 * reach)
        band.insert({i, j});
      else if (d < reach)
        want.insert({i, j});
    }
}

}  // namespace

TEST_CASE("cell levels: unequal spheres of radii 1:2 and more get nested levels; equal spheres one grid") {
  EngineParams p;
  p.radius = 0.25;
  p.max_radius = 2.5;  // 1:10: levels up to 1.25, 2.5, 5, 10 times the smallest
  EngineConstants c = derive_constants(p);
  CHECK(c.cell_levels == 4);
  CHECK(c.level_radius == doctest::Approx(0.3125));
  CHECK(c.cell_size * 8 >= c.list_reach);  // the top level's cells reach the largest pair
  CHECK(c.cell_size < c.list_reach / 4);
  p.max_radius = 0.5;  // 1:2
  c = derive_constants(p);
  CHECK(c.cell_levels == 2);
  CHECK(c.cell_size * 2 >= c.list_reach);
  p.max_radius = 0.45;  // under 1:2: one grid, sized for the largest pair
  c = derive_constants(p);
  CHECK(c.cell_levels == 1);
  CHECK(c.cell_size == c.list_reach);
  p.max_radius = 0;  // equal spheres: as before
  c = derive_constants(p);
  CHECK(c.cell_levels == 1);
  CHECK(c.cell_size == c.list_reach);
  CHECK(c.cell_capacity_up == c.cell_capacity);
}

TEST_CASE("cell levels: every form's lists equal a brute-force pair search on a 1:10 mix") {
  const double R = 8.0;
  const ScalarGrid field = sphere_grid(R, 0.25);
  // and the first mix once more in a box mostly outside the ball, whose far
  // cells of every level have no slots (CellGrid::set_domain)
  const ScalarGrid wide = sampled_grid(2 * R, 0.5, [R](const Vec3& x) { return sphere_distance(x, R); });
  for (int mix = 0; mix < 5; ++mix) {
    const bool middle = mix < 2 || mix == 4;
    const double cutoff = mix % 2 == 0 ? 0.0 : 2.5;
    const auto start = ten_to_one(5, 3000, R, 0.5, 11, middle);
    REQUIRE(start.size() == 3005);
    for (const Form& f : kForms) {
      INFO("form " << std::string(f.name) << ", cutoff " << cutoff << (middle ? ", levels 1, 2 too" : ", levels 0, 3")
                   << (mix == 4 ? ", wide box" : ""));
      Engine engine(shared_device(), params_for(f, cutoff));
      REQUIRE(engine.constants().cell_levels == 4);
      engine.set_field(mix == 4 ? wide : field);
      engine.add_particles(start);
      const auto at_build = engine.read_particles();  // as the kernels hold them (float)
      std::set<std::pair<uint32_t, uint32_t>> want, band;
      listed_by_brute_force(at_build, engine.constants(), kSmall, want, band);
      engine.run_steps(1);  // builds every list from at_build
      const auto rows = engine.step_lists();
      const bool once = engine.choices().newton;
      std::set<std::pair<uint32_t, uint32_t>> got;
      size_t entries = 0, wrong = 0, twice = 0;
      for (uint32_t i = 0; i < rows.size(); ++i)
        for (uint32_t j : rows[i]) {
          ++entries;
          const auto pair = std::make_pair(std::min(i, j), std::max(i, j));
          if (!got.insert(pair).second) ++twice;
          if (!want.count(pair) && !band.count(pair)) ++wrong;
        }
      size_t missing = 0;
      for (const auto& pair : want) missing += got.count(pair) ? 0 : 1;
      CHECK(missing == 0);
      CHECK(wrong == 0);
      if (once)
        CHECK(twice == 0);
      else
        CHECK(twice == got.size());  // each pair in both lists
      CHECK(want.size() > 1000);
      // the large spheres' pairs with the small ones are among them
      size_t mixed = 0;
      for (const auto& [i, j] : want) mixed += (at_build[i].radius > 1) != (at_build[j].radius > 1) ? 1 : 0;
      CHECK(mixed > 200);
      CHECK(engine.read_history().back().cell_overflow == 0);
    }
  }
}

TEST_CASE("cell levels: the neighbours the cells find equal the pairs in reach on a 1:10 mix") {
  const auto start = ten_to_one(5, 2000, 8.0, 0.5, 12);
  REQUIRE(start.size() == 2005);
  for (const Form& f : {kForms[0], kForms[1], kForms[4]}) {
    INFO("form " << std::string(f.name));
    EngineParams p = params_for(f, 2.5);
    Engine engine(shared_device(), p);
    ReferenceEngine ref(p);
    engine.set_field(sphere_grid(8.0, 0.25));
    engine.add_particles(start);
    ref.add_particles(engine.read_particles());
    CHECK(compare_lists(engine.neighbour_lists(), ref.neighbour_lists()).differ == 0);
  }
}

TEST_CASE("cell levels: every step form matches the reference on a 1:10 mix") {
  const double R = 8.0;
  const ScalarGrid field = sphere_grid(R, 0.25);
  const auto start = ten_to_one(5, 2000, R, 1.0, 13);
  REQUIRE(start.size() == 2005);
  for (double cutoff : {0.0, 2.5}) {
    for (const Form& f : kForms) {
      const EngineParams p = params_for(f, cutoff);
      Engine engine(shared_device(), p);
      ReferenceEngine ref(p);
      engine.set_field(field);
      ref.set_field(field);
      engine.add_particles(start);
      ref.add_particles(start);
      INFO("form " << std::string(f.name) << ", cutoff " << cutoff);
      StepRecord last{};
      for (int s = 0; s < 5; ++s) last = ref.step();
      engine.run_steps(5);
      const auto got = engine.read_particles();
      double dx = 0, dv = 0;
      for (size_t i = 0; i < got.size(); ++i) {
        dx = std::max(dx, length(got[i].position - ref.particles()[i].position));
        dv = std::max(dv, length(got[i].velocity - ref.particles()[i].velocity));
      }
      CHECK(dx < 1e-5);
      CHECK(dv < 5e-4);
      const auto h = engine.read_history();
      CHECK(h.back().colliding_pairs == last.colliding_pairs);
      CHECK(h.back().cell_overflow == 0);
      CHECK(last.colliding_pairs > 0);
    }
  }
}

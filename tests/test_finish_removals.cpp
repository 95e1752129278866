// The finish's deletions (src/fill/finish_removals.cpp) on jams whose
// answers are known: which spheres go after a stall, how many jams lose
// one, and never two touching spheres in a round.
#include <doctest/doctest.h>

#include <algorithm>
#include <set>

#include "fill/finish_removals.hpp"
#include "fill/finish_view.hpp"
#include "fill/particle_set_of.hpp"

using namespace pfill;

namespace {

/// One process's view of `n` spheres of radius 1 (where they lie does not
/// enter the choice: the overlaps are given).
FinishView view_of(size_t n) {
  std::vector<Particle> ps(n);
  for (size_t i = 0; i < n; ++i) ps[i].position = Vec3(3.0 * static_cast<double>(i), 0, 0), ps[i].radius = 1;
  FinishView v;
  static_cast<LocalView&>(v) = whole_view(ps);
  v.set = to_particle_set(ps);
  return v;
}

/// `jams` jams, each a chain of three spheres (3k, 3k + 1, 3k + 2) whose
/// middle one overlaps both others by just over the bound (0.0015 of r at
/// a 0.001 bound), jam k a little more than jam k + 1; and a pair under
/// the bound, which is no jam.
std::vector<Overlap> chains(size_t jams) {
  std::vector<Overlap> out;
  for (size_t k = 0; k < jams; ++k) {
    const auto a = static_cast<uint32_t>(3 * k);
    const double f = 0.0015 + 1e-6 * static_cast<double>(jams - k);
    out.push_back({a, a + 1, f});
    out.push_back({a + 1, a + 2, f});
  }
  const auto last = static_cast<uint32_t>(3 * jams);
  out.push_back({last, last + 1, 0.0005});
  return out;
}

/// The rule at a 0.001 bound, half the estimated excess, and `jam_share`.
RemovalRule rule_at(double jam_share) {
  RemovalRule rule;
  rule.max_overlap = 0.001;
  rule.jam_share = jam_share;
  rule.share = 0.5;
  return rule;
}

}  // namespace

TEST_CASE("finish removals: a tenth of the jams lose their most pressed sphere, the most pressed jams first") {
  const size_t jams = 20;
  // half of an excess of 0.045 spheres in all is 1
  const std::vector<size_t> out = most_compressed(view_of(3 * jams + 2), chains(jams), rule_at(0.1));
  // a tenth of 20 jams; the excess's one is among them
  REQUIRE(out.size() == 2);
  CHECK(out[0] == 1);  // the middle sphere of the most pressed jam
  CHECK(out[1] == 4);
}

TEST_CASE("finish removals: at a jam share of 1 every jam loses its most pressed sphere, never one it touches") {
  const size_t jams = 20;
  const std::vector<size_t> out = most_compressed(view_of(3 * jams + 2), chains(jams), rule_at(1));
  CHECK(out.size() == jams);
  std::set<size_t> jams_hit;
  for (size_t i : out) {
    CHECK(i % 3 == 1);  // each jam's middle sphere, the most pressed: never an end it touches
    jams_hit.insert(i / 3);
  }
  CHECK(jams_hit.size() == jams);
  CHECK(std::find(out.begin(), out.end(), 3 * jams) == out.end());  // the pair under the bound: no jam
}

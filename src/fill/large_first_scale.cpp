// Re-planning for rare large spheres (large_first_scale.hpp).
#include "fill/large_first_scale.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "fill/counter_rng.hpp"
#include "fill/size_deficit.hpp"
#include "pfill/count_rule.hpp"

namespace pfill {
namespace {

// Where the mix has inclusions (count_rule.hpp: radii 4 times the
// commonest's and more, rare), a class larger than the commonest that the
// fill expects at most this many times (other mixes: at most as many
// times as there are sites) is placed before pass 1: a handful of large
// spheres finds room only while the mesh is empty.
constexpr double kPlacedFirst = 16;
// Each try shrinks the radii by this factor (the volume by 27%), at most
// this many times (to 0.43): each try is a placement on the field alone.
constexpr double kScaleStep = 0.9;
constexpr int kScaleTries = 8;
// Then halvings between the last scale that missed and the first that fit
// (three: to within 1.3%).
constexpr int kRefinements = 3;

}  // namespace

double front_first_wave(const FillPlan& plan, size_t sites) {
  const double n = static_cast<double>(sites);
  return plan.sizes && inclusions_of(*plan.sizes).number_share > 0 ? std::max(kPlacedFirst, n) : n;
}

LargeFirstSettings large_first_settings(double smallest_radius) {
  LargeFirstSettings s;
  s.wall_gap = 0.5 * smallest_radius;
  s.pair_gap = smallest_radius;
  return s;
}

std::vector<double> front_loaded_radii(const FillPlan& plan, size_t sites, uint64_t seed) {
  if (!plan.sizes) return {};
  SizeDeficit sizes(*plan.sizes);
  sizes.front_load(plan.expected, front_first_wave(plan, sites));
  std::mt19937_64 rng(CounterRng(seed, 0, 0, 2)());
  return sizes.front_radii(rng);
}

double lowest_large_first_scale() { return std::pow(kScaleStep, kScaleTries); }

double large_first_scale(const LargePlacer& place, const FillPlan& plan, size_t sites, uint64_t seed) {
  const std::vector<double> radii = front_loaded_radii(plan, sites, seed);
  auto fits = [&](double scale) {
    std::vector<double> scaled = radii;
    for (double& r : scaled) r *= scale;
    return place(scaled, large_first_settings(scale * plan.radius)).centres.size() == radii.size();
  };
  if (radii.empty() || fits(1)) return 1;
  double fit = kScaleStep, miss = 1;
  for (int k = 1; !fits(fit); ++k, miss = fit, fit *= kScaleStep)
    if (k == kScaleTries) return 1;  // none fits them all: the count rule's radii, the shares held to those placed
  // The largest scale that fits, between the last miss and the first fit:
  // the denser the fill (the volume goes as the cube of the scale).
  for (int k = 0; k < kRefinements; ++k) {
    const double mid = std::sqrt(fit * miss);
    (fits(mid) ? fit : miss) = mid;
  }
  return fit;
}

}  // namespace pfill

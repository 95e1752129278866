// How close a set of radii comes to a size distribution
// (radius_distribution.hpp: compare_distribution).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "pfill/radius_distribution.hpp"

namespace pfill {
namespace {

std::string g3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}
}  // namespace

DistributionFit compare_distribution(const RadiusDistribution& d, const std::vector<double>& radii_in) {
  using Law = RadiusDistribution::Law;
  const bool ks = d.law() != Law::Discrete && d.law() != Law::Equal;
  const std::vector<SizeClass> classes = d.law() == Law::Uniform || d.law() == Law::Lognormal ||
                                                 d.law() == Law::Normal
                                             ? d.size_classes(8)
                                             : d.size_classes();
  std::vector<double> radii;  // NaN and inf say nothing of sizes
  for (double r : radii_in)
    if (std::isfinite(r)) radii.push_back(r);
  std::sort(radii.begin(), radii.end());
  DistributionFit fit;
  fit.class_error = !ks;
  fit.basis = d.law() == Law::Discrete ? d.basis() : FractionBasis::Number;
  std::vector<double> count(classes.size(), 0), volume(classes.size(), 0);
  double total_volume = 0;
  for (double r : radii) {
    // The nearest class (distance 0 inside [lo, hi]), the lower on a tie.
    size_t k = std::upper_bound(classes.begin(), classes.end(), r,
                                [](double x, const SizeClass& c) { return x < c.lo; }) - classes.begin();
    size_t best = 0;
    double best_gap = HUGE_VAL;
    for (size_t j = k >= 2 ? k - 2 : 0; j <= k && j < classes.size(); ++j) {
      const double gap = r < classes[j].lo ? classes[j].lo - r : r > classes[j].hi ? r - classes[j].hi : 0;
      if (gap < best_gap) best_gap = gap, best = j;
    }
    count[best] += 1;
    volume[best] += r * r * r;
    total_volume += r * r * r;
  }
  const double n = static_cast<double>(radii.size());
  for (size_t j = 0; j < classes.size(); ++j) {
    DistributionFit::ClassFit c;
    c.lo = classes[j].lo, c.hi = classes[j].hi;
    c.requested_number = classes[j].number_share, c.requested_volume = classes[j].volume_share;
    c.achieved_number = n > 0 ? count[j] / n : 0;
    c.achieved_volume = total_volume > 0 ? volume[j] / total_volume : 0;
    fit.classes.push_back(c);
    const double err = fit.basis == FractionBasis::Volume ? c.achieved_volume - c.requested_volume
                                                          : c.achieved_number - c.requested_number;
    if (!ks) fit.distance = std::max(fit.distance, std::abs(err));
  }
  if (ks) {
    fit.distance = radii.empty() ? 1 : 0;
    const double lowest = d.min_radius();
    for (size_t i = 0; i < radii.size(); ++i) {
      const double f = d.cdf(radii[i]), f_left = radii[i] <= lowest ? 0 : f;  // a sieve's share at its smallest radius
      fit.distance = std::max({fit.distance, (i + 1) / n - f, f_left - i / n});
    }
  }
  if (n > 0) {
    double sum = 0;
    for (double r : radii) sum += r;
    fit.mean = sum / n;
    double m2 = 0, m3 = 0;
    for (double r : radii) m2 += (r - fit.mean) * (r - fit.mean), m3 += std::pow(r - fit.mean, 3);
    fit.stddev = std::sqrt(m2 / n);
    fit.skewness = fit.stddev > 1e-12 * fit.mean ? m3 / n / std::pow(fit.stddev, 3) : 0;
  }
  return fit;
}

std::string DistributionFit::describe() const {
  std::string out;
  char line[160];
  for (const ClassFit& c : classes) {
    const std::string range = c.lo == c.hi ? "r " + g3(c.lo) : g3(c.lo) + ".." + g3(c.hi);
    std::snprintf(line, sizeof line, "%-18s number %5.1f%% -> %5.1f%%, volume %5.1f%% -> %5.1f%%\n", range.c_str(),
                  100 * c.requested_number, 100 * c.achieved_number, 100 * c.requested_volume,
                  100 * c.achieved_volume);
    out += line;
  }
  out += class_error ? "largest class error " + g3(100 * distance) + " percentage points by " + to_string(basis)
                     : "KS distance " + g3(distance);
  return out + "; radii mean " + g3(mean) + ", std " + g3(stddev) + ", skewness " + g3(skewness);
}

}  // namespace pfill

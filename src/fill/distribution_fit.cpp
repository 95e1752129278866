// How close a set of radii comes to a size distribution
// (radius_distribution.hpp: compare_distribution).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include "pfill/engine/process_group.hpp"
#include "pfill/particle_share.hpp"
#include "pfill/radius_distribution.hpp"

namespace pfill {
namespace {

std::string g3(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

/// The classes a fit reports: a continuous law's in 8 quantile bins.
std::vector<SizeClass> fit_classes(const RadiusDistribution& d) {
  using Law = RadiusDistribution::Law;
  return d.law() == Law::Uniform || d.law() == Law::Lognormal || d.law() == Law::Normal ? d.size_classes(8)
                                                                                          : d.size_classes();
}

/// Whether the fit is a Kolmogorov-Smirnov distance (else the largest class error).
bool by_ks(const RadiusDistribution& d) {
  using Law = RadiusDistribution::Law;
  return d.law() != Law::Discrete && d.law() != Law::Equal;
}

/// The finite radii (NaN and inf say nothing of sizes), ascending.
std::vector<double> finite_sorted(const std::vector<double>& radii_in) {
  std::vector<double> radii;
  for (double r : radii_in)
    if (std::isfinite(r)) radii.push_back(r);
  std::sort(radii.begin(), radii.end());
  return radii;
}

/// Per class: the number and the volume of `radii` in it (the nearest
/// class, distance 0 inside [lo, hi], the lower on a tie), then the whole
/// volume, the count and the radii's sum: 2 classes + 3 values.
std::vector<double> class_sums(const std::vector<SizeClass>& classes, const std::vector<double>& radii) {
  const size_t m = classes.size();
  std::vector<double> sums(2 * m + 3, 0);
  for (double r : radii) {
    size_t k = std::upper_bound(classes.begin(), classes.end(), r,
                                [](double x, const SizeClass& c) { return x < c.lo; }) - classes.begin();
    size_t best = 0;
    double best_gap = HUGE_VAL;
    for (size_t j = k >= 2 ? k - 2 : 0; j <= k && j < m; ++j) {
      const double gap = r < classes[j].lo ? classes[j].lo - r : r > classes[j].hi ? r - classes[j].hi : 0;
      if (gap < best_gap) best_gap = gap, best = j;
    }
    sums[best] += 1;
    sums[m + best] += r * r * r;
    sums[2 * m] += r * r * r;
    sums[2 * m + 2] += r;
  }
  sums[2 * m + 1] = static_cast<double>(radii.size());
  return sums;
}

/// The fit's classes, and for a discrete law its distance, from class_sums.
DistributionFit fit_of_classes(const RadiusDistribution& d, const std::vector<SizeClass>& classes,
                               const std::vector<double>& sums) {
  const size_t m = classes.size();
  const double total_volume = sums[2 * m], n = sums[2 * m + 1];
  DistributionFit fit;
  fit.class_error = !by_ks(d);
  fit.basis = d.law() == RadiusDistribution::Law::Discrete ? d.basis() : FractionBasis::Number;
  for (size_t j = 0; j < m; ++j) {
    DistributionFit::ClassFit c;
    c.lo = classes[j].lo, c.hi = classes[j].hi;
    c.requested_number = classes[j].number_share, c.requested_volume = classes[j].volume_share;
    c.achieved_number = n > 0 ? sums[j] / n : 0;
    c.achieved_volume = total_volume > 0 ? sums[m + j] / total_volume : 0;
    fit.classes.push_back(c);
    const double err = fit.basis == FractionBasis::Volume ? c.achieved_volume - c.requested_volume
                                                          : c.achieved_number - c.requested_number;
    if (fit.class_error) fit.distance = std::max(fit.distance, std::abs(err));
  }
  return fit;
}

/// The Kolmogorov-Smirnov terms of the sorted radius r at index i of n
/// (a sieve's share at its smallest radius counts from its left).
double ks_terms(const RadiusDistribution& d, double r, double i, double n) {
  const double f = d.cdf(r), f_left = r <= d.min_radius() ? 0 : f;
  return std::max((i + 1) / n - f, f_left - i / n);
}

/// The law's quantile bins for the distance in parts: fine enough that
/// few bins may hold it, 128 KiB summed over the processes.
constexpr size_t kQuantileBins = size_t{1} << 14;

size_t quantile_bin(double f) {
  return std::min(kQuantileBins - 1, static_cast<size_t>(std::max(0.0, f * static_cast<double>(kQuantileBins))));
}

/// The Kolmogorov-Smirnov distance of every process's radii together
/// (`radii`: this process's, sorted; n: all of them). Each radius's index
/// among all lies within its quantile bin's run, known from the bins'
/// counts summed: that bounds every radius's terms from below (summed
/// over the processes: a bound on the distance) and each bin's from above.
/// Only the bins whose bound passes the distance's can hold it: their
/// radii, from every process, give the exact terms there.
double ks_in_parts(const RadiusDistribution& d, const std::vector<double>& radii, double n, ProcessGroup& group) {
  std::vector<double> cdf(radii.size()), count(kQuantileBins, 0);
  for (size_t i = 0; i < radii.size(); ++i) count[quantile_bin(cdf[i] = d.cdf(radii[i]))] += 1;
  group.sum(count);
  std::vector<double> before(kQuantileBins, 0);  // radii in the bins below
  for (size_t k = 1; k < kQuantileBins; ++k) before[k] = before[k - 1] + count[k - 1];
  double lower = 0;
  for (size_t i = 0; i < radii.size(); ++i) {
    const size_t k = quantile_bin(cdf[i]);
    const double f = cdf[i], f_left = radii[i] <= d.min_radius() ? 0 : f;
    lower = std::max({lower, (before[k] + 1) / n - f, f_left - (before[k] + count[k] - 1) / n});
  }
  lower = group.max(lower);
  const double width = 1.0 / static_cast<double>(kQuantileBins);
  auto open = [&](size_t k) {
    return count[k] > 0 && std::max((before[k] + count[k]) / n - static_cast<double>(k) * width,
                                    static_cast<double>(k + 1) * width - before[k] / n) > lower;
  };
  std::vector<double> mine;  // the open bins' radii: (bin, radius) pairs
  for (size_t i = 0; i < radii.size(); ++i)
    if (const size_t k = quantile_bin(cdf[i]); open(k)) mine.insert(mine.end(), {static_cast<double>(k), radii[i]});
  Bytes bytes;
  to_bytes(mine, bytes);
  std::vector<double> all = from_bytes<double>(group.all_gather(bytes));
  std::vector<std::pair<double, double>> open_radii;
  for (size_t w = 0; w + 2 <= all.size(); w += 2) open_radii.emplace_back(all[w], all[w + 1]);
  std::sort(open_radii.begin(), open_radii.end());
  double distance = lower;
  for (size_t j = 0, first = 0; j < open_radii.size(); ++j) {
    if (open_radii[j].first != open_radii[first].first) first = j;
    const double i = before[static_cast<size_t>(open_radii[j].first)] + static_cast<double>(j - first);
    distance = std::max(distance, ks_terms(d, open_radii[j].second, i, n));
  }
  return distance;
}

/// The sums of the radii's deviations from `mean`, squared and cubed.
std::vector<double> deviation_sums(const std::vector<double>& radii, double mean) {
  std::vector<double> m{0, 0};
  for (double r : radii) m[0] += (r - mean) * (r - mean), m[1] += std::pow(r - mean, 3);
  return m;
}

/// The radii's mean, standard deviation and skewness into `fit`, from
/// their count n, their sum, and the sums of their deviations' squares
/// and cubes (about the mean).
void set_moments(DistributionFit& fit, double n, double mean, double m2, double m3) {
  if (n <= 0) return;
  fit.mean = mean;
  fit.stddev = std::sqrt(m2 / n);
  fit.skewness = fit.stddev > 1e-12 * fit.mean ? m3 / n / std::pow(fit.stddev, 3) : 0;
}

}  // namespace

DistributionFit compare_distribution(const RadiusDistribution& d, const std::vector<double>& radii_in) {
  const std::vector<double> radii = finite_sorted(radii_in);
  const std::vector<SizeClass> classes = fit_classes(d);
  const std::vector<double> sums = class_sums(classes, radii);
  DistributionFit fit = fit_of_classes(d, classes, sums);
  const double n = static_cast<double>(radii.size());
  if (by_ks(d)) {
    fit.distance = radii.empty() ? 1 : 0;
    for (size_t i = 0; i < radii.size(); ++i)
      fit.distance = std::max(fit.distance, ks_terms(d, radii[i], static_cast<double>(i), n));
  }
  if (n > 0) {
    const double mean = sums[2 * classes.size() + 2] / n;
    const std::vector<double> m = deviation_sums(radii, mean);
    set_moments(fit, n, mean, m[0], m[1]);
  }
  return fit;
}

DistributionFit compare_distribution(const RadiusDistribution& d, const std::vector<double>& radii_in,
                                     const ParticleShare& share) {
  if (share.complete()) return compare_distribution(d, radii_in);
  ProcessGroup& group = *share.group;
  const std::vector<double> radii = finite_sorted(radii_in);
  const std::vector<SizeClass> classes = fit_classes(d);
  std::vector<double> sums = class_sums(classes, radii);
  group.sum(sums);
  DistributionFit fit = fit_of_classes(d, classes, sums);
  const double n = sums[2 * classes.size() + 1];
  if (by_ks(d)) fit.distance = n > 0 ? ks_in_parts(d, radii, n, group) : 1;
  if (n > 0) {
    const double mean = sums[2 * classes.size() + 2] / n;
    std::vector<double> deviations = deviation_sums(radii, mean);
    group.sum(deviations);
    set_moments(fit, n, mean, deviations[0], deviations[1]);
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

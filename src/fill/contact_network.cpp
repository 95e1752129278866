// The contact network of a particle set (include/pfill/contact_network.hpp):
// pairs within a gap from a grid of cells over the centres, spheres
// touching the surface from exact closest points.
#include "pfill/contact_network.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "fill/centre_grid.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

void check_gap(double gap_fraction) {
  if (!(gap_fraction >= 0 && gap_fraction <= 1))
    throw Error("contact gap " + std::to_string(gap_fraction) +
                ": give a fraction of the smaller radius in [0, 1] (default 0.02)");
}

}  // namespace

ContactNetwork find_contacts(const ParticleSet& particles, double gap_fraction) {
  check_gap(gap_fraction);
  validate(particles, "particles");
  ContactNetwork net;
  net.gap_fraction = gap_fraction;
  const size_t n = particles.size();
  net.coordination.assign(n, 0);
  if (n < 2) return net;
  double max_r = 0;
  for (double r : particles.radii) max_r = std::max(max_r, r);
  // The farthest centres that can touch: 2 max_r + gap x max_r.
  const CentreGrid grid(particles.positions, (2 + gap_fraction) * max_r * (1 + 1e-12));
  // Each particle's partners above it, in parallel by blocks, then joined in order.
  std::vector<std::vector<PairContact>> per(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 512), [&](const tbb::blocked_range<size_t>& range) {
   for (size_t i = range.begin(); i != range.end(); ++i) {
    const Vec3& p = particles.positions[i];
    const double ri = particles.radii[i];
    std::vector<PairContact>& out = per[i];
    grid.for_near(p, [&](uint32_t j) {
      if (j <= i) return;
      const double rj = particles.radii[j];
      const double gap = length(particles.positions[j] - p) - ri - rj;
      if (gap <= gap_fraction * std::min(ri, rj)) out.push_back({static_cast<uint32_t>(i), j, gap});
    });
    std::sort(out.begin(), out.end(), [](const PairContact& x, const PairContact& y) { return x.b < y.b; });
   }
  });
  size_t total = 0;
  for (const auto& v : per) total += v.size();
  net.pairs.reserve(total);
  for (auto& v : per) {
    for (const PairContact& c : v) {
      net.pairs.push_back(c);
      ++net.coordination[c.a];
      ++net.coordination[c.b];
    }
    std::vector<PairContact>().swap(v);
  }
  return net;
}

void find_wall_contacts(ContactNetwork& net, const ParticleSet& particles, const Boundary& boundary) {
  const size_t n = particles.size();
  std::vector<std::optional<ClosestPoint>> hits(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& range) {
   for (size_t i = range.begin(); i != range.end(); ++i) {
    const double r = particles.radii[i];
    const Vec3& p = particles.positions[i];
    std::optional<ClosestPoint> c = boundary.closest_within(p, r * (1 + net.gap_fraction));
    if (!c) continue;
    // A centre outside the solid crosses the surface by d + r.
    const bool outside = dot(p - c->point, c->normal) > 0;
    const double gap = outside ? -(c->distance + r) : c->distance - r;
    if (gap <= net.gap_fraction * r) hits[i] = c;
   }
  });
  net.wall.clear();
  for (size_t i = 0; i < n; ++i) {
    if (!hits[i]) continue;
    const ClosestPoint& c = *hits[i];
    const Vec3& p = particles.positions[i];
    const bool outside = dot(p - c.point, c.normal) > 0;
    const double r = particles.radii[i];
    net.wall.push_back({static_cast<uint32_t>(i), c.point, c.normal, outside ? -(c.distance + r) : c.distance - r});
  }
}

nlohmann::ordered_json contacts_report_json(const ContactNetwork& net, const ParticleSet& particles,
                                    const Boundary* boundary) {
  nlohmann::ordered_json j;
  const size_t n = particles.size();
  j["gap_fraction"] = net.gap_fraction;
  j["pairs"] = net.pairs.size();
  j["mean_coordination"] = net.mean_coordination();
  double min_gap = 0, max_gap = 0;  // fractions of the smaller radius
  bool first = true, within = true;
  for (const PairContact& c : net.pairs) {
    const double g = c.gap / std::min(particles.radii[c.a], particles.radii[c.b]);
    within = within && g <= net.gap_fraction * (1 + 1e-9);
    if (first || g < min_gap) min_gap = g;
    if (first || g > max_gap) max_gap = g;
    first = false;
  }
  j["smallest_gap"] = min_gap;  // negative: the largest overlap
  j["largest_gap"] = max_gap;
  j["all_within_gap"] = within;
  uint32_t top = 0;
  for (uint32_t c : net.coordination) top = std::max(top, c);
  std::vector<size_t> histogram(n ? top + 1 : 0, 0);
  for (uint32_t c : net.coordination) ++histogram[c];
  j["coordination_histogram"] = histogram;
  if (boundary) {
    j["wall_contacts"] = net.wall.size();
    double mean_r = 0;
    for (double r : particles.radii) mean_r += r;
    mean_r = n ? mean_r / n : 1;
    const std::vector<double> sd = boundary->signed_distance(particles.positions);
    constexpr int kBins = 8;  // depth in radii: [<1], [1,2), ..., [7, inf)
    std::vector<size_t> count(kBins, 0), sum(kBins, 0);
    for (size_t i = 0; i < n; ++i) {
      const double depth = -sd[i] / mean_r;
      const int bin = std::clamp(static_cast<int>(std::floor(depth)), 0, kBins - 1);
      ++count[bin];
      sum[bin] += net.coordination[i];
    }
    nlohmann::ordered_json bins = nlohmann::ordered_json::array();
    for (int b = 0; b < kBins; ++b) {
      if (!count[b]) continue;
      nlohmann::ordered_json e;
      e["depth_from"] = b == 0 ? 0.0 : double(b);  // the centre's distance from the wall, in radii
      e["depth_to"] = b == kBins - 1 ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(double(b + 1));
      e["particles"] = count[b];
      e["mean_coordination"] = double(sum[b]) / count[b];
      bins.push_back(e);
    }
    j["coordination_by_depth"] = bins;
  }
  return j;
}

}  // namespace pfill

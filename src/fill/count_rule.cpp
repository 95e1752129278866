// The count rule (count_rule.hpp): the packing a fill reaches, fitted to
// fills of spot and a sphere at the 0.1% and 5% bounds (measurements in
// docs/fill-figures.md).
#include "pfill/count_rule.hpp"

#include <algorithm>
#include <cmath>

#include "pfill/vec3.hpp"

namespace pfill {
namespace {

// Inclusions (inclusions_of): classes at least this many times the
// commonest class's radius, together at most this share by number and
// this share of the volume (past it the large touch each other, and the
// rcp fit holds again).
constexpr double kInclusionRatio = 4, kInclusionsAtMost = 0.02, kInclusionVolumeAtMost = 0.6;
// Up to this many inclusions expected, the scale gives them a whole number.
constexpr double kWholeInclusionsUpTo = 32;

}  // namespace

double expected_packing(double max_overlap, double wall_share) {
  // (a few spheres in a thin part: the fit says nothing there; 0.3 keeps the radius sensible)
  return std::max(0.3, 0.643 + 0.79 * std::min(max_overlap, 0.05) - 0.19 * wall_share);
}

double expected_fill_count(double volume, double area, double half_rest, double max_overlap,
                           double rest_distance) {
  // With a rest distance past contact (--rest-distance 5 -n 500 gave 771),
  // the spacing spheres (radius half_rest) reach past the wall by
  // half_rest - r, since a centre needs only r of room: they fill the mesh
  // grown by that much; and their spacing gives a little (closest pairs
  // 0.94 of the rest distance): spot at 5 and 10 measured 1.08-1.15 times
  // the count without the factor k. At contact both are 1.
  const double grown = volume + std::max(area, 0.0) * half_rest * (1 - 1 / rest_distance);
  const double k = 1 + 0.15 * (1 - 1 / rest_distance);
  return k * expected_packing(max_overlap, area * half_rest / grown) * grown / sphere_volume(half_rest);
}

double fill_radius_for_count(double volume, double area, size_t count, double max_overlap, double rest_distance) {
  if (!(volume > 0) || count == 0 || !(rest_distance >= 1)) return 0;
  // The packing depends on the radius a little (the wall's share): a few rounds settle it.
  const double n = static_cast<double>(count);
  double r = std::cbrt(3.0 * 0.6 * volume / (4.0 * kPi * n));
  if (rest_distance == 1) {
    for (int k = 0; k < 6; ++k)
      r = std::cbrt(3.0 * expected_packing(max_overlap, std::max(area, 0.0) * r / volume) * volume / (4.0 * kPi * n));
    return r;
  }
  double half_rest = r;  // the spacing's radius
  for (int k = 0; k < 12; ++k)
    half_rest *= std::cbrt(expected_fill_count(volume, area, half_rest, max_overlap, rest_distance) / n);
  return half_rest / rest_distance;
}

double expected_fill_count(double volume, double area, const RadiusDistribution& sizes, double max_overlap) {
  if (!(volume > 0)) return 0;
  const double r = sizes.mean();
  const Inclusions large = inclusions_of(sizes);
  double packing = expected_packing(max_overlap, std::max(area, 0.0) * r / volume) + sizes.rcp_gain();
  if (large.volume_share > 0) {
    // Large spheres in a matrix of small ones: they take y of the solid,
    // v = y phi of the mesh, and the small pack the rest as against a wall
    // that has the large spheres' surface (3 v V / R) besides the mesh's:
    // phi = phi_s / (1 - y (1 - phi_s)). (The rcp fit's skewness term, far
    // outside its range here, gave 0.23 more at 1:10 and a packing of 0.85.)
    packing = 0.6;
    for (int k = 0; k < 6; ++k) {
      const double v = large.volume_share * packing;
      const double wall = (std::max(area, 0.0) + 3 * v * volume / large.radius) * r / (volume * (1 - v));
      const double small = expected_packing(max_overlap, wall);
      packing = small / (1 - large.volume_share * (1 - small));
    }
  }
  return packing * volume / (4.0 / 3.0 * kPi * sizes.mean_cube());
}

Inclusions inclusions_of(const RadiusDistribution& sizes) {
  Inclusions out;
  if (sizes.is_equal()) return out;
  const std::vector<SizeClass> classes = sizes.size_classes();
  size_t commonest = 0;
  for (size_t k = 0; k < classes.size(); ++k)
    if (classes[k].number_share > classes[commonest].number_share) commonest = k;
  double surface = 0;  // volume share over radius, summed
  for (const SizeClass& c : classes)
    if (c.lo >= kInclusionRatio * classes[commonest].hi) {
      out.number_share += c.number_share;
      out.volume_share += c.volume_share;
      surface += c.volume_share / (0.5 * (c.lo + c.hi));
    }
  if (out.number_share > kInclusionsAtMost || out.volume_share > kInclusionVolumeAtMost || !(surface > 0)) return {};
  out.radius = out.volume_share / surface;
  return out;
}

double fill_scale_for_count(double volume, double area, size_t count, const RadiusDistribution& sizes,
                            double max_overlap) {
  if (!(volume > 0) || count == 0) return 0;
  // The count goes as the scale^-3, but for the wall's share: a few rounds settle it.
  auto scale_for = [&](double n) {
    double s = 1;
    for (int k = 0; k < 8; ++k) s *= std::cbrt(expected_fill_count(volume, area, sizes.scaled(s), max_overlap) / n);
    return s;
  };
  const double s = scale_for(static_cast<double>(count));
  // A handful of large spheres: the count that gives them a whole number,
  // so that their volume share is the one asked (at -n 750, 1:4 with 30%
  // of the volume large expects 4.99 of them; 5 or 6 placed is 30% or 36%).
  const Inclusions large = inclusions_of(sizes);
  if (large.number_share <= 0) return s;
  const double expected = large.number_share * expected_fill_count(volume, area, sizes.scaled(s), max_overlap);
  if (expected > kWholeInclusionsUpTo) return s;
  return scale_for(std::max(1.0, std::round(expected)) / large.number_share);
}

}  // namespace pfill

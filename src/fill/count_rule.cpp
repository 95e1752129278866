// The count rule (count_rule.hpp): the packing a fill reaches, fitted to
// fills of spot and a sphere at the 0.1% and 5% bounds (measurements in
// docs/fill-figures.md).
#include "pfill/count_rule.hpp"

#include <algorithm>
#include <cmath>

#include "pfill/vec3.hpp"

namespace pfill {

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
  const double packing = expected_packing(max_overlap, std::max(area, 0.0) * r / volume) + sizes.rcp_gain();
  return packing * volume / (4.0 / 3.0 * kPi * sizes.mean_cube());
}

double fill_scale_for_count(double volume, double area, size_t count, const RadiusDistribution& sizes,
                            double max_overlap) {
  if (!(volume > 0) || count == 0) return 0;
  // The count goes as the scale^-3, but for the wall's share: a few rounds settle it.
  double s = 1;
  for (int k = 0; k < 8; ++k)
    s *= std::cbrt(expected_fill_count(volume, area, sizes.scaled(s), max_overlap) / static_cast<double>(count));
  return s;
}

}  // namespace pfill

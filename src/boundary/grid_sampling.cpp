// Host-side trilinear sampling of a ScalarGrid and its analytic gradient.
#include <algorithm>
#include <cmath>
#include <string>

#include "pfill/error.hpp"
#include "pfill/sdf.hpp"

namespace pfill {
namespace {

// Where p falls: its cell, the fractions within it, and the offset from the
// grid box when p lies outside it.
struct CellPosition {
  int i[3];
  double f[3];
  Vec3 outside;
};

CellPosition locate(const ScalarGrid& grid, const Vec3& p) {
  if (grid.dims[0] < 2 || grid.dims[1] < 2 || grid.dims[2] < 2 || !(grid.spacing > 0) ||
      grid.values.size() != size_t(grid.dims[0]) * grid.dims[1] * grid.dims[2])
    throw Error("signed distance field: the grid is empty or inconsistent; build it with build_signed_distance_field");
  if (!is_finite(p)) throw Error("signed distance field: sampled at a non-finite point");
  CellPosition c;
  for (int a = 0; a < 3; ++a) {
    const double t = (p[a] - grid.origin[a]) / grid.spacing;
    const double last = grid.dims[a] - 1;
    const double clamped = std::clamp(t, 0.0, last);
    c.outside[a] = (t - clamped) * grid.spacing;
    c.i[a] = std::min(static_cast<int>(std::floor(clamped)), grid.dims[a] - 2);
    c.f[a] = clamped - c.i[a];
  }
  return c;
}

// The 8 values of the cell, x fastest.
std::array<double, 8> cell_values(const ScalarGrid& grid, const CellPosition& c) {
  std::array<double, 8> v;
  for (int n = 0; n < 8; ++n) v[n] = grid.at(c.i[0] + (n & 1), c.i[1] + ((n >> 1) & 1), c.i[2] + ((n >> 2) & 1));
  return v;
}

double lerp(double a, double b, double t) { return a + (b - a) * t; }

}  // namespace

double sample(const ScalarGrid& grid, const Vec3& p) {
  const CellPosition c = locate(grid, p);
  const auto v = cell_values(grid, c);
  const double x00 = lerp(v[0], v[1], c.f[0]), x10 = lerp(v[2], v[3], c.f[0]);
  const double x01 = lerp(v[4], v[5], c.f[0]), x11 = lerp(v[6], v[7], c.f[0]);
  const double value = lerp(lerp(x00, x10, c.f[1]), lerp(x01, x11, c.f[1]), c.f[2]);
  return value + length(c.outside);
}

Vec3 gradient(const ScalarGrid& grid, const Vec3& p) {
  const CellPosition c = locate(grid, p);
  const auto v = cell_values(grid, c);
  const double fx = c.f[0], fy = c.f[1], fz = c.f[2];
  // Differences along one axis, interpolated bilinearly in the other two.
  const double gx = lerp(lerp(v[1] - v[0], v[3] - v[2], fy), lerp(v[5] - v[4], v[7] - v[6], fy), fz);
  const double gy = lerp(lerp(v[2] - v[0], v[3] - v[1], fx), lerp(v[6] - v[4], v[7] - v[5], fx), fz);
  const double gz = lerp(lerp(v[4] - v[0], v[5] - v[1], fx), lerp(v[6] - v[2], v[7] - v[3], fx), fy);
  Vec3 g = Vec3(gx, gy, gz) / grid.spacing;
  // Outside the box, sample() adds |p - nearest box point|: its gradient
  // replaces the components along the axes where p is out.
  const double out = length(c.outside);
  if (out > 0)
    for (int a = 0; a < 3; ++a)
      if (c.outside[a] != 0) g[a] = c.outside[a] / out;
  return g;
}

}  // namespace pfill

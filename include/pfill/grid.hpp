/// @file grid.hpp
/// @brief A regular 3D grid of float samples, the form in which the signed
/// distance field travels from the boundary (Embree side) to the engine
/// (OpenCL side); neither side needs the other's headers.
#pragma once
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

/// Samples at origin + spacing * (i, j, k), i fastest:
/// values[i + nx * (j + ny * k)]. Ready to upload as one OpenCL buffer or
/// as a 3D image of CL_R / CL_FLOAT.
struct ScalarGrid {
  Vec3 origin;
  double spacing = 0;
  std::array<int, 3> dims{0, 0, 0};  ///< nx, ny, nz
  std::vector<float> values;

  size_t index(int i, int j, int k) const {
    return static_cast<size_t>(i) +
           static_cast<size_t>(dims[0]) * (static_cast<size_t>(j) + static_cast<size_t>(dims[1]) * k);
  }
  float at(int i, int j, int k) const { return values[index(i, j, k)]; }
  Vec3 point(int i, int j, int k) const { return origin + Vec3(i, j, k) * spacing; }
  size_t size() const { return values.size(); }
  size_t bytes() const { return values.size() * sizeof(float); }
  Vec3 upper() const {
    return origin + Vec3(dims[0] - 1, dims[1] - 1, dims[2] - 1) * spacing;
  }
};

/// `distance` (any callable Vec3 -> double, e.g. an analytic signed
/// distance) sampled at `spacing` over [-extent, extent]^3, plus two
/// samples a side.
template <typename Distance>
ScalarGrid sampled_grid(double extent, double spacing, Distance distance) {
  ScalarGrid g;
  const int n = static_cast<int>(std::ceil(2 * extent / spacing)) + 5;
  g.spacing = spacing;
  g.origin = Vec3(-1, -1, -1) * (extent + 2 * spacing);
  g.dims = {n, n, n};
  g.values.resize(static_cast<size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) g.values[g.index(i, j, k)] = static_cast<float>(distance(g.point(i, j, k)));
  return g;
}

}  // namespace pfill

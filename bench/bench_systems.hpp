// The systems the engine benchmarks step (bench_step, bench_variants):
// spheres of radius kRadius on an FCC lattice at packing kPacking in a
// walled box, and the sampled fields of their walls.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "pfill/engine/engine.hpp"
#include "pfill/grid.hpp"

namespace bench {

using namespace pfill;

constexpr double kRadius = 0.5;
constexpr double kPacking = 0.6;

// The SDF of the box [-h, h]^3 sampled at `spacing`.
inline ScalarGrid box_field(double h, double spacing) {
  return sampled_grid(h, spacing, [h](const Vec3& p) {
    const Vec3 q{std::fabs(p.x) - h, std::fabs(p.y) - h, std::fabs(p.z) - h};
    const Vec3 out{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
    return length(out) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0);
  });
}

// N spheres of radius 0.5 on an FCC lattice filling a box at packing 0.6
// (nearest neighbours 1.07 apart: no overlap), small random velocities.
// Returns the box half-size.
inline double fcc_system(size_t n, std::vector<Particle>& out) {
  const double volume = n * (4.0 / 3.0) * M_PI * std::pow(kRadius, 3) / kPacking;
  const double side = std::cbrt(volume);
  const int cells = static_cast<int>(std::ceil(std::cbrt(n / 4.0)));
  const double a = side / cells;  // FCC cell edge
  const double h = side / 2 + kRadius;  // walls one radius beyond the lattice's outer centres
  std::mt19937 rng(42);
  std::uniform_real_distribution<double> vel(-0.5, 0.5);
  const double basis[4][3] = {{0, 0, 0}, {0.5, 0.5, 0}, {0.5, 0, 0.5}, {0, 0.5, 0.5}};
  out.clear();
  for (int k = 0; k < cells && out.size() < n; ++k)
    for (int j = 0; j < cells && out.size() < n; ++j)
      for (int i = 0; i < cells && out.size() < n; ++i)
        for (const auto& b : basis) {
          if (out.size() >= n) break;
          Particle p;
          p.position = Vec3(i + b[0] + 0.25, j + b[1] + 0.25, k + b[2] + 0.25) * a - Vec3(1, 1, 1) * (side / 2);
          p.velocity = {vel(rng), vel(rng), vel(rng)};
          p.radius = kRadius;
          out.push_back(p);
        }
  return h;
}

// `base` (the command line's tuning) for spheres of kRadius, restitution 0.5.
inline EngineParams sphere_params(EngineParams base, bool field_image) {
  base.field_image = field_image;
  base.radius = kRadius;
  base.restitution = 0.5;
  base.wall_restitution = 0.5;
  return base;
}

}  // namespace bench

// Finding holes in a packing that can take another sphere.
#include "pfill/voids.hpp"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

#include "fill/centre_grid.hpp"

namespace pfill {
namespace {

/// Trilinear sample of `g` at p (clamped to the grid's box).
double sample(const ScalarGrid& g, const Vec3& p) {
  const Vec3 q = (p - g.origin) / g.spacing;
  const double gx = std::clamp(q.x, 0.0, g.dims[0] - 1.0), gy = std::clamp(q.y, 0.0, g.dims[1] - 1.0),
               gz = std::clamp(q.z, 0.0, g.dims[2] - 1.0);
  const int i = std::min(static_cast<int>(gx), g.dims[0] - 2), j = std::min(static_cast<int>(gy), g.dims[1] - 2),
            k = std::min(static_cast<int>(gz), g.dims[2] - 2);
  const double tx = gx - i, ty = gy - j, tz = gz - k;
  auto lerp = [](double a, double b, double t) { return a + (b - a) * t; };
  const double a00 = lerp(g.at(i, j, k), g.at(i + 1, j, k), tx), a10 = lerp(g.at(i, j + 1, k), g.at(i + 1, j + 1, k), tx);
  const double a01 = lerp(g.at(i, j, k + 1), g.at(i + 1, j, k + 1), tx),
               a11 = lerp(g.at(i, j + 1, k + 1), g.at(i + 1, j + 1, k + 1), tx);
  return lerp(lerp(a00, a10, ty), lerp(a01, a11, ty), tz);
}

}  // namespace

std::vector<Vec3> find_holes(const ParticleSet& particles, const ScalarGrid& sdf, double radius, double clearance,
                             size_t limit) {
  std::vector<Vec3> holes;
  const double reach = clearance;  // nearest centres beyond the clearance do not matter
  CentreGrid grid(particles.positions, reach);
  auto centre = [&](uint32_t id) { return id < particles.size() ? particles.positions[id] : holes[id - particles.size()]; };
  auto nearest = [&](const Vec3& p) {
    double d = reach;
    grid.for_near(p, [&](uint32_t id) { d = std::min(d, length(centre(id) - p)); });
    return d;
  };
  // Grid points whose nearest centre is within the grid's reach of the clearance ...
  const double miss = std::sqrt(3.0) * 0.5 * sdf.spacing;  // farthest a point lies from the nearest grid point
  struct Candidate {
    Vec3 p;
    double d;
  };
  const double least = std::max(0.0, clearance - miss);
  const double surely_near2 = least * least * (1 - 1e-9);  // a centre closer than this: d < clearance - miss
  std::vector<std::vector<Candidate>> slices(static_cast<size_t>(std::max(0, sdf.dims[2])));
  tbb::parallel_for(0, sdf.dims[2], [&](int k) {  // (no hole is taken yet: `nearest` only reads)
    for (int j = 0; j < sdf.dims[1]; ++j)
      for (int i = 0; i < sdf.dims[0]; ++i) {
        if (-sdf.at(i, j, k) < radius) continue;
        const Vec3 p = sdf.point(i, j, k);
        // Most points have a centre well within the clearance: one found ends the search.
        if (grid.any_near(p, [&](uint32_t id) {
              const Vec3 v = particles.positions[id] - p;
              return dot(v, v) < surely_near2;
            }))
          continue;
        const double d = nearest(p);
        if (d >= clearance - miss) slices[static_cast<size_t>(k)].push_back({p, d});
      }
  });
  std::vector<Candidate> cands;
  for (const auto& slice : slices) cands.insert(cands.end(), slice.begin(), slice.end());
  std::stable_sort(cands.begin(), cands.end(), [](const Candidate& a, const Candidate& b) { return a.d > b.d; });
  // ... climbed to where the nearest centre is farthest (staying r deep), and
  // taken, largest first, where that reaches the clearance.
  static const Vec3 dirs[] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1},
                              {1, 1, 1}, {1, 1, -1}, {1, -1, 1}, {1, -1, -1}, {-1, 1, 1}, {-1, 1, -1},
                              {-1, -1, 1}, {-1, -1, -1}};
  uint32_t next_id = static_cast<uint32_t>(particles.size());
  for (const Candidate& c : cands) {
    if (holes.size() >= limit) break;
    Vec3 p = c.p;
    double d = nearest(p);
    if (d < clearance - miss) continue;  // a hole taken since
    for (double step = 0.5 * sdf.spacing; step > 0.005 * radius;) {
      bool moved = false;
      for (const Vec3& dir : dirs) {
        const Vec3 q = p + dir * (step / length(dir));
        const double dq = nearest(q);
        if (dq > d && -sample(sdf, q) >= radius) {
          p = q;
          d = dq;
          moved = true;
        }
      }
      if (!moved) step *= 0.5;
    }
    if (d < clearance) continue;
    holes.push_back(p);
    grid.insert(p, next_id++);
  }
  return holes;
}

}  // namespace pfill

// Boundary particles on a mesh's surface (include/pfill/surface_sampling.hpp):
// sample elimination to the hexagonal count, tangential relaxation with
// projection back to the surface, and the shell's figures.
#include "pfill/surface_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <random>
#include <string>
#include <unordered_map>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "pfill/error.hpp"

namespace pfill {
namespace {

// Points in a hash of cubic cells.
class PointGrid {
 public:
  PointGrid(const std::vector<Vec3>& points, double cell) : points_(points), inv_(1.0 / cell) {
    cells_.reserve(points.size());
    for (size_t i = 0; i < points.size(); ++i) cells_[key(cell_of(points[i]))].push_back(static_cast<uint32_t>(i));
  }

  // f(j) for the points in the cells within `ring` cells of p's.
  template <class F>
  void for_near(const Vec3& p, int ring, F&& f) const {
    const auto c = cell_of(p);
    for (int64_t dz = -ring; dz <= ring; ++dz)
      for (int64_t dy = -ring; dy <= ring; ++dy)
        for (int64_t dx = -ring; dx <= ring; ++dx) {
          auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (uint32_t j : it->second) f(j);
        }
  }

  // The nearest point to p other than `skip` (distance, index); infinity when there is none.
  std::pair<double, uint32_t> nearest(const Vec3& p, uint32_t skip = UINT32_MAX) const {
    double best = std::numeric_limits<double>::infinity();
    uint32_t at = UINT32_MAX;
    for (int ring = 1; ring <= 3; ++ring) {
      for_near(p, ring, [&](uint32_t j) {
        if (j == skip) return;
        const double d = length(points_[j] - p);
        if (d < best) best = d, at = j;
      });
      if (best <= ring / inv_) return {best, at};  // nothing farther out can be nearer
    }
    for (uint32_t j = 0; j < points_.size(); ++j) {  // sparse: all of them
      if (j == skip) continue;
      const double d = length(points_[j] - p);
      if (d < best) best = d, at = j;
    }
    return {best, at};
  }

 private:
  std::array<int64_t, 3> cell_of(const Vec3& p) const {
    return {static_cast<int64_t>(std::floor(p.x * inv_)), static_cast<int64_t>(std::floor(p.y * inv_)),
            static_cast<int64_t>(std::floor(p.z * inv_))};
  }
  static uint64_t key(const std::array<int64_t, 3>& c) {
    return (static_cast<uint64_t>(c[0] & 0x1FFFFF) << 42) | (static_cast<uint64_t>(c[1] & 0x1FFFFF) << 21) |
           static_cast<uint64_t>(c[2] & 0x1FFFFF);
  }
  const std::vector<Vec3>& points_;
  double inv_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

double triangle_area(const Mesh& m, const Triangle& t) {
  return 0.5 * length(cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
}

// Opposite sides of a thin part (normals facing away) do not count as neighbours.
constexpr double kSameSide = -0.3;
// The relaxation's repulsion: (1 - d / h)^2 out to h = kRelaxReach x 2R,
// which reaches a hexagonal layer's first ring (2R) and not its second
// (3.46 R). (Measured on spot at 5,000: springs to 2R alone left holes of
// 1.5-1.7 R; reach 1.6-1.7 x 2R jammed tighter.)
constexpr double kRelaxReach = 1.4;
// The count: 97% of a hexagonal layer's, A / (sqrt(3)/2 (2R)^2). A
// disordered layer at the full count jams below 2R (spot, 5,000: nearest
// neighbours at 0.92 x 2R on average, 96.6% within 15%); at 97% 0.94 x 2R,
// 99.4%, and coverage 1.38 R.
constexpr double kDensity = 0.97;
constexpr double kClosest = 0.8;
// A hole: a surface point this many R from every particle (spot, 5,000,
// seeds 1-3: coverage 1.38-1.49 R; at 1.25 R the fills crowded, 96-97.5%
// of nearest neighbours within 15%, coverage 1.46-1.62 R).
constexpr double kHole = 1.4;
constexpr double kRelaxStep = 0.6;  // displacement per round: this x 2R x the summed repulsion

}  // namespace

double surface_radius_for_count(double area, size_t count) {
  if (!(area > 0) || count == 0) return 0;
  return 0.5 * std::sqrt(kDensity * area / (static_cast<double>(count) * std::sqrt(3.0) / 2));
}

SurfaceSamples sample_surface(const Boundary& boundary, const SurfaceSamplingOptions& o) {
  const Mesh& mesh = boundary.mesh();
  if (!(o.radius > 0) || !std::isfinite(o.radius))
    throw Error("surface particles: give a radius > 0 (-r), not " + std::to_string(o.radius));
  SurfaceSamples out;
  out.radius = o.radius;
  const size_t triangles = mesh.triangles.size();
  std::vector<double> cumulative(triangles);
  double area = 0;
  for (size_t t = 0; t < triangles; ++t) cumulative[t] = area += triangle_area(mesh, mesh.triangles[t]);
  out.surface_area = area;
  const double s = 2 * o.radius;
  const double count_real = kDensity * area / (std::sqrt(3.0) / 2 * s * s);
  if (!(count_real <= 1e8))
    throw Error("surface particles: a radius of " + std::to_string(o.radius) + " gives about " +
                std::to_string(count_real) + " particles on this surface; choose a larger radius");
  const size_t n = std::max<size_t>(1, static_cast<size_t>(std::llround(count_real)));
  if (!(area > 0)) return out;

  // Candidates uniform by area.
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const size_t m = n * static_cast<size_t>(std::max(2, o.candidates_per_particle));
  std::vector<Vec3> cand(m), cand_normal(m);
  const double orient = boundary.inward_oriented() ? -1.0 : 1.0;
  for (size_t k = 0; k < m; ++k) {
    const size_t t = std::min<size_t>(
        triangles - 1, std::upper_bound(cumulative.begin(), cumulative.end(), unit(rng) * area) - cumulative.begin());
    const Triangle& tri = mesh.triangles[t];
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
    cand[k] = a + (b - a) * u + (c - a) * v;
    cand_normal[k] = normalize(cross(b - a, c - a)) * orient;
  }

  // Sample elimination (Yuksel 2015) down to n.
  {
    const double r_max = std::sqrt(area / (2 * std::sqrt(3.0) * static_cast<double>(n)));
    const double reach = 2 * r_max;
    const PointGrid grid(cand, reach);
    std::vector<std::vector<std::pair<uint32_t, float>>> near(m);
    std::vector<double> weight(m, 0);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, m, 1024), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        grid.for_near(cand[i], 1, [&](uint32_t j) {
          if (j == i || dot(cand_normal[i], cand_normal[j]) < kSameSide) return;
          const double d = length(cand[j] - cand[i]);
          if (d >= reach) return;
          const float w = static_cast<float>(std::pow(1 - d / reach, 8));
          near[i].push_back({j, w});
          weight[i] += w;
        });
      }
    });
    std::vector<uint8_t> alive(m, 1);
    std::priority_queue<std::pair<double, uint32_t>> heap;
    for (size_t i = 0; i < m; ++i) heap.push({weight[i], static_cast<uint32_t>(i)});
    size_t left = m;
    while (left > n && !heap.empty()) {
      const auto [w, i] = heap.top();
      heap.pop();
      if (!alive[i] || w != weight[i]) continue;  // stale
      alive[i] = 0;
      --left;
      for (const auto& [j, wj] : near[i]) {
        if (!alive[j]) continue;
        weight[j] -= wj;
        heap.push({weight[j], j});
      }
    }
    for (size_t i = 0; i < m; ++i)
      if (alive[i]) out.positions.push_back(cand[i]), out.normals.push_back(cand_normal[i]);
  }

  // Where the surface is sharper than the spacing (the tip of a horn), the
  // projection can pile particles onto one vertex: of a pair closer than
  // kClosest x 2R the one with more close neighbours goes.
  auto thin_out = [&] {
    const size_t count = out.positions.size();
    const PointGrid grid(out.positions, s);
    std::vector<uint32_t> crowd(count, 0);
    for (size_t i = 0; i < count; ++i)
      grid.for_near(out.positions[i], 1, [&](uint32_t j) {
        if (j != i && length(out.positions[j] - out.positions[i]) < kClosest * s) ++crowd[i];
      });
    std::vector<uint8_t> gone(count, 0);
    for (size_t i = 0; i < count; ++i) {
      if (!crowd[i] || gone[i]) continue;
      grid.for_near(out.positions[i], 1, [&](uint32_t j) {
        if (gone[i] || j == i || gone[j] || length(out.positions[j] - out.positions[i]) >= kClosest * s) return;
        // The pair becomes one particle between them (covering what both did).
        const uint32_t loser = crowd[j] > crowd[i] || (crowd[j] == crowd[i] && j > i) ? j : static_cast<uint32_t>(i);
        const uint32_t keeper = loser == j ? static_cast<uint32_t>(i) : j;
        const ClosestPoint cp = boundary.closest((out.positions[i] + out.positions[j]) * 0.5);
        out.positions[keeper] = cp.point, out.normals[keeper] = cp.normal;
        gone[loser] = 1;
      });
    }
    size_t kept = 0;
    for (size_t i = 0; i < count; ++i)
      if (!gone[i]) out.positions[kept] = out.positions[i], out.normals[kept] = out.normals[i], ++kept;
    out.positions.resize(kept);
    out.normals.resize(kept);
  };
  // A particle where a surface point is farther than kHole R from all of
  // them (a scan at spacing R/2 over every triangle), the farthest first.
  auto fill_holes = [&] {
    const PointGrid grid(out.positions, s);
    std::vector<std::pair<double, Vec3>> holes;
    const double step = 0.5 * o.radius;
    for (const Triangle& tri : mesh.triangles) {
      const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
      const double longest = std::max({length(b - a), length(c - b), length(a - c)});
      const int k = std::clamp(static_cast<int>(std::ceil(longest / step)), 1, 2000);
      for (int i = 0; i <= k; ++i)
        for (int j = 0; i + j <= k; ++j) {
          const Vec3 p = a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k);
          const double d = grid.nearest(p).first;
          if (d > kHole * o.radius) holes.push_back({d, p});
        }
    }
    std::sort(holes.begin(), holes.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
    std::vector<Vec3> added;
    for (const auto& [d, p] : holes) {
      bool near = false;
      for (const Vec3& q : added) near = near || length(q - p) <= kHole * o.radius;
      if (near) continue;
      added.push_back(p);
      const ClosestPoint cp = boundary.closest(p);
      out.positions.push_back(cp.point);
      out.normals.push_back(cp.normal);
    }
  };
  // Tangential relaxation: springs to the spacing s, moves in the tangent plane, projection back.
  std::vector<Vec3> moved;
  const double reach = kRelaxReach * s;
  for (int it = 0; it < o.relax_iterations; ++it) {
    if (it == o.relax_iterations * 3 / 4) {  // the rounds left settle the changes
      thin_out();
      fill_holes();
    }
    const size_t count = out.positions.size();
    moved.resize(count);
    const PointGrid grid(out.positions, reach);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const Vec3 p = out.positions[i], nrm = out.normals[i];
        Vec3 f;
        grid.for_near(p, 1, [&](uint32_t j) {
          if (j == i || dot(nrm, out.normals[j]) < kSameSide) return;
          const Vec3 d = p - out.positions[j];
          const double l = length(d);
          if (l >= reach) return;
          const double w = (1 - l / reach) * (1 - l / reach);
          f = f + (l > 1e-12 * s ? d * (w / l) : Vec3(w, 0, 0));
        });
        f = f - nrm * dot(f, nrm);
        f = f * (kRelaxStep * s);
        const double fl = length(f);
        if (fl > 0.25 * s) f = f * (0.25 * s / fl);
        moved[i] = p + f;
      }
    });
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 128), [&](const tbb::blocked_range<size_t>& range) {
      for (size_t i = range.begin(); i != range.end(); ++i) {
        const std::optional<ClosestPoint> c = boundary.closest_within(moved[i], s);
        const ClosestPoint cp = c ? *c : boundary.closest(moved[i]);
        out.positions[i] = cp.point;
        out.normals[i] = cp.normal;
      }
    });
  }
  thin_out();
  // The areas: each particle's share of the surface (its Voronoi cell on it).
  out.areas = measure_shell(boundary, out.positions, o.radius, 2).areas;
  return out;
}

ShellStats measure_shell(const Boundary& boundary, const std::vector<Vec3>& positions, double radius,
                         double density) {
  ShellStats st;
  st.count = positions.size();
  st.spacing = 2 * radius;
  st.areas.assign(positions.size(), 0.0);
  if (positions.empty() || !(radius > 0)) return st;
  const PointGrid grid(positions, 2 * radius);

  // Nearest neighbours.
  std::vector<double> nn(positions.size());
  std::vector<double> off(positions.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      nn[i] = grid.nearest(positions[i], static_cast<uint32_t>(i)).first;
      off[i] = boundary.closest(positions[i]).distance;
    }
  });
  double sum = 0;
  size_t within = 0, finite = 0;
  st.nn_min = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < nn.size(); ++i) {
    st.largest_off_surface = std::max(st.largest_off_surface, off[i]);
    if (!std::isfinite(nn[i])) continue;
    ++finite;
    sum += nn[i];
    st.nn_min = std::min(st.nn_min, nn[i]);
    st.nn_max = std::max(st.nn_max, nn[i]);
    if (std::abs(nn[i] - st.spacing) <= 0.15 * st.spacing) ++within;
    if (nn[i] < 0.8 * st.spacing) ++st.closer_than_08;
  }
  st.nn_mean = finite ? sum / finite : 0;
  if (!finite) st.nn_min = 0;
  st.share_within_15 = static_cast<double>(within) / positions.size();

  // Coverage and areas: a regular grid of points on each triangle, k
  // intervals a side, each point standing for its share of the k^2 small triangles.
  const Mesh& mesh = boundary.mesh();
  const double step = radius / std::max(density, 0.25);
  struct Local {
    std::vector<double> areas;
    double coverage = 0;
    Vec3 at;
    size_t points = 0;
  };
  tbb::enumerable_thread_specific<Local> locals([&] { return Local{std::vector<double>(positions.size(), 0.0), 0, {}, 0}; });
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.triangles.size(), 16), [&](const tbb::blocked_range<size_t>& r) {
    Local& local = locals.local();
    for (size_t t = r.begin(); t != r.end(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
      const double longest = std::max({length(b - a), length(c - b), length(a - c)});
      const int k = std::clamp(static_cast<int>(std::ceil(longest / step)), 1, 2000);
      const double small = triangle_area(mesh, tri) / (static_cast<double>(k) * k);
      for (int i = 0; i <= k; ++i)
        for (int j = 0; i + j <= k; ++j) {
          const int l = k - i - j;
          // Small triangles around the point: 6 inside, 3 on an edge, 1 at a corner.
          const int zeros = (i == 0) + (j == 0) + (l == 0);
          const double incident = zeros == 0 ? 6 : (zeros == 1 ? 3 : 1);
          const Vec3 p = a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k);
          const auto [d, at] = grid.nearest(p);
          if (d > local.coverage) local.coverage = d, local.at = p;
          ++local.points;
          if (at != UINT32_MAX) local.areas[at] += incident / 3.0 * small;
        }
    }
  });
  for (const Local& local : locals) {
    if (local.coverage > st.coverage) st.coverage = local.coverage, st.least_covered = local.at;
    st.surface_points += local.points;
    for (size_t i = 0; i < positions.size(); ++i) st.areas[i] += local.areas[i];
  }
  st.coverage_over_r = st.coverage / radius;
  return st;
}

}  // namespace pfill

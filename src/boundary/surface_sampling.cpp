// Boundary particles on a mesh's surface (include/pfill/surface_sampling.hpp):
// sample elimination to the hexagonal count, tangential relaxation with
// projection back to the surface, and the shell's figures.
#include "pfill/surface_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <random>
#include <string>
#include <tuple>

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "boundary/point_grid.hpp"
#include "boundary/surface_walk.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

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
  std::vector<uint32_t> cand_triangle(m);
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
    cand_triangle[k] = static_cast<uint32_t>(t);
  }

  // Sample elimination (Yuksel 2015) down to n.
  std::vector<uint32_t> triangle;  // each particle's, where the relaxation's walk starts
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
          const double w2 = (1 - d / reach) * (1 - d / reach), w4 = w2 * w2;
          const float w = static_cast<float>(w4 * w4);  // (1 - d / reach)^8
          near[i].push_back({j, w});
          weight[i] += w;
        });
      }
    });
    // A max-heap of the candidates by (weight, index) with each one's place
    // in it: a neighbour's weight only falls, so it sifts down in place (a
    // queue of stale copies grew to 20 entries per candidate).
    std::vector<uint8_t> alive(m, 1);
    std::vector<uint32_t> heap(m), place(m);
    auto above = [&](uint32_t a, uint32_t b) { return weight[a] > weight[b] || (weight[a] == weight[b] && a > b); };
    auto sift_down = [&](size_t at) {
      const uint32_t item = heap[at];
      for (;;) {
        size_t child = 2 * at + 1;
        if (child >= heap.size()) break;
        if (child + 1 < heap.size() && above(heap[child + 1], heap[child])) ++child;
        if (!above(heap[child], item)) break;
        heap[at] = heap[child], place[heap[at]] = static_cast<uint32_t>(at);
        at = child;
      }
      heap[at] = item, place[item] = static_cast<uint32_t>(at);
    };
    for (size_t i = 0; i < m; ++i) heap[i] = static_cast<uint32_t>(i);
    for (size_t at = m / 2; at-- > 0;) sift_down(at);
    for (size_t left = m; left > n; --left) {
      const uint32_t i = heap[0];
      alive[i] = 0;
      heap[0] = heap.back();
      heap.pop_back();
      if (!heap.empty()) sift_down(0);
      for (const auto& [j, wj] : near[i]) {
        if (!alive[j]) continue;
        weight[j] -= wj;
        sift_down(place[j]);
      }
    }
    for (size_t i = 0; i < m; ++i)
      if (alive[i]) {
        out.positions.push_back(cand[i]);
        out.normals.push_back(cand_normal[i]);
        triangle.push_back(cand_triangle[i]);
      }
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
        out.positions[keeper] = cp.point, out.normals[keeper] = cp.normal, triangle[keeper] = cp.triangle;
        gone[loser] = 1;
      });
    }
    size_t kept = 0;
    for (size_t i = 0; i < count; ++i)
      if (!gone[i]) {
        out.positions[kept] = out.positions[i], out.normals[kept] = out.normals[i], triangle[kept] = triangle[i];
        ++kept;
      }
    out.positions.resize(kept);
    out.normals.resize(kept);
    triangle.resize(kept);
    return count - kept;
  };
  // A particle where a surface point is farther than kHole R from all of
  // them (a scan at spacing R/2 over every triangle), the farthest first.
  auto fill_holes = [&] {
    const PointGrid grid(out.positions, s);
    const double step = 0.5 * o.radius;
    tbb::enumerable_thread_specific<std::vector<std::pair<double, Vec3>>> found;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, triangles, 64), [&](const tbb::blocked_range<size_t>& r) {
      auto& local = found.local();
      for (size_t t = r.begin(); t != r.end(); ++t) {
        const Triangle& tri = mesh.triangles[t];
        const Vec3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
        const double longest = std::max({length(b - a), length(c - b), length(a - c)});
        const int k = std::clamp(static_cast<int>(std::ceil(longest / step)), 1, 2000);
        for (int i = 0; i <= k; ++i)
          for (int j = 0; i + j <= k; ++j) {
            const Vec3 p = a + (b - a) * (double(i) / k) + (c - a) * (double(j) / k);
            const double d = grid.nearest(p).first;
            if (d > kHole * o.radius) local.push_back({d, p});
          }
      }
    });
    std::vector<std::pair<double, Vec3>> holes;
    for (const auto& local : found) holes.insert(holes.end(), local.begin(), local.end());
    // The farthest first; ties by position, so the threads' order does not matter.
    std::sort(holes.begin(), holes.end(), [](const auto& x, const auto& y) {
      if (x.first != y.first) return x.first > y.first;
      return std::tie(x.second.x, x.second.y, x.second.z) < std::tie(y.second.x, y.second.y, y.second.z);
    });
    std::vector<Vec3> added;
    for (const auto& [d, p] : holes) {
      bool near = false;
      for (const Vec3& q : added) near = near || length(q - p) <= kHole * o.radius;
      if (near) continue;
      const ClosestPoint cp = boundary.closest(p);
      // A wall inside another part of a union is no surface: nothing to cover.
      if (cp.distance > 0.25 * o.radius) continue;
      added.push_back(p);
      out.positions.push_back(cp.point);
      out.normals.push_back(cp.normal);
      triangle.push_back(cp.triangle);
    }
    return added.size();
  };
  // Tangential relaxation: springs to the spacing s, moves in the tangent plane, projection back.
  std::vector<Vec3> moved;
  const double reach = kRelaxReach * s;
  // Where the parts of a union overlap, the closest point must skip the
  // surfaces inside other parts: Boundary's search knows them, a walk does not.
  std::optional<SurfaceWalk> walk;
  if (!boundary.union_of_parts()) walk.emplace(mesh, orient);
  // Neighbour lists out to reach + skin, rebuilt once some particle has
  // moved skin / 2 since (two of them closing in then still find each other):
  // most rounds then read a short list instead of probing 27 cells.
  const double skin = 0.3 * s;
  std::vector<uint32_t> first, listed;
  std::vector<Vec3> at_build;
  double moved_most = HUGE_VAL;
  auto build_lists = [&] {
    const size_t count = out.positions.size();
    const PointGrid grid(out.positions, reach + skin);
    first.assign(count + 1, 0);
    auto each = [&](size_t i, auto&& f) {
      grid.for_near(out.positions[i], 1, [&](uint32_t j) {
        if (j != i && length(out.positions[j] - out.positions[i]) < reach + skin) f(j);
      });
    };
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) each(i, [&](uint32_t) { ++first[i + 1]; });
    });
    for (size_t i = 0; i < count; ++i) first[i + 1] += first[i];
    listed.resize(first[count]);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        uint32_t k = first[i];
        each(i, [&](uint32_t j) { listed[k++] = j; });
      }
    });
    at_build = out.positions;
    moved_most = 0;
  };
  auto relax = [&](int rounds) {
    moved_most = HUGE_VAL;  // particles came and went
    for (int it = 0; it < rounds; ++it) {
      const size_t count = out.positions.size();
      moved.resize(count);
      if (moved_most > 0.5 * skin) build_lists();
      tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 256), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          const Vec3 p = out.positions[i], nrm = out.normals[i];
          Vec3 f;
          for (uint32_t k = first[i]; k < first[i + 1]; ++k) {
            const uint32_t j = listed[k];
            if (dot(nrm, out.normals[j]) < kSameSide) continue;
            const Vec3 d = p - out.positions[j];
            const double l = length(d);
            if (l >= reach) continue;
            const double w = (1 - l / reach) * (1 - l / reach);
            f = f + (l > 1e-12 * s ? d * (w / l) : Vec3(w, 0, 0));
          }
          f = f - nrm * dot(f, nrm);
          f = f * (kRelaxStep * s);
          const double fl = length(f);
          if (fl > 0.25 * s) f = f * (0.25 * s / fl);
          moved[i] = p + f;
        }
      });
      tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 128), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i != range.end(); ++i) {
          if (walk && walk->project(moved[i], triangle[i], out.positions[i], out.normals[i])) continue;
          const std::optional<ClosestPoint> c = boundary.closest_within(moved[i], s);
          const ClosestPoint cp = c ? *c : boundary.closest(moved[i]);
          out.positions[i] = cp.point;
          out.normals[i] = cp.normal;
          triangle[i] = cp.triangle;
        }
      });
      for (size_t i = 0; i < count; ++i) moved_most = std::max(moved_most, length(out.positions[i] - at_build[i]));
    }
  };
  // Three quarters of the rounds, then piles merged and holes filled, and
  // the rest to settle. The last merges can open a hole where the surface is
  // sharp (spot's muzzle: 1.56 R): while a check changes something, it is
  // filled and settled again (a tenth of the rounds, at most three times).
  const int settle = std::max(1, o.relax_iterations / 10);
  relax(o.relax_iterations * 3 / 4);
  if (o.relax_iterations > 0) {
    thin_out();
    fill_holes();
    relax(o.relax_iterations - o.relax_iterations * 3 / 4);
  }
  for (int pass = 0;; ++pass) {
    const size_t merged = thin_out();
    if (o.relax_iterations == 0 || pass == 3) break;
    if (merged + fill_holes() == 0) break;
    relax(settle);
  }
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

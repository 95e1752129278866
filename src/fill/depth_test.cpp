// The hole search's depth test (depth_test.hpp).
#include "fill/depth_test.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <tbb/parallel_for.h>

namespace pfill {
namespace {

constexpr uint64_t kAxis = (uint64_t(1) << 21) - 1;
// A bound must clear the test by this share of the depth, against rounding
// (the samples lie within rounding of their triangles; the exact value
// differs from the true one by rounding): never an answer the exact test
// would not give.
constexpr double kMargin = 1e-6;

// Points of the mesh's triangles: their corners, and a lattice about
// `spacing` apart on those wider than that; one per cube of `spacing`
// (a sort, not a hash set: the closed bunny's 35k corners in milliseconds).
std::vector<Vec3> surface_samples(const Mesh& mesh, double spacing) {
  std::vector<std::pair<uint64_t, Vec3>> keyed;
  const double inv = 1 / spacing;
  auto add = [&](const Vec3& p) {
    const auto cell = [&](double v) { return static_cast<uint64_t>(static_cast<int64_t>(std::floor(v * inv)) & 0x1FFFFF); };
    keyed.emplace_back(cell(p.x) << 42 | cell(p.y) << 21 | cell(p.z), p);
  };
  std::vector<char> used(mesh.positions.size(), 0);  // (a vertex no triangle uses is no wall)
  for (const Triangle& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  for (size_t v = 0; v < used.size(); ++v)
    if (used[v]) add(mesh.positions[v]);
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double longest = std::max({length(b - a), length(c - b), length(a - c)});
    const int n = static_cast<int>(std::ceil(longest / spacing));
    for (int i = 0; n > 1 && i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) add(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
  }
  std::stable_sort(keyed.begin(), keyed.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  std::vector<Vec3> out;
  for (size_t i = 0; i < keyed.size(); ++i)
    if (i == 0 || keyed[i].first != keyed[i - 1].first) out.push_back(keyed[i].second);
  return out;
}

}  // namespace

DepthTest::DepthTest(const Boundary& boundary, double depth, const Vec3& lattice_origin, double step)
    : boundary_(boundary), depth_(depth),
      lipschitz_(boundary.closed() && !boundary.overlapping() && !boundary.union_of_parts()),
      origin_(lattice_origin), corner_step_(2 * step) {
  if (boundary.union_of_parts()) return;  // its inner surfaces are no wall: no samples
  samples_ = surface_samples(boundary.mesh(), depth / 2);
  const double limit = depth * (1 - kMargin);
  limit2_ = limit * limit;
  grid_ = CentreGrid(samples_, depth);
}

bool DepthTest::exact(const Vec3& p) const {
  return boundary_.fast_signed_distance(p, std::numeric_limits<double>::infinity()) <= -depth_;
}

uint64_t DepthTest::corner_key(const Vec3& p) const {
  const Vec3 q = (p - origin_) / corner_step_;
  const auto axis = [](double v) { return static_cast<uint64_t>(std::max<int64_t>(0, std::llround(v))) & kAxis; };
  return axis(q.x) | axis(q.y) << 21 | axis(q.z) << 42;
}

Vec3 DepthTest::corner(uint64_t key) const {
  return origin_ + Vec3(static_cast<double>(key & kAxis), static_cast<double>((key >> 21) & kAxis),
                        static_cast<double>(key >> 42)) * corner_step_;
}

void DepthTest::evaluate_corners(std::vector<uint64_t> keys) {
  std::sort(keys.begin(), keys.end());
  keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  keys.erase(std::remove_if(keys.begin(), keys.end(), [&](uint64_t k) { return corners_.count(k) > 0; }), keys.end());
  std::vector<double> values(keys.size());
  tbb::parallel_for(size_t(0), keys.size(), [&](size_t i) {
    values[i] = boundary_.fast_signed_distance(corner(keys[i]), std::numeric_limits<double>::infinity());
  });
  for (size_t i = 0; i < keys.size(); ++i) corners_.emplace(keys[i], values[i]);
}

std::vector<uint8_t> DepthTest::deep(const std::vector<Vec3>& points) {
  constexpr uint8_t kUnknown = 2;
  std::vector<uint8_t> out(points.size());
  tbb::parallel_for(size_t(0), points.size(), [&](size_t i) { out[i] = near_wall(points[i]) ? 0 : kUnknown; });
  if (lipschitz_) {
    std::vector<uint64_t> keys;
    for (size_t i = 0; i < points.size(); ++i)
      if (out[i] == kUnknown) keys.push_back(corner_key(points[i]));
    evaluate_corners(std::move(keys));
  }
  tbb::parallel_for(size_t(0), points.size(), [&](size_t i) {
    if (out[i] != kUnknown) return;
    if (lipschitz_) {
      const uint64_t key = corner_key(points[i]);
      const double bound = corners_.at(key) - length(points[i] - corner(key));  // phi(p) >= phi(c) - |p - c|
      if (bound > -depth_ * (1 - kMargin)) {
        out[i] = 0;
        return;
      }
    }
    out[i] = exact(points[i]);
  });
  return out;
}

}  // namespace pfill

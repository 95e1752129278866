// The hole search's depth test (depth_test.hpp).
#include "fill/depth_test.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace pfill {
namespace {

constexpr uint64_t kAxis = (uint64_t(1) << 21) - 1;
// A bound must clear the test by this share of the depth, against rounding
// (the samples lie within rounding of their triangles; the exact value
// differs from the true one by rounding): never an answer the exact test
// would not give.
constexpr double kMargin = 1e-6;

}  // namespace

DepthTest::DepthTest(const Boundary& boundary, double depth, const Vec3& lattice_origin, double step)
    : boundary_(boundary), depth_(depth),
      lipschitz_(boundary.closed() && !boundary.overlapping() && !boundary.union_of_parts()),
      origin_(lattice_origin), corner_step_(2 * step) {
  if (boundary.union_of_parts()) return;  // its inner surfaces are no wall: no voxels
  mark_wall_voxels(boundary.mesh());
}

// Voxels a sample of the surface lies in: the triangles' corners, and a
// lattice half a voxel apart on those wider than that. A point in such a
// voxel or a face neighbour lies within sqrt(6) voxels of that sample.
void DepthTest::mark_wall_voxels(const Mesh& mesh) {
  voxel_ = depth_ * (1 - kMargin) / std::sqrt(6.0);
  const Box3 box = mesh.bounds();
  voxel_origin_ = box.lo - Vec3(2, 2, 2) * voxel_;
  uint64_t voxels = 1;
  for (int a = 0; a < 3; ++a) {
    voxel_dims_[a] = static_cast<int64_t>((box.hi[a] - box.lo[a]) / voxel_) + 5;
    voxels *= static_cast<uint64_t>(voxel_dims_[a]);
  }
  if (voxels > (uint64_t(1) << 31)) return;  // (256 MiB of bits: the exact test alone)
  wall_.assign(voxels / 64 + 1, 0);
  auto add = [&](const Vec3& p) {
    const int64_t n = voxel_of(p);
    if (n >= 0) wall_[static_cast<uint64_t>(n) >> 6] |= uint64_t(1) << (n & 63);
  };
  for (const Triangle& t : mesh.triangles) {  // (a vertex no triangle uses is no wall)
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double longest = std::max({length(b - a), length(c - b), length(a - c)});
    const int n = std::max(1, static_cast<int>(std::ceil(2 * longest / voxel_)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) add(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
  }
}

int64_t DepthTest::voxel_of(const Vec3& p) const {
  int64_t c[3];
  for (int a = 0; a < 3; ++a) {
    const double v = std::floor((p[a] - voxel_origin_[a]) / voxel_);
    if (!(v >= 0 && v < static_cast<double>(voxel_dims_[a]))) return -1;
    c[a] = static_cast<int64_t>(v);
  }
  return c[0] + voxel_dims_[0] * (c[1] + voxel_dims_[1] * c[2]);
}

bool DepthTest::near_wall(const Vec3& p) const {
  if (wall_.empty()) return false;
  const int64_t n = voxel_of(p);
  if (n < 0) return false;
  const int64_t steps[7] = {0, 1, -1, voxel_dims_[0], -voxel_dims_[0], voxel_dims_[0] * voxel_dims_[1],
                            -voxel_dims_[0] * voxel_dims_[1]};
  for (int64_t d : steps) {  // (the margin of 2 voxels keeps the neighbours of a point near the mesh inside)
    const int64_t m = n + d;
    if (m >= 0 && static_cast<uint64_t>(m) < static_cast<uint64_t>(wall_.size()) * 64 &&
        (wall_[static_cast<uint64_t>(m) >> 6] >> (m & 63)) & 1)
      return true;
  }
  return false;
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

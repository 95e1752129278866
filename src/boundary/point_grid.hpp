// Points in cubic cells for the neighbour queries of the surface sampler and
// the shell's figures (private to src/boundary). The ids are sorted by cell
// and an open-addressing table maps each occupied cell to its run: a rebuild
// each relaxation round costs one sort, and a query probes a flat table
// (a hash map of small vectors spent a third of `pfill surface` in lookups
// and allocations).
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

class PointGrid {
 public:
  PointGrid(const std::vector<Vec3>& points, double cell) : points_(points), inv_(1.0 / cell) {
    const size_t n = points.size();
    std::vector<std::pair<uint64_t, uint32_t>> order(n);
    for (size_t i = 0; i < n; ++i) order[i] = {key(cell_of(points[i])), static_cast<uint32_t>(i)};
    std::sort(order.begin(), order.end());
    ids_.resize(n);
    size_t cells = 0;
    for (size_t i = 0; i < n; ++i) {
      ids_[i] = order[i].second;
      cells += i == 0 || order[i].first != order[i - 1].first;
    }
    size_t size = 16;
    int bits = 4;
    while (size < 2 * cells) size *= 2, ++bits;
    mask_ = size - 1;
    shift_ = 64 - bits;
    keys_.assign(size, kEmpty);
    runs_.resize(size);
    for (size_t i = 0; i < n;) {
      size_t j = i;
      while (j < n && order[j].first == order[i].first) ++j;
      size_t slot = hash(order[i].first);
      while (keys_[slot] != kEmpty) slot = (slot + 1) & mask_;
      keys_[slot] = order[i].first;
      runs_[slot] = {static_cast<uint32_t>(i), static_cast<uint32_t>(j)};
      i = j;
    }
  }

  // f(j) for the points in the cells within `ring` cells of p's.
  template <class F>
  void for_near(const Vec3& p, int ring, F&& f) const {
    const auto c = cell_of(p);
    for (int64_t dz = -ring; dz <= ring; ++dz)
      for (int64_t dy = -ring; dy <= ring; ++dy)
        for (int64_t dx = -ring; dx <= ring; ++dx) {
          const uint64_t k = key({c[0] + dx, c[1] + dy, c[2] + dz});
          for (size_t slot = hash(k); keys_[slot] != kEmpty; slot = (slot + 1) & mask_)
            if (keys_[slot] == k) {
              for (uint32_t at = runs_[slot][0]; at < runs_[slot][1]; ++at) f(ids_[at]);
              break;
            }
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
  static constexpr uint64_t kEmpty = std::numeric_limits<uint64_t>::max();  // no key has all 64 bits set
  std::array<int64_t, 3> cell_of(const Vec3& p) const {
    return {static_cast<int64_t>(std::floor(p.x * inv_)), static_cast<int64_t>(std::floor(p.y * inv_)),
            static_cast<int64_t>(std::floor(p.z * inv_))};
  }
  static uint64_t key(const std::array<int64_t, 3>& c) {
    return (static_cast<uint64_t>(c[0] & 0x1FFFFF) << 42) | (static_cast<uint64_t>(c[1] & 0x1FFFFF) << 21) |
           static_cast<uint64_t>(c[2] & 0x1FFFFF);
  }
  // Fibonacci hashing: the product's top bits, which every bit of the key
  // reaches (its middle bits missed x, so cells in a row along x collided).
  size_t hash(uint64_t k) const { return static_cast<size_t>((k * 0x9E3779B97F4A7C15ull) >> shift_); }

  const std::vector<Vec3>& points_;
  double inv_;
  std::vector<uint32_t> ids_;
  std::vector<uint64_t> keys_;
  std::vector<std::array<uint32_t, 2>> runs_;
  size_t mask_ = 0;
  int shift_ = 60;
};

}  // namespace pfill

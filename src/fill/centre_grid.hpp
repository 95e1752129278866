// A uniform hash grid over sphere centres for neighbour queries on the host
// (metrics, overlap search, void filling). Cells at least as large as the
// query distance, so a query visits the 27 cells around a point.
#pragma once
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

class CentreGrid {
 public:
  explicit CentreGrid(double cell) : inv_(1.0 / cell) {}
  CentreGrid(const std::vector<Vec3>& centres, double cell) : inv_(1.0 / cell) {
    cells_.reserve(centres.size());
    for (size_t i = 0; i < centres.size(); ++i) insert(centres[i], static_cast<uint32_t>(i));
  }

  void insert(const Vec3& p, uint32_t id) { cells_[key(cell_of(p))].push_back(id); }

  /// Calls f(id) for every centre in the 27 cells around p.
  template <class F>
  void for_near(const Vec3& p, F&& f) const {
    const auto c = cell_of(p);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (uint32_t id : it->second) f(id);
        }
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
  double inv_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace pfill

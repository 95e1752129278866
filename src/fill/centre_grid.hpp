// A uniform grid over sphere centres for neighbour queries on the host
// (metrics, overlap search, void filling). Cells at least as large as the
// query distance, so a query visits the 27 cells around a point.
//
// The centres given at construction lie in a dense array of cells (counts
// and ids sorted by cell, as a list build on the device does): a query
// reads three runs of ids, one per row of 3 cells, instead of hashing 27
// keys, which made hole searches over millions of grid points slow. Centres
// inserted later, and sparse sets in big boxes, go to a hash of cells. Cells
// are numbered from the origin either way, so a query finds the same
// centres whichever store holds them (a row's dense cells first, then its
// hashed ones).
#pragma once
#include <algorithm>
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
    if (centres.empty()) return;
    std::array<int64_t, 3> lo = cell_of(centres[0]), hi = lo;
    for (const Vec3& p : centres) {
      const auto c = cell_of(p);
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
    }
    double cells = 1;
    for (int a = 0; a < 3; ++a) cells *= static_cast<double>(hi[a] - lo[a] + 1);
    // A few centres far apart (a sparse set in a big box) would need more
    // cells than centres: those go to the hash.
    if (cells > 8.0 * static_cast<double>(centres.size()) + 4096) {
      cells_.reserve(centres.size());
      for (size_t i = 0; i < centres.size(); ++i) insert(centres[i], static_cast<uint32_t>(i));
      return;
    }
    lo_ = lo;
    for (int a = 0; a < 3; ++a) dims_[a] = hi[a] - lo[a] + 1;
    std::vector<uint32_t> cell_of_centre(centres.size());
    start_.assign(static_cast<size_t>(cells) + 1, 0);
    for (size_t i = 0; i < centres.size(); ++i) {
      cell_of_centre[i] = static_cast<uint32_t>(dense_index(cell_of(centres[i])));
      ++start_[cell_of_centre[i] + 1];
    }
    for (size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    ids_.resize(centres.size());
    std::vector<uint32_t> next(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < centres.size(); ++i) ids_[next[cell_of_centre[i]]++] = static_cast<uint32_t>(i);
  }

  void insert(const Vec3& p, uint32_t id) { cells_[key(cell_of(p))].push_back(id); }

  /// Calls f(id) for every centre in the 27 cells around p.
  template <class F>
  void for_near(const Vec3& p, F&& f) const {
    any_near(p, [&](uint32_t id) {
      f(id);
      return false;
    });
  }

  /// Calls pred(id) for the centres in the 27 cells around p until it
  /// returns true; returns whether it did.
  template <class Pred>
  bool any_near(const Vec3& p, Pred&& pred) const {
    const auto c = cell_of(p);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy) {
        if (!start_.empty()) {
          // The row's cells inside the dense box are one run of ids.
          const int64_t z = c[2] + dz - lo_[2], y = c[1] + dy - lo_[1];
          const int64_t x0 = std::max<int64_t>(c[0] - 1 - lo_[0], 0), x1 = std::min<int64_t>(c[0] + 1 - lo_[0], dims_[0] - 1);
          if (z >= 0 && z < dims_[2] && y >= 0 && y < dims_[1] && x0 <= x1) {
            const size_t row = static_cast<size_t>((z * dims_[1] + y) * dims_[0]);
            for (uint32_t m = start_[row + x0], end = start_[row + x1 + 1]; m < end; ++m)
              if (pred(ids_[m])) return true;
          }
        }
        if (cells_.empty()) continue;
        for (int dx = -1; dx <= 1; ++dx) {
          auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (uint32_t id : it->second)
            if (pred(id)) return true;
        }
      }
    return false;
  }

 private:
  std::array<int64_t, 3> cell_of(const Vec3& p) const {
    return {static_cast<int64_t>(std::floor(p.x * inv_)), static_cast<int64_t>(std::floor(p.y * inv_)),
            static_cast<int64_t>(std::floor(p.z * inv_))};
  }
  size_t dense_index(const std::array<int64_t, 3>& c) const {
    return static_cast<size_t>(((c[2] - lo_[2]) * dims_[1] + (c[1] - lo_[1])) * dims_[0] + (c[0] - lo_[0]));
  }
  static uint64_t key(const std::array<int64_t, 3>& c) {
    return (static_cast<uint64_t>(c[0] & 0x1FFFFF) << 42) | (static_cast<uint64_t>(c[1] & 0x1FFFFF) << 21) |
           static_cast<uint64_t>(c[2] & 0x1FFFFF);
  }
  double inv_;
  // Dense store: the cells of [lo_, lo_ + dims_), ids_ sorted by cell, a cell's run from start_.
  std::array<int64_t, 3> lo_{0, 0, 0}, dims_{0, 0, 0};
  std::vector<uint32_t> start_, ids_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;  ///< later inserts; sparse sets
};

}  // namespace pfill

// Which process decides a birth site (birth_view.hpp).
#include "pfill/engine/birth_view.hpp"

#include <algorithm>
#include <cmath>

namespace pfill {

double distance_to_box(const Box3& b, const Vec3& p) {
  const double dx = std::max({b.lo.x - p.x, p.x - b.hi.x, 0.0});
  const double dy = std::max({b.lo.y - p.y, p.y - b.hi.y, 0.0});
  const double dz = std::max({b.lo.z - p.z, p.z - b.hi.z, 0.0});
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

int owning_region(const std::vector<Box3>& regions, const Vec3& p) {
  for (size_t r = 0; r < regions.size(); ++r) {
    const Box3& b = regions[r];
    if (p.x >= b.lo.x && p.y >= b.lo.y && p.z >= b.lo.z && p.x < b.hi.x && p.y < b.hi.y && p.z < b.hi.z)
      return static_cast<int>(r);
  }
  int best = 0;
  for (size_t r = 1; r < regions.size(); ++r)
    if (distance_to_box(regions[r], p) < distance_to_box(regions[static_cast<size_t>(best)], p)) best = static_cast<int>(r);
  return best;
}

bool BirthView::decides(const Vec3& p) const { return complete() || owning_region(regions, p) == region; }

}  // namespace pfill

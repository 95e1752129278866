// Choosing birth sites from the signed distance field, and the room test.
#include "pfill/birth_sites.hpp"

#include <algorithm>
#include <numeric>

namespace pfill {

std::vector<BirthSite> choose_birth_sites(const ScalarGrid& sdf, int count, double min_depth, double depth_share) {
  std::vector<BirthSite> sites;
  size_t deepest = sdf.values.size();
  for (size_t i = 0; i < sdf.values.size(); ++i)
    if (deepest == sdf.values.size() || sdf.values[i] < sdf.values[deepest]) deepest = i;
  if (deepest == sdf.values.size() || -sdf.values[deepest] < min_depth) return sites;

  const int nx = sdf.dims[0], ny = sdf.dims[1];
  auto point = [&](size_t idx) {
    return sdf.point(static_cast<int>(idx % nx), static_cast<int>((idx / nx) % ny),
                     static_cast<int>(idx / (static_cast<size_t>(nx) * ny)));
  };
  const double max_depth = -static_cast<double>(sdf.values[deepest]);
  sites.push_back({point(deepest), max_depth});

  // The deep core, and each candidate's distance to the nearest chosen site.
  std::vector<size_t> core;
  const double floor_depth = std::max(min_depth, depth_share * max_depth);
  for (size_t i = 0; i < sdf.values.size(); ++i)
    if (-sdf.values[i] >= floor_depth) core.push_back(i);
  std::vector<double> nearest(core.size());
  for (size_t k = 0; k < core.size(); ++k) nearest[k] = length(point(core[k]) - sites[0].position);
  while (static_cast<int>(sites.size()) < count) {
    // Farthest core point whose inscribed ball does not meet another site's.
    size_t best = core.size();
    for (size_t k = 0; k < core.size(); ++k) {
      if (best != core.size() && nearest[k] <= nearest[best]) continue;
      const Vec3 p = point(core[k]);
      const double depth = -static_cast<double>(sdf.values[core[k]]);
      const bool apart = std::all_of(sites.begin(), sites.end(), [&](const BirthSite& s) {
        return length(s.position - p) >= s.depth + depth;
      });
      if (apart) best = k;
    }
    if (best == core.size()) break;  // no room for another site
    const Vec3 p = point(core[best]);
    sites.push_back({p, -static_cast<double>(sdf.values[core[best]])});
    for (size_t k = 0; k < core.size(); ++k) nearest[k] = std::min(nearest[k], length(point(core[k]) - p));
  }
  return sites;
}

bool site_has_room(const std::vector<Vec3>& centres, const Vec3& site, double clearance) {
  const double c2 = clearance * clearance;
  for (const Vec3& p : centres) {
    const Vec3 d = p - site;
    if (dot(d, d) < c2) return false;
  }
  return true;
}

}  // namespace pfill

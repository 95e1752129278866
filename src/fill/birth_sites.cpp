// Choosing birth sites from the signed distance field, and the room test.
#include "pfill/birth_sites.hpp"

#include <algorithm>
#include <numeric>

namespace pfill {

std::vector<BirthSite> choose_birth_sites(const ScalarGrid& sdf, int count, double min_depth, double separation) {
  std::vector<BirthSite> sites;
  // Candidates: every grid point deep enough, deepest first.
  std::vector<size_t> order;
  for (size_t i = 0; i < sdf.values.size(); ++i)
    if (-sdf.values[i] >= min_depth) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return sdf.values[a] < sdf.values[b] || (sdf.values[a] == sdf.values[b] && a < b);
  });
  const int nx = sdf.dims[0], ny = sdf.dims[1];
  for (size_t idx : order) {
    if (static_cast<int>(sites.size()) >= count) break;
    const int i = static_cast<int>(idx % nx), j = static_cast<int>((idx / nx) % ny),
              k = static_cast<int>(idx / (static_cast<size_t>(nx) * ny));
    const Vec3 p = sdf.point(i, j, k);
    const double far_enough = sites.empty() ? 0 : separation * sites.front().depth;
    const bool clear = std::all_of(sites.begin(), sites.end(),
                                   [&](const BirthSite& s) { return length(s.position - p) >= far_enough; });
    if (clear) sites.push_back({p, -static_cast<double>(sdf.values[idx])});
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

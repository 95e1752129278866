// The report's birth sites from the mesh, over the processes (mesh_sites.hpp).
#include "fill/mesh_sites.hpp"

#include <algorithm>

#include "fill/pick_over_processes.hpp"

namespace pfill {

std::vector<BirthSite> choose_birth_sites(const HeldCandidates& held, int count, double min_depth,
                                          double depth_share, ProcessGroup& group) {
  std::vector<BirthSite> sites;
  Pick deepest;  // (by the depth in `gap`'s place)
  for (const LargeCandidate& c : held.points) {
    const Pick p{c.point, c.depth, c.depth, c.order, 1};
    if (c.depth >= min_depth && beats(p, deepest, true)) deepest = p;
  }
  deepest = best_over(group, deepest, true);
  if (!deepest.found) return sites;
  sites.push_back({deepest.point, deepest.depth});

  // The deep core this process holds, and each one's distance to the nearest site.
  const double floor_depth = std::max(min_depth, depth_share * deepest.depth);
  std::vector<LargeCandidate> core;
  for (const LargeCandidate& c : held.points)
    if (c.depth >= floor_depth) core.push_back(c);
  std::vector<double> nearest(core.size());
  for (size_t k = 0; k < core.size(); ++k) nearest[k] = length(core[k].point - sites[0].position);
  while (static_cast<int>(sites.size()) < count) {
    // The farthest core point whose inscribed ball meets no site's.
    Pick mine;
    for (size_t k = 0; k < core.size(); ++k) {
      const Pick p{core[k].point, nearest[k], core[k].depth, core[k].order, 1};
      if (!beats(p, mine, true)) continue;
      if (std::all_of(sites.begin(), sites.end(),
                      [&](const BirthSite& s) { return length(s.position - p.point) >= s.depth + p.depth; }))
        mine = p;
    }
    const Pick best = best_over(group, mine, true);
    if (!best.found) break;  // no room for another site
    sites.push_back({best.point, best.depth});
    for (size_t k = 0; k < core.size(); ++k) nearest[k] = std::min(nearest[k], length(core[k].point - best.point));
  }
  return sites;
}

}  // namespace pfill

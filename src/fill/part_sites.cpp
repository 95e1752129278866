// A birth site for every closed part that has none (part_sites.hpp).
#include "fill/part_sites.hpp"

#include <tbb/parallel_for.h>

#include "fill/pick_over_processes.hpp"

namespace pfill {
namespace {

// A process's word on one part: whether a site lies in it, and its deepest candidate there.
struct PartOffer {
  Pick deepest;  ///< (by the depth in `gap`'s place)
  uint64_t part = 0;
  uint64_t has_site = 0;
};

}  // namespace

PartSiteChoice sites_for_empty_parts(const MeshParts& parts, const std::vector<BirthSite>& sites,
                                     const HeldCandidates& candidates, double min_depth, ProcessGroup& group) {
  std::vector<PartOffer> mine(parts.count());
  for (size_t p = 0; p < mine.size(); ++p) mine[p].part = p;
  for (const BirthSite& s : sites) mine[parts.part_at(s.position, s.depth)].has_site = 1;
  const std::vector<LargeCandidate>& c = candidates.points;
  std::vector<uint32_t> part_of(c.size());
  tbb::parallel_for(size_t(0), c.size(), [&](size_t k) { part_of[k] = parts.part_at(c[k].point, c[k].depth); });
  for (size_t k = 0; k < c.size(); ++k) {
    const Pick p{c[k].point, c[k].depth, c[k].depth, c[k].order, 1};
    PartOffer& o = mine[part_of[k]];
    if (c[k].depth >= min_depth && beats(p, o.deepest, true)) o.deepest = p;
  }
  std::vector<PartOffer> offered;
  for (const PartOffer& o : mine)
    if (o.has_site || o.deepest.found) offered.push_back(o);
  Bytes bytes;
  to_bytes(offered, bytes);
  std::vector<PartOffer> all(parts.count());
  for (const PartOffer& o : from_bytes<PartOffer>(group.all_gather(bytes))) {
    PartOffer& a = all[o.part];
    a.has_site |= o.has_site;
    if (beats(o.deepest, a.deepest, true)) a.deepest = o.deepest;
  }
  PartSiteChoice out;
  out.counts.parts = parts.count();
  for (size_t p = 0; p < all.size(); ++p) {
    if (all[p].has_site) continue;
    if (!all[p].deepest.found) {
      ++out.counts.too_small;
      continue;
    }
    out.added.push_back({{all[p].deepest.point, all[p].deepest.depth}, kPartKeyBase + p});
    ++out.counts.added;
  }
  return out;
}

}  // namespace pfill

// One candidate chosen over the processes (issue 31): each process offers
// the best of the candidates it holds, and every process takes the best of
// the offers, by one gather of a few words. The order of equally good
// candidates is the same on every process, so the choice is the one a
// single process holding every candidate makes (large_first.hpp,
// mesh_sites.hpp).
#pragma once
#include <cstdint>
#include <cstring>
#include <vector>

#include "pfill/engine/process_group.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

struct Pick {
  Vec3 point;
  double gap = 0, depth = 0;  ///< the distance the pick is made by, and the point's depth
  uint64_t order = 0;         ///< the candidate's rank among equals (lower wins)
  uint64_t found = 0;         ///< 0: no candidate offered
};

/// Whether `a` beats `b`: the farthest (larger gap) or the shallowest; ties to the lower order.
inline bool beats(const Pick& a, const Pick& b, bool farthest) {
  if (!a.found || !b.found) return a.found && !b.found;
  const double va = farthest ? -a.gap : a.depth, vb = farthest ? -b.gap : b.depth;
  return va < vb || (va == vb && a.order < b.order);
}

/// Every process's pick; the best of them, on every process (collective).
inline Pick best_over(ProcessGroup& group, const Pick& mine, bool farthest) {
  Bytes bytes(sizeof(Pick));
  std::memcpy(bytes.data(), &mine, sizeof(Pick));
  Pick best;
  for (const Pick& p : from_bytes<Pick>(group.all_gather(bytes)))
    if (beats(p, best, farthest)) best = p;
  return best;
}

}  // namespace pfill

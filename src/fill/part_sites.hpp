// A birth site for every closed part of the mesh that has none, where no
// process builds a field (issue 31; on the field: add_sites_per_part). A
// part too small for the waves' or the report's sites gets its deepest
// candidate, the best of every process's (one gather of a few words a
// part), so the sites are the same at any process count.
#pragma once
#include <cstdint>
#include <vector>

#include "fill/large_first.hpp"
#include "fill/mesh_parts.hpp"
#include "fill/site_choice.hpp"
#include "pfill/birth_sites.hpp"
#include "pfill/engine/process_group.hpp"

namespace pfill {

/// A part's site's key: past every lattice index of the waves' sites,
/// before the room sites' keys (held_sites.hpp's kRoomKeyBase).
constexpr uint64_t kPartKeyBase = uint64_t(1) << 61;

struct PartSiteChoice {
  PartSites counts;
  std::vector<KeyedSite> added;  ///< the new sites on every process, in part order, keyed kPartKeyBase + part
};

/// The parts none of `sites` (this process's, or every site on every
/// process) lies in get their deepest candidate of `candidates` (this
/// process's) at least `min_depth` deep; a part with no such candidate is
/// too small (collective).
PartSiteChoice sites_for_empty_parts(const MeshParts& parts, const std::vector<BirthSite>& sites,
                                     const HeldCandidates& candidates, double min_depth, ProcessGroup& group);

}  // namespace pfill

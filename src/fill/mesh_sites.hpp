// The report's few birth sites (FillOptions::sites, not waves) where no
// process builds a field (issue 31; the LAMMPS engine): choose_birth_sites'
// rule (birth_sites.hpp) on candidates held per process, the points of a
// lattice with the mesh's exact depths (large_first.hpp's mesh_candidates).
// The deepest candidate, then each next site at the deep core's candidate
// farthest from the sites chosen whose inscribed ball meets none of
// theirs: every choice is the best of every process's best (one gather of
// a few words a site), the same at any process count.
#pragma once
#include <vector>

#include "fill/large_first.hpp"
#include "pfill/birth_sites.hpp"
#include "pfill/engine/process_group.hpp"

namespace pfill {

/// Up to `count` sites, none shallower than `min_depth` (empty when no
/// candidate is that deep), the core at least `depth_share` of the
/// deepest's depth; the same list on every process (collective).
std::vector<BirthSite> choose_birth_sites(const HeldCandidates& held, int count, double min_depth,
                                          double depth_share, ProcessGroup& group);

}  // namespace pfill

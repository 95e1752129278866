// Rare large spheres placed before pass 1 (issue 29, radii 1:10): a class
// the whole fill expects only a few of (SizeDeficit::front_load) needs a
// clear ball of several small radii, which no birth site has once the
// small spheres stream in. So they are placed first, at rest, each at a
// point of the distance field deep enough for it and clear of the ones
// placed before; pass 1 then fills around them.
//
// Where no process builds a field (the LAMMPS engine's sites from the
// mesh, FillOptions::wall_from_mesh), the candidates are points of a
// lattice with the mesh's exact depths, each held by the process whose
// sub-domain holds it, and each sphere's point is the best of every
// process's best (one gather of a few words a sphere): the placement is
// the same at any process count.
#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "pfill/boundary.hpp"
#include "pfill/engine/birth_view.hpp"
#include "pfill/engine/process_group.hpp"
#include "pfill/grid.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

struct LargeFirstSettings {
  double wall_gap = 0;  ///< a placed sphere's surface stays this far inside the wall (by the field)
  double pair_gap = 0;  ///< and this far from any other placed sphere's surface
};

/// Centres for spheres of `radii` (largest first) on `field`'s inside, at
/// grid points (on a sub-lattice an eighth of the smallest radius apart)
/// whose depth is at least the sphere's radius + wall_gap and whose
/// distance to every centre placed before is at least the two radii +
/// pair_gap. Farthest-point placement: the first sphere at one of a few
/// dozen starts spread over its points, each next one at the fitting point
/// farthest from the spheres placed (what packs the most equal spheres
/// into a room); the start that places the most wins (ties: the most room
/// to spare). A sphere that finds no point is skipped (smaller ones may
/// still fit after it); the result lists the placed ones in order.
struct LargePlacement {
  std::vector<Vec3> centres;
  std::vector<double> radii;
};
LargePlacement place_large_first(const ScalarGrid& field, const std::vector<double>& radii,
                                 const LargeFirstSettings& s);

/// A candidate point and its depth; `order` ranks the candidates alike on
/// every process (ties between equally good points go to the lower).
struct LargeCandidate {
  Vec3 point;
  double depth = 0;
  uint64_t order = 0;
};

/// The candidates this process holds: lattice points `step` apart over
/// `box`, at least `min_depth` inside by the mesh's exact distance, those
/// `view` decides (a complete view: all), in lattice order.
struct HeldCandidates {
  std::vector<LargeCandidate> points;  ///< (radii needing less than min_depth see no shallower point)
};
HeldCandidates mesh_candidates(const Boundary& boundary, const Box3& box, double step, double min_depth,
                               const BirthView& view);

/// place_large_first on candidates held across the processes of `group`
/// (collective; the same result on every process, and at any process
/// count). The first sphere's starts: its points with the 64 smallest
/// hashes of their order (a spread sample), and its shallowest.
LargePlacement place_large_first(const HeldCandidates& held, const std::vector<double>& radii,
                                 const LargeFirstSettings& s, ProcessGroup& group);

/// A placement of `radii` (largest first) with `s`: on a field or on held candidates.
using LargePlacer = std::function<LargePlacement(const std::vector<double>& radii, const LargeFirstSettings& s)>;

}  // namespace pfill

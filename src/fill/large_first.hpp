// Rare large spheres placed before pass 1 (issue 29, radii 1:10): a class
// the whole fill expects only a few of (SizeDeficit::front_load) needs a
// clear ball of several small radii, which no birth site has once the
// small spheres stream in. So they are placed first, at rest, each at a
// point of the distance field deep enough for it and clear of the ones
// placed before; pass 1 then fills around them.
#pragma once
#include <vector>

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

}  // namespace pfill

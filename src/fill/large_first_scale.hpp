// Re-planning for rare large spheres that do not all fit (issue 29): the
// count rule sizes a 1:10 mix so that -n spheres fill the mesh, but the
// few large ones it expects may find no room together (the bunny holds
// 22-28% of its volume in them, by farthest-point placement, where 50/50
// by volume at a packing of 0.64 asks 32%). Before the engine is built,
// the placement is tried on the distance field (cheap) at the plan's
// scale and then at smaller ones, until the quota fits: all radii shrink
// by the same factor, the large spheres' quota stays, and the other
// classes, held to their shares of them, keep the total near -n.
#pragma once
#include <cstdint>
#include <vector>

#include "fill/fill_plan.hpp"
#include "fill/large_first.hpp"

namespace pfill {

/// How many spheres of the front-loaded classes may be born first
/// (SizeDeficit::front_load's `first_wave`) over `sites` birth sites.
double front_first_wave(const FillPlan& plan, size_t sites);

/// The gaps the large spheres keep: from the wall half a smallest radius
/// (past the finish's wall margin), from each other a smallest radius.
LargeFirstSettings large_first_settings(double smallest_radius);

/// The radii placed before pass 1 (SizeDeficit::front_radii, largest
/// first) for `plan` over `sites` sites, drawn from the seed's own stream
/// (counter_rng.hpp: stream 2 of step 0); empty when no class is front-loaded.
std::vector<double> front_loaded_radii(const FillPlan& plan, size_t sites, uint64_t seed);

/// The largest scale of the plan's radii at which `place` places every
/// front-loaded sphere: 1, then steps of 0.9 (to lowest_large_first_scale()
/// at most), then halvings between the last miss and the first fit;
/// 1 when all fit at once, none is front-loaded, or no scale tried fits
/// them all (the other classes are then held to those placed).
double large_first_scale(const LargePlacer& place, const FillPlan& plan, size_t sites, uint64_t seed);

/// The smallest scale large_first_scale tries (0.9^8, 0.43).
double lowest_large_first_scale();

}  // namespace pfill

// Unequal spheres: the radii the finish's holes get (issue 31). A hole's
// radius depends on the holes before it (SizeDeficit::take_within counts
// each in, and draws inside the class from one generator), so where the
// spheres are split over processes every process walks every process's
// holes alike, in process order, on the same counts (summed over the
// processes) and the same generator, and keeps its own holes' radii. One
// process walks its own, untold: the radii are those of a walk in order.
#pragma once
#include <random>
#include <vector>

#include "fill/finish_view.hpp"
#include "fill/size_deficit.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

/// The radius each of this process's holes gets, at most its room
/// (`rooms`, one a hole; 0: no class fits). Collective.
std::vector<double> radii_walked_alike(ParticleEngine& engine, const FinishView& view, const std::vector<double>& rooms,
                                       SizeDeficit& sizes, std::mt19937_64& rng);

/// The same for holes that take a sphere as they are (the finish's last
/// fits, at `fits`): a fit's room (`rooms`) also shrinks to its gap to
/// the fits placed before it, of every process. Collective.
std::vector<double> fit_radii_walked_alike(ParticleEngine& engine, const FinishView& view,
                                           const std::vector<Vec3>& fits, const std::vector<double>& rooms,
                                           SizeDeficit& sizes, std::mt19937_64& rng);

}  // namespace pfill

/// @file voids.hpp
/// @brief Holes in a packing big enough for one more sphere: after the
/// physics has jammed, the fill inserts spheres there and relaxes again,
/// which lifts the density and makes it depend less on the seed.
#pragma once
#include <vector>

#include "pfill/grid.hpp"
#include "pfill/particles.hpp"

namespace pfill {

/// Grid points of `sdf` at least `radius` inside the surface whose nearest
/// centre in `particles` is at least `clearance` away, chosen greedily in
/// grid order so that the chosen points
/// are also `clearance` apart. At most `limit` points.
std::vector<Vec3> find_voids(const ParticleSet& particles, const ScalarGrid& sdf, double radius, double clearance,
                             size_t limit);

}  // namespace pfill

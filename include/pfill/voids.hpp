/// @file voids.hpp
/// @brief Holes in a packing big enough for one more sphere: after the
/// physics has jammed, the fill inserts spheres there and relaxes again,
/// which lifts the density and makes it depend less on the seed.
#pragma once
#include <functional>
#include <vector>

#include "pfill/grid.hpp"
#include "pfill/particles.hpp"

namespace pfill {

/// Points at least `radius` inside (by `sdf`) whose nearest centre is at
/// least `clearance` away, each climbed from a grid point to where its
/// nearest centre is farthest, so that holes between grid points are found
/// too; largest first, the chosen points `clearance` apart. At most `limit`.
/// With clearance 2 r, a sphere fits at each without overlap.
/// Unequal spheres: with `reference_radius` > 0, "centre" distances are
/// to each sphere's surface plus the reference radius (the same for
/// spheres of that radius), and a hole taken counts as a sphere of it.
/// `distances`, when given, gets each hole's nearest distance so measured.
/// `within`, when given, limits the search to the grid points in that box
/// (a process's sub-domain: the particles then need only reach a clearance
/// past it); a climb may end a little outside it.
std::vector<Vec3> find_holes(const ParticleSet& particles, const ScalarGrid& sdf, double radius, double clearance,
                             size_t limit, double reference_radius = 0, std::vector<double>* distances = nullptr,
                             const Box3* within = nullptr);

/// As above, with "inside" by `signed_distance` (exact, say: ExactField)
/// at the points of `lattice`, whose values are not read (it may hold
/// none); only the points no centre is near are asked, and the climbs.
std::vector<Vec3> find_holes(const ParticleSet& particles, const ScalarGrid& lattice,
                             const std::function<double(const Vec3&)>& signed_distance, double radius,
                             double clearance, size_t limit, double reference_radius = 0,
                             std::vector<double>* distances = nullptr, const Box3* within = nullptr);

}  // namespace pfill

/// @file count_rule.hpp
/// @brief How many spheres a fill packs into a mesh, and so the radius for
/// a count: one rule for `pfill fill -n`, `pfill info`, Python and the
/// time-left estimate.
#pragma once
#include <cstddef>

#include "pfill/radius_distribution.hpp"

namespace pfill {

/// The packing fraction a fill reaches at a bound on the overlaps
/// (`max_overlap`, a fraction of r): looser bounds pack denser, and spheres
/// pack looser against the wall, whose share of the inside is about
/// `wall_share` = S r / V (surface S, volume V, radius r).
double expected_packing(double max_overlap, double wall_share);

/// About how many spheres fill `volume` (enclosed by a surface of `area`)
/// when they keep `half_rest` (half the rest distance; r for touching
/// spheres) from each other, overlapping by at most `max_overlap`, at a
/// `rest_distance` in contact distances 2r (centres need only r of room
/// from the wall, so sparse spacings reach past it).
double expected_fill_count(double volume, double area, double half_rest, double max_overlap,
                           double rest_distance = 1);

/// The sphere radius that gives about `count` spheres in `volume` (enclosed
/// by a surface of `area`) at the bound `max_overlap` and the rest distance
/// `rest_distance` (contact distances). 0 for no volume or no count.
double fill_radius_for_count(double volume, double area, size_t count, double max_overlap = 0.001,
                             double rest_distance = 1);

/// Unequal spheres: about how many spheres of `sizes` (mesh units) fill
/// `volume` (enclosed by `area`): the equal spheres' packing at the mean
/// radius, plus the distribution's random-close-packing gain
/// (RadiusDistribution::rcp_gain), over the mean sphere volume.
double expected_fill_count(double volume, double area, const RadiusDistribution& sizes, double max_overlap);

/// The factor that scales `sizes` (relative radii) so that about `count`
/// spheres fill `volume`; 0 for no volume or no count.
double fill_scale_for_count(double volume, double area, size_t count, const RadiusDistribution& sizes,
                            double max_overlap = 0.001);

}  // namespace pfill

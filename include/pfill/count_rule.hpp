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

/// Rare large spheres among small ones (radii 1:4 and more): the classes
/// at least 4 times the commonest's radius, when they are at most 2% by
/// number and 60% of the volume; zero shares when there are none.
struct Inclusions {
  double number_share = 0, volume_share = 0;
  double radius = 0;  ///< their radius, weighted as their surface is (volume over surface share)
};
Inclusions inclusions_of(const RadiusDistribution& sizes);

/// Unequal spheres: about how many spheres of `sizes` (mesh units) fill
/// `volume` (enclosed by `area`): the equal spheres' packing at the mean
/// radius, plus the distribution's random-close-packing gain
/// (RadiusDistribution::rcp_gain), over the mean sphere volume. With
/// inclusions, the small spheres' packing around them instead (the large
/// spheres' surface counted as wall).
double expected_fill_count(double volume, double area, const RadiusDistribution& sizes, double max_overlap);

/// The factor that scales `sizes` (relative radii) so that about `count`
/// spheres fill `volume`; 0 for no volume or no count. With up to 32
/// inclusions expected, the count nearest `count` that expects a whole
/// number of them (their volume share then holds).
double fill_scale_for_count(double volume, double area, size_t count, const RadiusDistribution& sizes,
                            double max_overlap = 0.001);

}  // namespace pfill

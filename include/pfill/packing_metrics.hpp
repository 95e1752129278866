/// @file packing_metrics.hpp
/// @brief How good a set of spheres in a mesh is, measured exactly (Embree
/// distances, not the interpolated field): packing fraction, containment,
/// overlaps, coordination; and the final repair that moves spheres crossing
/// the surface back inside or removes them. Used after every fill and by
/// `pfill check`.
#pragma once
#include <cstddef>
#include <vector>

#include "pfill/boundary.hpp"
#include "pfill/particle_share.hpp"
#include "pfill/particles.hpp"

namespace pfill {

struct PackingMetrics {
  size_t count = 0;
  double mesh_volume = 0;
  double packing_fraction = 0;     ///< sum of sphere volumes / mesh volume
  double contained_share = 0;      ///< spheres inside within the tolerance, 0..1
  size_t centres_outside = 0;      ///< spheres whose centre is outside the mesh
  double max_penetration = 0;      ///< largest (r - depth of centre) / r, 0 when all inside
  size_t overlapping_pairs = 0;    ///< pairs closer than r_i + r_j
  double mean_overlap = 0;         ///< mean (r_i + r_j - d) / min(r_i, r_j) over overlapping pairs
  double max_overlap = 0;          ///< largest (r_i + r_j - d) / min(r_i, r_j): of the smaller radius
  double mean_coordination = 0;    ///< contacts per sphere (gap below contact_gap min(r_i, r_j))
  double containment_tolerance = 0;
  double min_distance = 0;         ///< smallest centre distance over r_i + r_j (1: touching; < 1: overlapping)
  /// Largest empty hole: the largest distance from a point at least r
  /// inside the mesh to the nearest sphere's surface, over r (r the
  /// smallest radius, as the fill measures it). At 1 or more a sphere of
  /// the smallest radius fits there, inside and overlapping none.
  /// Negative when not measured (MetricsOptions::holes).
  double largest_hole = -1;
};

struct MetricsOptions {
  double containment_tolerance = 0.01;  ///< a sphere may cross the surface by this fraction of r
  double contact_gap = 0.02;            ///< spheres closer than r_i + r_j + gap * r touch
  bool holes = true;                    ///< measure the largest empty hole (largest_hole_over_r)
};

/// The largest empty hole of PackingMetrics::largest_hole, in units of
/// `radius`: grid points at r/2 near the spheres, the best of them checked
/// with exact distances and then climbed to the local maximum. Holes wider
/// than 2 r count as 2 r. Parallel.
double largest_hole_over_r(const Boundary& boundary, const ParticleSet& particles, double radius);

/// The same hole and where it is: a sphere of `radius` centred there lies
/// inside and overlaps none when gap_over_r >= 1.
struct Hole {
  Vec3 centre;
  double gap_over_r = 0;
};
Hole largest_hole(const Boundary& boundary, const ParticleSet& particles, double radius);
/// largest_hole's hole first, then the other distinct holes (a radius or
/// more apart) as wide within a grid step of r / 2, widest first: one
/// search for the holes a fill may fill before it must look again.
std::vector<Hole> largest_holes(const Boundary& boundary, const ParticleSet& particles, double radius);
/// The same over a packing held in parts: each process searches its own
/// region, with a halo of the others' spheres; every process gets the
/// holes of all, widest first, each a radius or more from a wider one.
/// Collective; one process: largest_holes.
std::vector<Hole> largest_holes(const Boundary& boundary, const ParticleSet& own, double radius,
                                const ParticleShare& share);

/// Measures `particles` in the mesh of `boundary` (whose volume is given,
/// since open meshes need the estimate from diagnose()). Parallel. Held in
/// parts (`share` over several processes): `particles` are this process's
/// own, and every process gets the measures of the whole. Collective.
PackingMetrics measure_packing(const Boundary& boundary, double mesh_volume, const ParticleSet& particles,
                               const MetricsOptions& options = {}, const ParticleShare& share = {});

/// The pairs (i < j) whose spheres overlap, with overlap (r_i + r_j - d) as a
/// fraction of the smaller radius. Host hash grid, O(n).
struct Overlap {
  uint32_t i = 0, j = 0;
  double fraction = 0;
};
std::vector<Overlap> find_overlaps(const ParticleSet& particles, double min_fraction = 0.0);

struct ContainmentRepair {
  size_t moved = 0;    ///< spheres pushed back to lie inside
  size_t removed = 0;  ///< spheres that could not be placed inside without overlapping
};

/// Every sphere crossing the surface by more than `tolerance` r is moved
/// along the surface normal to lie exactly inside; if it then overlaps a
/// neighbour by more than `max_overlap` r, or its centre is still not deep
/// enough (a part thinner than the sphere), it is removed. Of two moved
/// spheres over the bound, the one that was further out gives way. Exact
/// distances. Held in parts: this process's own spheres, the counts over
/// all (collective).
ContainmentRepair repair_containment(const Boundary& boundary, ParticleSet& particles, double tolerance,
                                     double max_overlap, const ParticleShare& share = {});

}  // namespace pfill

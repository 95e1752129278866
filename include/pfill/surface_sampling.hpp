/// @file surface_sampling.hpp
/// @brief Boundary particles: the surface of a mesh sampled with particles
/// at an even spacing 2R (SPH walls, Akinci et al. 2012), each with its
/// outward normal and the area it stands for; and the figures of such a
/// shell (nearest-neighbour spacing, coverage) for `pfill surface` and
/// `pfill check --shell`.
///
/// The sampling: blue noise on the triangles by sample elimination
/// (Yuksel 2015: candidates uniform by area, the most crowded removed one by
/// one down to the count a hexagonal layer at spacing 2R has, A / (sqrt(3)
/// / 2 (2R)^2)), then a tangential relaxation: each particle is pushed away
/// from neighbours closer than 2R along the surface's tangent plane and
/// projected back to the closest surface point, so the spacing evens out
/// across sharp edges. Neighbours whose normals face away (the two sides of
/// a part thinner than 2R) do not push each other. Where the surface is
/// sharper than the spacing (a horn's tip), the projection can pile
/// particles together: of any pair closer than 0.8 x 2R one is removed
/// (three quarters through the rounds, and at the end), and surface points
/// farther than 1.4 R from every particle get one; after the last rounds,
/// while that changes something, a few more rounds settle it. The projection
/// walks over the triangles around each particle's own (Embree only where
/// parts of a union overlap), and the neighbours come from lists rebuilt
/// once a particle has moved 0.15 x 2R.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "pfill/boundary.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

struct SurfaceSamplingOptions {
  double radius = 0;          ///< particle radius R (> 0); the spacing is 2R
  uint64_t seed = 1;          ///< same seed, mesh and radius: same particles
  int relax_iterations = 80;  ///< tangential relaxation rounds (0: blue noise only)
  int candidates_per_particle = 6;  ///< candidates for the elimination (>= 2)
};

struct SurfaceSamples {
  double radius = 0;
  std::vector<Vec3> positions;  ///< on the surface
  std::vector<Vec3> normals;    ///< unit, out of the solid
  std::vector<double> areas;    ///< surface area each particle stands for (sums to the mesh's area)
  double surface_area = 0;
};

/// Samples the surface of `boundary`'s mesh. Throws pfill::Error for a
/// radius that is not > 0 or would give more than 1e8 particles.
SurfaceSamples sample_surface(const Boundary& boundary, const SurfaceSamplingOptions& options);

/// The radius R that gives about `count` particles on a surface of `area`.
double surface_radius_for_count(double area, size_t count);

/// Figures of a shell of particles of radius R on a surface.
struct ShellStats {
  size_t count = 0;
  double spacing = 0;             ///< 2R
  double nn_mean = 0, nn_min = 0, nn_max = 0;  ///< nearest-neighbour centre distances
  double share_within_15 = 0;     ///< share of particles whose nearest neighbour is within +-15% of 2R
  size_t closer_than_08 = 0;      ///< particles whose nearest neighbour is closer than 0.8 x 2R
  double coverage = 0;            ///< largest distance from a surface point to its nearest particle
  double coverage_over_r = 0;     ///< coverage / R (a perfect hexagonal layer: 1.155)
  Vec3 least_covered;             ///< the surface point farthest from every particle
  size_t surface_points = 0;      ///< surface points the coverage was measured at
  double largest_off_surface = 0; ///< largest distance of a particle from the surface
  /// The area each particle stands for: the surface points' areas given to
  /// their nearest particle (the particles' Voronoi cells on the surface).
  std::vector<double> areas;
};

/// Measures a shell: nearest-neighbour distances among `positions`, and the
/// coverage at surface points spaced about R / `density` apart on every
/// triangle (its corners and edges included). Parallel.
ShellStats measure_shell(const Boundary& boundary, const std::vector<Vec3>& positions, double radius,
                         double density = 4);

}  // namespace pfill

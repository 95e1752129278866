/// @file winding_sweep.hpp
/// @brief The winding number of a closed mesh sampled along parallel rays:
/// the volume where it is non-zero (the union of intersecting parts, counted
/// once) and its range, which tells whether parts overlap or the surface
/// intersects itself. No Embree: the mesh layer's own ray sweep.
#pragma once
#include <cstddef>

#include "pfill/mesh.hpp"

namespace pfill {

struct WindingSweep {
  double volume = 0;     ///< volume where the winding number is non-zero
  int max_winding = 0;   ///< largest winding number met (orientation-corrected: outward)
  int min_winding = 0;   ///< smallest; < 0 where the surface folds inside out
  size_t rays = 0;       ///< rays cast
  /// Some region is enclosed twice (intersecting or nested parts, a limb
  /// pushed through the body) or inside out.
  bool overlapping() const { return max_winding > 1 || min_winding < 0; }
};

/// Casts `rays_per_axis`^2 rays along +z over the mesh's box (each at a
/// fixed irrational offset in its cell) and integrates the length where the
/// winding number is non-zero. `orientation` (+1 or -1) multiplies every
/// crossing, so an inside-out mesh counts as outward. Meaningful for closed
/// meshes whose every edge is walked once each way; an edge-on hit is given
/// to exactly one of the triangles that share it. The volume's relative
/// error is about the surface area times the ray spacing over the volume.
WindingSweep sweep_winding(const Mesh& mesh, int orientation = 1, int rays_per_axis = 256);

/// True when every directed edge a->b of the triangles is matched by as
/// many b->a: the mesh is a closed surface (possibly of intersecting parts)
/// on which the winding number is well defined.
bool edges_balanced(const Mesh& mesh);

}  // namespace pfill

/// @file shell_fill.hpp
/// @brief `fill --shell`: the inner fill and the boundary particles
/// (surface_sampling.hpp) in one set, told apart by a `kind` attribute. The
/// fill runs in the mesh moved in by the shell's radius (inset_mesh), so
/// that its wall keeps the inner spheres clear of the shell; whatever still
/// overlaps a shell particle by more than the bound is removed.
#pragma once
#include <cstddef>

#include "pfill/mesh.hpp"
#include "pfill/particle_attributes.hpp"
#include "pfill/particles.hpp"
#include "pfill/surface_sampling.hpp"

namespace pfill {

/// The mesh with every vertex moved into the solid so that the planes of
/// its triangles move in by about `inset`: along the angle-weighted vertex
/// normal, lengthened by 1 / the smallest cosine to an incident triangle's
/// normal (at most 3x; a cube's corner moves by inset x (1, 1, 1)). Exact
/// for planar faces meeting at edges and corners; on curved parts the
/// surface moves in by inset to first order. `inward_oriented`: the
/// triangles wind clockwise seen from outside.
Mesh inset_mesh(const Mesh& mesh, double inset, bool inward_oriented);

struct ShellFill {
  ParticleSet particles;          ///< the inner spheres first, then the shell's
  ParticleAttributes attributes;  ///< kinds (0 inner, 1 boundary), normals and areas (zero for inner)
  size_t inner = 0;               ///< inner spheres kept
  size_t removed = 0;             ///< inner spheres removed: overlapping a shell particle by more than the bound
};

/// Joins `inner` (a fill) and `shell` into one set. An inner sphere that
/// overlaps a shell particle by more than `max_overlap` x its radius is
/// removed. Shell particles get the ids after the largest inner id.
ShellFill join_shell(const ParticleSet& inner, const SurfaceSamples& shell, double max_overlap);

}  // namespace pfill

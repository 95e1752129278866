// The closest surface point near a known triangle, for points that moved a
// little from the surface (the sampler's relaxation; private to
// src/boundary). It tests the triangle the point stood on and, unless the
// point projects inside it, walks over the triangles around it: a few
// triangle tests instead of an Embree query per particle and round, and it
// stays on its own side of a part thinner than the spacing.
#pragma once
#include <cstdint>
#include <vector>

#include "boundary/surface_normals.hpp"
#include "pfill/mesh.hpp"

namespace pfill {

class SurfaceWalk {
 public:
  /// `orientation`: -1 for an inward-oriented mesh (normals turned out of the solid).
  SurfaceWalk(const Mesh& mesh, double orientation);

  /// The closest point to p on the triangles around `triangle` (those sharing
  /// a vertex with it), walking on while a neighbour's is closer; p's
  /// projection into `triangle` itself when it falls inside (at a sharp
  /// edge, moved inwards, another face can be a little closer). Sets
  /// `triangle`, `point` and `normal` (out of the solid; the pseudonormal on
  /// an edge or a vertex, as Boundary::closest gives for points on the
  /// surface); false when the walk did not settle within a few steps.
  bool project(const Vec3& p, uint32_t& triangle, Vec3& point, Vec3& normal) const;

 private:
  const Mesh& mesh_;
  double orientation_;
  SurfaceNormals normals_;
  std::vector<uint32_t> first_, around_;  // triangles around each vertex (CSR)
};

}  // namespace pfill

// Per-face, per-edge and per-vertex normals of a mesh and where they can be
// trusted to tell inside from outside (private to src/boundary).
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "boundary/point_triangle.hpp"
#include "pfill/mesh.hpp"

namespace pfill {

/// The angle-weighted pseudonormals of Baerentzen & Aanaes (2005): for a
/// closed, consistently oriented manifold, sign(dot(p - q, n_feature)) is the
/// side of p, where q is the closest point and n_feature the pseudonormal of
/// the face, edge or vertex holding q. Normals follow the winding as given
/// (outward on outward-oriented meshes).
struct SurfaceNormals {
  std::vector<Vec3> face;    ///< unit face normals; zero for degenerate triangles
  std::vector<Vec3> edge;    ///< unit sum of the adjacent face normals
  std::vector<Vec3> vertex;  ///< unit angle-weighted sum of the incident face normals
  std::vector<std::array<uint32_t, 3>> triangle_edges;  ///< edge ids of AB, BC, CA
  // Whether each feature's pseudonormal decides a sign: manifold, closed,
  // consistently oriented and non-degenerate around it.
  std::vector<uint8_t> face_ok, edge_ok, vertex_ok;
  double signed_volume = 0;
  bool closed = false;  ///< every edge ok

  /// The pseudonormal of `feature` of triangle `t`; `*ok` says whether it
  /// can decide a sign.
  Vec3 pseudonormal(const Mesh& mesh, uint32_t t, TriangleFeature feature, bool* ok) const;
};

SurfaceNormals compute_surface_normals(const Mesh& mesh);

}  // namespace pfill

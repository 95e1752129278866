// Exact closest point on a triangle, in double precision: the inner step of
// Boundary::closest (private to src/boundary).
#pragma once
#include <cstdint>

#include "pfill/vec3.hpp"

namespace pfill {

/// Which part of the triangle holds the closest point: the Voronoi region of
/// the query point, needed to pick the right pseudonormal.
enum class TriangleFeature : uint8_t { Face, EdgeAB, EdgeBC, EdgeCA, VertexA, VertexB, VertexC };

struct PointTriangleResult {
  Vec3 point;                 ///< closest point = (1-u-v) A + u B + v C
  double u = 0, v = 0;        ///< barycentrics of B and C
  double distance2 = 0;       ///< squared distance from the query point
  TriangleFeature feature = TriangleFeature::Face;
};

/// Closest point of triangle ABC to p (Ericson, Real-Time Collision
/// Detection, 5.1.5). Degenerate (zero-area) triangles are handled as their
/// three edges, so the answer is always finite.
PointTriangleResult closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace pfill

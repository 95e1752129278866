/// @file boundary.hpp
/// @brief The geometry of a mesh's surface through Embree 3: inside/outside,
/// closest point, signed distance, single and batched.
///
/// One Boundary owns one Embree device and scene (built once, robust mode,
/// high build quality) plus a double-precision copy of the mesh; Embree only
/// finds candidates, every distance is computed exactly in double.
/// Queries are const and safe to call from many threads at once.
///
/// Conventions:
/// - inside(p) is a majority vote of rays along several fixed, well-spread
///   directions (BoundaryOptions::parity_rays, odd). On a closed mesh (every
///   edge walked once each way) a ray says inside when the winding number,
///   its signed crossings, is non-zero: intersecting or nested closed parts
///   count as their union. Elsewhere (open or inconsistently oriented
///   meshes) it says inside on an odd number of crossings (parity ignores
///   the orientation; on a mesh with small holes the majority still gives
///   the right answer away from the holes). Hits are collected
///   along the whole ray and deduplicated per triangle; a ray that passes
///   within rounding of an edge or vertex is re-cast in a perturbed direction,
///   so edge and vertex hits are never double counted. Inside-out meshes
///   are read with their orientation reversed.
/// - Where closed parts overlap (overlapping()), each an outward solid,
///   distances are the union's (union_of_parts()): the smallest of the
///   parts' signed distances, so the surfaces inside other parts are no
///   walls. On a surface that passes through itself the signs come from
///   inside(), not from pseudonormals.
/// - signed_distance(p) = -distance inside, +distance outside (sign from
///   inside()).
/// - ClosestPoint::normal is a unit vector pointing out of the solid
///   (orientation-corrected on inward-oriented meshes): the triangle normal
///   when the closest point is inside a face; when it is on an edge or a
///   vertex, the direction from the closest point to p, turned so that it
///   points out of the solid by the angle-weighted pseudonormal of that
///   edge or vertex (for p on the surface: the pseudonormal itself). Off the
///   surface this is the gradient of the signed distance.
#pragma once
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "pfill/mesh.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

struct BoundaryOptions {
  int parity_rays = 5;  ///< rays per inside() vote; odd, 1..31
};

struct ClosestPoint {
  Vec3 point;              ///< closest point on the surface
  double distance = 0;     ///< |p - point|, unsigned
  uint32_t triangle = 0;   ///< index into Mesh::triangles
  double u = 0, v = 0;     ///< point = (1-u-v) A + u B + v C of that triangle
  Vec3 normal;             ///< unit, out of the solid (see the file comment)
};

class Boundary {
 public:
  /// Validates the mesh (throws pfill::Error naming mesh.source on bad
  /// input) and builds the Embree scene; Embree errors become pfill::Error.
  explicit Boundary(const Mesh& mesh, BoundaryOptions options = {});
  ~Boundary();
  Boundary(Boundary&&) noexcept;
  Boundary& operator=(Boundary&&) noexcept;
  Boundary(const Boundary&) = delete;
  Boundary& operator=(const Boundary&) = delete;

  /// Ray-parity majority vote; see the file comment.
  bool inside(const Vec3& p) const;
  /// Closest surface point; exact in double (ties: lowest triangle index).
  ClosestPoint closest(const Vec3& p) const;
  /// The closest point if one lies within `radius` of p, else nothing.
  /// Cheaper than closest() when a bound is known.
  std::optional<ClosestPoint> closest_within(const Vec3& p, double radius) const;
  /// Negative inside, sign from inside().
  double signed_distance(const Vec3& p) const;

  /// Signed distance with the sign taken from the angle-weighted pseudonormal
  /// of the closest feature (Baerentzen & Aanaes 2005) wherever the mesh is
  /// closed, manifold and consistently oriented around that feature, and from
  /// inside() elsewhere. It equals signed_distance() on closed meshes and
  /// costs one point query instead of several rays. `upper_bound` (a known
  /// bound on the distance, or infinity) only speeds up the search.
  /// `*used_parity` (optional) says whether the ray vote decided the sign.
  double fast_signed_distance(const Vec3& p, double upper_bound = std::numeric_limits<double>::infinity(),
                              bool* used_parity = nullptr) const;

  /// Batched, parallel over the points (TBB); same results as the singles.
  std::vector<uint8_t> inside(const std::vector<Vec3>& points) const;
  std::vector<ClosestPoint> closest(const std::vector<Vec3>& points) const;
  std::vector<double> signed_distance(const std::vector<Vec3>& points) const;

  /// Number of surface crossings along the ray origin + t * direction,
  /// t > 0, each triangle counted once. If some hit lies within rounding of
  /// an edge or a vertex, the ray is re-cast in slightly perturbed
  /// directions until none does, so the parity of the count is reliable.
  int crossings(const Vec3& origin, const Vec3& direction) const;
  /// The fixed unit directions inside() votes along.
  const std::vector<Vec3>& parity_directions() const;

  const Mesh& mesh() const;
  /// Signed volume < 0: the triangles wind clockwise seen from outside.
  bool inward_oriented() const;
  double signed_volume() const;
  /// True when every edge has exactly two triangles that traverse it in
  /// opposite directions (closed, manifold, consistently oriented).
  bool closed() const;
  /// Some region is enclosed twice (parts intersect or nest, or the surface
  /// passes through itself); decided by a winding sweep on closed meshes.
  bool overlapping() const;
  /// Distances are those of the union of overlapping closed parts.
  bool union_of_parts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pfill

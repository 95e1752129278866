// The hole search's depth test (largest_hole.cpp): is a point at least a
// given depth inside the mesh? Exactly Boundary::fast_signed_distance(p)
// <= -depth, but most of the ~100,000 grid points it is asked about at
// -n 4000 lie in the layer between the wall and the spheres or outside,
// where cheaper facts answer "no" without an Embree closest-point query
// (~10 us each on the closed bunny's 69k triangles):
// - a point of the surface (a sample of its triangles) in p's voxel or a
//   face neighbour, voxels of depth / sqrt(6): then |distance| < depth;
// - on closed meshes that do not intersect themselves, where the signed
//   distance is 1-Lipschitz, the exact value at a lattice corner nearby:
//   phi(p) >= phi(c) - |p - c| > -depth. The corners, on a lattice of twice
//   the search grid's step, are shared by ~8 grid points each.
#pragma once
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "pfill/boundary.hpp"

namespace pfill {

class DepthTest {
 public:
  /// `lattice_origin` and `step`: the search grid's (corners at origin + 2 step (i, j, k)).
  DepthTest(const Boundary& boundary, double depth, const Vec3& lattice_origin, double step);

  /// The exact test, with the surface samples first.
  bool deep(const Vec3& p) const { return !near_wall(p) && exact(p); }
  /// deep() of each point, in parallel, with the corners' bound between.
  std::vector<uint8_t> deep(const std::vector<Vec3>& points);

  /// A voxel at or beside p's holds a point of the surface: then
  /// |signed distance(p)| < depth.
  bool near_wall(const Vec3& p) const;

 private:
  bool exact(const Vec3& p) const;
  uint64_t corner_key(const Vec3& p) const;
  void mark_wall_voxels(const Mesh& mesh);
  int64_t voxel_of(const Vec3& p) const;  ///< -1 outside the voxels' box
  Vec3 corner(uint64_t key) const;
  void evaluate_corners(std::vector<uint64_t> keys);

  const Boundary& boundary_;
  double depth_;
  bool lipschitz_;  ///< closed, not self-intersecting, one part: the corners' bound holds
  Vec3 origin_;
  double corner_step_;
  // Voxels of depth / sqrt(6) over the mesh's box (two voxels of margin), a bit each: set where the surface is.
  double voxel_ = 1;
  Vec3 voxel_origin_;
  int64_t voxel_dims_[3] = {0, 0, 0};
  std::vector<uint64_t> wall_;
  std::unordered_map<uint64_t, double> corners_;  ///< signed distance at each corner asked so far
};

}  // namespace pfill

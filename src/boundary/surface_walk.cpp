// Closest points by a walk over the triangles (boundary/surface_walk.hpp).
#include "boundary/surface_walk.hpp"

#include "boundary/point_triangle.hpp"

namespace pfill {

SurfaceWalk::SurfaceWalk(const Mesh& mesh, double orientation)
    : mesh_(mesh), orientation_(orientation), normals_(compute_surface_normals(mesh)) {
  first_.assign(mesh.positions.size() + 1, 0);
  for (const Triangle& t : mesh.triangles)
    for (uint32_t v : t) ++first_[v + 1];
  for (size_t v = 0; v < mesh.positions.size(); ++v) first_[v + 1] += first_[v];
  around_.resize(first_.back());
  std::vector<uint32_t> at(first_.begin(), first_.end() - 1);
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (uint32_t v : mesh.triangles[t]) around_[at[v]++] = static_cast<uint32_t>(t);
}

bool SurfaceWalk::project(const Vec3& p, uint32_t& triangle, Vec3& point, Vec3& normal) const {
  auto test = [&](uint32_t t) {
    const Triangle& tri = mesh_.triangles[t];
    return closest_point_on_triangle(p, mesh_.positions[tri[0]], mesh_.positions[tri[1]], mesh_.positions[tri[2]]);
  };
  PointTriangleResult best = test(triangle);
  // Inside its own triangle: no neighbour is closer unless the surface
  // folds back within the step, which the relaxation's steps are too short for.
  for (int step = 0; best.feature != TriangleFeature::Face && step < 8; ++step) {
    uint32_t next = triangle;
    for (uint32_t v : mesh_.triangles[triangle])
      for (uint32_t k = first_[v]; k < first_[v + 1]; ++k) {
        const uint32_t t = around_[k];
        if (t == triangle) continue;
        const PointTriangleResult r = test(t);
        if (r.distance2 < best.distance2) best = r, next = t;
      }
    if (next == triangle) break;  // a local minimum: settled
    triangle = next;
    if (step == 7) return false;
  }
  point = best.point;
  bool ok = false;
  normal = normals_.pseudonormal(mesh_, triangle, best.feature, &ok) * orientation_;
  if (normal == Vec3{}) normal = normals_.face[triangle] * orientation_;
  return normal != Vec3{};
}

}  // namespace pfill

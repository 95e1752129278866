// The closed parts of a mesh's solid (mesh_parts.hpp).
#include "fill/mesh_parts.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "pfill/mesh_diagnostics.hpp"

namespace pfill {
namespace {

// Whether the ray from `o` along `d` crosses triangle (a, b, c) (Moeller-Trumbore).
bool ray_crosses(const Vec3& o, const Vec3& d, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = cross(d, e2);
  const double det = dot(e1, p);
  if (det == 0) return false;
  const Vec3 s = o - a;
  const double u = dot(s, p) / det;
  if (u < 0 || u > 1) return false;
  const Vec3 q = cross(s, e1);
  const double v = dot(d, q) / det;
  if (v < 0 || u + v > 1) return false;
  return dot(e2, q) / det > 0;
}

struct Component {
  double volume = 0;  ///< signed, with the solid's sign when it encloses solid
  Box3 bounds;
  std::vector<uint32_t> triangles;
};

// Whether component `c` encloses p: a majority of three rays crosses it an
// odd number of times (a ray through an edge or vertex may count twice).
bool encloses(const Mesh& mesh, const Component& c, const Vec3& p) {
  static const std::array<Vec3, 3> kDirections = {Vec3(0.5773, 0.5774, 0.5775), Vec3(-0.3124, 0.8123, -0.4925),
                                                  Vec3(0.7071, -0.1093, 0.6986)};
  for (int a = 0; a < 3; ++a)
    if (p[a] < c.bounds.lo[a] || p[a] > c.bounds.hi[a]) return false;
  int odd = 0;
  for (const Vec3& d : kDirections) {
    int crossings = 0;
    for (uint32_t t : c.triangles) {
      const Triangle& tri = mesh.triangles[t];
      crossings += ray_crosses(p, d, mesh.positions[tri[0]], mesh.positions[tri[1]], mesh.positions[tri[2]]) ? 1 : 0;
    }
    odd += crossings % 2;
  }
  return odd >= 2;
}

}  // namespace

MeshParts::MeshParts(const Boundary& boundary) : boundary_(boundary) {
  const Mesh& mesh = boundary.mesh();
  component_of_triangle_ = triangle_components(mesh);
  std::vector<Component> components;
  const double solid_sign = boundary.inward_oriented() ? -1 : 1;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uint32_t c = component_of_triangle_[t];
    if (c >= components.size()) components.resize(c + 1);
    const Triangle& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &d = mesh.positions[tri[2]];
    components[c].volume += solid_sign * dot(a, cross(b, d)) / 6;
    for (const Vec3* v : {&a, &b, &d}) components[c].bounds.add(*v);
    components[c].triangles.push_back(static_cast<uint32_t>(t));
  }
  // Parts first, numbered in component order; then each cavity to its part.
  constexpr uint32_t kNone = UINT32_MAX;
  part_of_component_.assign(components.size(), kNone);
  for (size_t c = 0; c < components.size(); ++c)
    if (components[c].volume >= 0) part_of_component_[c] = static_cast<uint32_t>(parts_++);
  for (size_t c = 0; c < components.size(); ++c) {
    if (part_of_component_[c] != kNone) continue;
    const Vec3& corner = mesh.positions[mesh.triangles[components[c].triangles[0]][0]];
    size_t smallest = kNone;
    for (size_t o = 0; o < components.size(); ++o) {
      if (components[o].volume < 0 || !encloses(mesh, components[o], corner)) continue;
      if (smallest == kNone || components[o].volume < components[smallest].volume) smallest = o;
    }
    // (a cavity in no part: a part turned inside out, a part of its own)
    part_of_component_[c] = smallest != kNone ? part_of_component_[smallest] : static_cast<uint32_t>(parts_++);
  }
}

uint32_t MeshParts::part_at(const Vec3& p, double depth) const {
  std::optional<ClosestPoint> near = boundary_.closest_within(p, depth * (1 + 1e-9) + 1e-12);
  const uint32_t triangle = near ? near->triangle : boundary_.closest(p).triangle;
  return part_of_component_[component_of_triangle_[triangle]];
}

}  // namespace pfill

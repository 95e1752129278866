// Pseudonormals and the closed/consistent test behind fast_signed_distance.
#include "boundary/surface_normals.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace pfill {

SurfaceNormals compute_surface_normals(const Mesh& mesh) {
  SurfaceNormals s;
  const size_t nt = mesh.triangles.size();
  s.face.resize(nt);
  s.triangle_edges.resize(nt);
  s.vertex.assign(mesh.positions.size(), Vec3{});

  // Edges keyed by (lower, higher) vertex id; `winding` sums +1 for a
  // traversal lower->higher and -1 for the reverse, so a consistently
  // oriented manifold edge has two faces and winding 0.
  std::unordered_map<uint64_t, uint32_t> edge_ids;
  edge_ids.reserve(nt * 2);
  std::vector<int> faces_per_edge, winding;
  std::vector<uint8_t> face_degenerate(nt, 0);

  for (size_t t = 0; t < nt; ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
    const Vec3 n = cross(b - a, c - a);
    s.signed_volume += dot(a, cross(b, c)) / 6.0;
    const double scale2 = std::max({dot(b - a, b - a), dot(c - a, c - a), dot(c - b, c - b)});
    face_degenerate[t] = dot(n, n) <= 1e-24 * scale2 * scale2;
    s.face[t] = face_degenerate[t] ? Vec3{} : normalize(n);

    for (int k = 0; k < 3; ++k) {
      const uint32_t v0 = tri[k], v1 = tri[(k + 1) % 3];
      const uint64_t key = (static_cast<uint64_t>(std::min(v0, v1)) << 32) | std::max(v0, v1);
      auto [it, inserted] = edge_ids.emplace(key, static_cast<uint32_t>(faces_per_edge.size()));
      if (inserted) {
        faces_per_edge.push_back(0);
        winding.push_back(0);
        s.edge.emplace_back();
      }
      const uint32_t e = it->second;
      s.triangle_edges[t][k] = e;
      faces_per_edge[e] += 1;
      winding[e] += v0 < v1 ? 1 : -1;
      s.edge[e] += s.face[t];

      // Angle at vertex k, the weight of this face in the vertex normal.
      const Vec3& p = mesh.positions[tri[k]];
      const Vec3 e1 = mesh.positions[tri[(k + 1) % 3]] - p, e2 = mesh.positions[tri[(k + 2) % 3]] - p;
      const double angle = std::atan2(length(cross(e1, e2)), dot(e1, e2));
      s.vertex[tri[k]] += s.face[t] * angle;
    }
  }

  const size_t ne = faces_per_edge.size();
  s.edge_ok.assign(ne, 0);
  for (size_t e = 0; e < ne; ++e) {
    s.edge_ok[e] = faces_per_edge[e] == 2 && winding[e] == 0;
    s.edge[e] = normalize(s.edge[e]);
  }
  s.closed = std::all_of(s.edge_ok.begin(), s.edge_ok.end(), [](uint8_t ok) { return ok != 0; });

  s.face_ok.assign(nt, 0);
  s.vertex_ok.assign(mesh.positions.size(), 1);
  for (size_t t = 0; t < nt; ++t) {
    const auto& te = s.triangle_edges[t];
    s.face_ok[t] = !face_degenerate[t] && s.edge_ok[te[0]] && s.edge_ok[te[1]] && s.edge_ok[te[2]];
    if (!s.face_ok[t])
      for (uint32_t v : mesh.triangles[t]) s.vertex_ok[v] = 0;
  }
  // An edge next to a degenerate or badly connected face is not trusted either.
  for (size_t t = 0; t < nt; ++t)
    if (!s.face_ok[t])
      for (uint32_t e : s.triangle_edges[t]) s.edge_ok[e] = 0;
  for (Vec3& n : s.vertex) n = normalize(n);
  return s;
}

Vec3 SurfaceNormals::pseudonormal(const Mesh& mesh, uint32_t t, TriangleFeature feature, bool* ok) const {
  const Triangle& tri = mesh.triangles[t];
  const auto& te = triangle_edges[t];
  switch (feature) {
    case TriangleFeature::Face: *ok = face_ok[t]; return face[t];
    case TriangleFeature::EdgeAB: *ok = edge_ok[te[0]]; return edge[te[0]];
    case TriangleFeature::EdgeBC: *ok = edge_ok[te[1]]; return edge[te[1]];
    case TriangleFeature::EdgeCA: *ok = edge_ok[te[2]]; return edge[te[2]];
    case TriangleFeature::VertexA: *ok = vertex_ok[tri[0]]; return vertex[tri[0]];
    case TriangleFeature::VertexB: *ok = vertex_ok[tri[1]]; return vertex[tri[1]];
    case TriangleFeature::VertexC: *ok = vertex_ok[tri[2]]; return vertex[tri[2]];
  }
  *ok = false;
  return face[t];
}

}  // namespace pfill

// Topology and measures of a triangle mesh for `pfill info`.
#include "pfill/mesh_diagnostics.hpp"

#include <cmath>
#include <numeric>
#include <unordered_map>

namespace pfill {
namespace {


uint64_t edge_key(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | b;
}

struct EdgeUse {
  uint32_t count = 0;
  uint32_t forward = 0;  ///< uses walking it from the smaller to the larger index
};

struct DisjointSets {
  std::vector<uint32_t> parent;
  explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

double triangle_area(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * length(cross(b - a, c - a)); }

// Volume of the tetrahedron (origin, a, b, c) relative to `o`, signed.
double signed_tet_volume(const Vec3& o, const Vec3& a, const Vec3& b, const Vec3& c) {
  return dot(a - o, cross(b - o, c - o)) / 6.0;
}

}  // namespace

MeshDiagnostics diagnose(const Mesh& mesh) {
  MeshDiagnostics d;
  d.triangles = mesh.triangles.size();
  const size_t nv = mesh.positions.size();

  std::vector<bool> used(nv, false);
  for (const Triangle& t : mesh.triangles)
    for (uint32_t v : t) used[v] = true;
  for (size_t i = 0; i < nv; ++i)
    if (used[i]) {
      ++d.vertices;
      d.bounds.add(mesh.positions[i]);
    }

  // Volumes are taken about the box centre: it keeps the sums well conditioned.
  const Vec3 origin = d.bounds.centre();
  const double tiny_area = 1e-14 * d.bounds.diagonal() * d.bounds.diagonal();

  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(mesh.triangles.size() * 2);
  DisjointSets sets(nv);
  for (const Triangle& t : mesh.triangles) {
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const double area = triangle_area(a, b, c);
    d.surface_area += area;
    d.signed_volume += signed_tet_volume(origin, a, b, c);
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2] || area <= tiny_area) ++d.degenerate_triangles;
    for (int k = 0; k < 3; ++k) {
      const uint32_t u = t[k], v = t[(k + 1) % 3];
      if (u == v) continue;
      EdgeUse& e = edges[edge_key(u, v)];
      ++e.count;
      if (u < v) ++e.forward;
    }
    sets.unite(t[0], t[1]);
    sets.unite(t[1], t[2]);
  }

  d.edges = edges.size();
  // Boundary edges, directed as their one triangle walks them, chained into loops.
  std::unordered_multimap<uint32_t, uint32_t> boundary_next;
  for (const auto& [key, use] : edges) {
    if (use.count == 1) {
      ++d.boundary_edges;
      const uint32_t lo = static_cast<uint32_t>(key >> 32), hi = static_cast<uint32_t>(key & 0xffffffffu);
      if (use.forward == 1) boundary_next.emplace(lo, hi);
      else boundary_next.emplace(hi, lo);
    } else if (use.count > 2) {
      ++d.non_manifold_edges;
    } else if (use.forward != 1) {
      ++d.misoriented_edges;
    }
  }

  // Close each hole with a fan to its loop's centroid, so the volume of an
  // open scan is an estimate of the solid's rather than of a fragment.
  while (!boundary_next.empty()) {
    auto it = boundary_next.begin();
    const uint32_t start = it->first;
    std::vector<uint32_t> loop{start};
    uint32_t cur = it->second;
    boundary_next.erase(it);
    while (cur != start) {
      loop.push_back(cur);
      auto next = boundary_next.find(cur);
      if (next == boundary_next.end()) break;  // a chain that does not close (non-manifold)
      cur = next->second;
      boundary_next.erase(next);
    }
    ++d.boundary_loops;
    if (loop.size() < 3) continue;
    Vec3 centroid;
    for (uint32_t v : loop) centroid += mesh.positions[v];
    centroid = centroid / static_cast<double>(loop.size());
    // The cap walks the loop backwards so that it agrees with the surface.
    for (size_t i = 0; i < loop.size(); ++i) {
      const Vec3& a = mesh.positions[loop[i]];
      const Vec3& b = mesh.positions[loop[(i + 1) % loop.size()]];
      d.signed_volume += signed_tet_volume(origin, b, a, centroid);
    }
  }

  std::vector<bool> root(nv, false);
  for (size_t i = 0; i < nv; ++i)
    if (used[i] && !root[sets.find(static_cast<uint32_t>(i))]) {
      root[sets.find(static_cast<uint32_t>(i))] = true;
      ++d.components;
    }

  if (d.boundary_edges == 0 && d.signed_volume != 0 && edges_balanced(mesh))
    d.winding = sweep_winding(mesh, d.signed_volume < 0 ? -1 : 1);

  if (d.watertight()) {
    // Euler: V - E + F = 2 (C - g) summed over components.
    const long long chi = static_cast<long long>(d.vertices) - static_cast<long long>(d.edges) +
                          static_cast<long long>(d.triangles);
    d.genus = static_cast<int>(static_cast<long long>(d.components) - chi / 2);
  }
  return d;
}

std::vector<uint32_t> triangle_components(const Mesh& mesh) {
  DisjointSets sets(mesh.positions.size());
  for (const Triangle& t : mesh.triangles) {
    sets.unite(t[0], t[1]);
    sets.unite(t[1], t[2]);
  }
  constexpr uint32_t kUnnumbered = UINT32_MAX;
  std::vector<uint32_t> number(mesh.positions.size(), kUnnumbered), out(mesh.triangles.size());
  uint32_t next = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    uint32_t& n = number[sets.find(mesh.triangles[t][0])];
    if (n == kUnnumbered) n = next++;
    out[t] = n;
  }
  return out;
}

}  // namespace pfill

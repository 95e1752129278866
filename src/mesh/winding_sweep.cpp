// The winding number of a closed mesh along a grid of +z rays: a 2-D bin of
// the triangles' xy boxes, then per ray the crossings sorted by height.
#include "pfill/winding_sweep.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace pfill {
namespace {

// Twice the signed area of (a, b, p) in xy, computed from the lower vertex
// index first, so the two triangles that share an edge get the same value
// with opposite signs, bit for bit.
double edge_function(const Mesh& m, uint32_t a, uint32_t b, double px, double py) {
  const bool swap = a > b;
  const Vec3& u = m.positions[swap ? b : a];
  const Vec3& v = m.positions[swap ? a : b];
  const double f = (v.x - u.x) * (py - u.y) - (v.y - u.y) * (px - u.x);
  return swap ? -f : f;
}

struct Crossing {
  double z;
  int sign;
};

}  // namespace

bool edges_balanced(const Mesh& mesh) {
  std::unordered_map<uint64_t, int64_t> balance;  // forward minus backward walks of each edge
  balance.reserve(mesh.triangles.size() * 2);
  for (const Triangle& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = t[k], b = t[(k + 1) % 3];
      if (a == b) continue;
      const uint64_t key = (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      balance[key] += a < b ? 1 : -1;
    }
  return std::all_of(balance.begin(), balance.end(), [](const auto& e) { return e.second == 0; });
}

WindingSweep sweep_winding(const Mesh& mesh, int orientation, int rays_per_axis) {
  WindingSweep out;
  const Box3 box = mesh.bounds();
  const int n = std::max(2, rays_per_axis);
  const double hx = box.size().x / n, hy = box.size().y / n;
  if (!(hx > 0) || !(hy > 0)) return out;

  // Triangles by the cells their xy boxes touch.
  std::vector<std::vector<uint32_t>> cells(static_cast<size_t>(n) * n);
  auto cell_of = [&](double v, double lo, double h) {
    return std::clamp(static_cast<int>(std::floor((v - lo) / h)), 0, n - 1);
  };
  for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
    const int i0 = cell_of(std::min({a.x, b.x, c.x}), box.lo.x, hx), i1 = cell_of(std::max({a.x, b.x, c.x}), box.lo.x, hx);
    const int j0 = cell_of(std::min({a.y, b.y, c.y}), box.lo.y, hy), j1 = cell_of(std::max({a.y, b.y, c.y}), box.lo.y, hy);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) cells[static_cast<size_t>(j) * n + i].push_back(t);
  }

  std::vector<Crossing> crossings;
  double length_inside = 0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      // Irrational offsets within the cell: no grid of the mesh lines up with them.
      const double px = box.lo.x + (i + 0.5 + 0.2 * std::sin(1.0 + i * 0.7548776662 + j * 0.5698402910)) * hx;
      const double py = box.lo.y + (j + 0.5 + 0.2 * std::sin(2.0 + i * 0.5698402910 + j * 0.7548776662)) * hy;
      crossings.clear();
      for (uint32_t t : cells[static_cast<size_t>(j) * n + i]) {
        const Triangle& tri = mesh.triangles[t];
        double w[3];
        bool hit = true;
        int side = 0;  // +1: the triangle faces +z in xy, -1: -z
        for (int k = 0; k < 3 && hit; ++k) {
          const uint32_t a = tri[k], b = tri[(k + 1) % 3];
          w[k] = edge_function(mesh, a, b, px, py);
          // On an edge (w == 0) the hit goes to the triangle that walks it
          // from its lower index: one of the two that share it.
          const int s = w[k] > 0 ? 1 : w[k] < 0 ? -1 : (a < b ? 1 : -1);
          if (side == 0) side = s;
          else if (s != side) hit = false;
        }
        if (!hit) continue;
        const double area = w[0] + w[1] + w[2];
        if (area == 0) continue;  // seen edge-on
        const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
        // w[k] weighs the vertex opposite edge k (edge k runs from vertex k to k+1).
        const double z = (w[1] * a.z + w[2] * b.z + w[0] * c.z) / area;
        // Going up through a face that looks down enters the solid.
        crossings.push_back({z, side < 0 ? orientation : -orientation});
      }
      ++out.rays;
      if (crossings.empty()) continue;
      std::sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) { return x.z < y.z; });
      int winding = 0;
      for (size_t k = 0; k < crossings.size(); ++k) {
        winding += crossings[k].sign;
        out.max_winding = std::max(out.max_winding, winding);
        out.min_winding = std::min(out.min_winding, winding);
        if (winding != 0 && k + 1 < crossings.size()) length_inside += crossings[k + 1].z - crossings[k].z;
      }
    }
  out.volume = length_inside * hx * hy;
  return out;
}

}  // namespace pfill

// Meshes generated in code: built-in shapes and test fixtures.
#include "pfill/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "pfill/error.hpp"

namespace pfill {
namespace {


// Builds the six faces of [-h, h]^3; `skip_top` leaves out the +z face.
Mesh make_cube_faces(double h, int n, bool skip_top) {
  if (n < 1) throw Error("cube: need at least one quad per face edge");
  struct Face { Vec3 normal, u, v; };
  // u x v = outward normal, so quads walked in (u, v) order face outwards.
  const Face faces[6] = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
  };
  Mesh mesh;
  for (const Face& f : faces) {
    if (skip_top && f.normal.z > 0) continue;
    const uint32_t base = static_cast<uint32_t>(mesh.positions.size());
    for (int b = 0; b <= n; ++b)
      for (int a = 0; a <= n; ++a) {
        const double s = -h + 2.0 * h * a / n, t = -h + 2.0 * h * b / n;
        mesh.positions.push_back(f.normal * h + f.u * s + f.v * t);
      }
    auto id = [&](int a, int b) { return base + static_cast<uint32_t>(b * (n + 1) + a); };
    auto uv = [&](int a, int b) { return Uv{static_cast<float>(a) / n, static_cast<float>(b) / n}; };
    for (int b = 0; b < n; ++b)
      for (int a = 0; a < n; ++a) {
        mesh.triangles.push_back({id(a, b), id(a + 1, b), id(a + 1, b + 1)});
        mesh.corner_uvs.insert(mesh.corner_uvs.end(), {uv(a, b), uv(a + 1, b), uv(a + 1, b + 1)});
        mesh.triangles.push_back({id(a, b), id(a + 1, b + 1), id(a, b + 1)});
        mesh.corner_uvs.insert(mesh.corner_uvs.end(), {uv(a, b), uv(a + 1, b + 1), uv(a, b + 1)});
      }
  }
  weld_vertices(mesh);  // edge vertices are computed identically by both faces
  return mesh;
}

}  // namespace

Mesh make_icosphere(double radius, int subdivisions) {
  if (subdivisions < 0 || subdivisions > 8) throw Error("icosphere: subdivisions must be in 0..8");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<Triangle> tris = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (Vec3& v : p) v = normalize(v);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
      const auto key = std::minmax(a, b);
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      p.push_back(normalize((p[a] + p[b]) * 0.5));
      const uint32_t id = static_cast<uint32_t>(p.size() - 1);
      midpoint.emplace(key, id);
      return id;
    };
    std::vector<Triangle> next;
    next.reserve(tris.size() * 4);
    for (const Triangle& tr : tris) {
      const uint32_t a = mid(tr[0], tr[1]), b = mid(tr[1], tr[2]), c = mid(tr[2], tr[0]);
      next.push_back({tr[0], a, c});
      next.push_back({tr[1], b, a});
      next.push_back({tr[2], c, b});
      next.push_back({a, b, c});
    }
    tris = std::move(next);
  }
  Mesh mesh;
  for (const Vec3& v : p) mesh.positions.push_back(v * radius);
  mesh.triangles = std::move(tris);
  mesh.source = "icosphere";
  return mesh;
}

Mesh make_cube(double half_size, int n) {
  Mesh mesh = make_cube_faces(half_size, n, false);
  mesh.source = "cube";
  return mesh;
}

Mesh make_open_cube(double half_size, int n) {
  Mesh mesh = make_cube_faces(half_size, n, true);
  mesh.source = "open cube";
  return mesh;
}

Mesh make_inside_out_cube(double half_size, int n) {
  Mesh mesh = make_cube_faces(half_size, n, false);
  flip_orientation(mesh);
  mesh.source = "inside-out cube";
  return mesh;
}

Mesh make_torus(double ring_radius, double tube_radius, int nu, int nv) {
  if (nu < 3 || nv < 3) throw Error("torus: need at least 3 segments each way");
  if (!(tube_radius > 0 && tube_radius < ring_radius))
    throw Error("torus: the tube radius must be positive and smaller than the ring radius");
  Mesh mesh;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const double th = 2 * kPi * i / nu, ph = 2 * kPi * j / nv;
      const double w = ring_radius + tube_radius * std::cos(ph);
      mesh.positions.push_back({w * std::cos(th), w * std::sin(th), tube_radius * std::sin(ph)});
    }
  auto id = [&](int i, int j) { return static_cast<uint32_t>((i % nu) * nv + (j % nv)); };
  // (d/dtheta) x (d/dphi) points out of the tube, so this winding faces out.
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  mesh.source = "torus";
  return mesh;
}

std::vector<std::string> builtin_shape_names() { return {"torus", "sphere", "cube"}; }

Mesh make_builtin(const std::string& name) {
  Mesh mesh;
  if (name == "torus") mesh = make_torus(1.0, 0.45, 96, 48);
  else if (name == "sphere") mesh = make_icosphere(1.0, 4);
  else if (name == "cube") mesh = make_cube(1.0, 4);
  else {
    std::string list;
    for (const std::string& n : builtin_shape_names()) list += (list.empty() ? "" : ", ") + n;
    throw Error("unknown built-in shape '" + name + "'; choose one of: " + list);
  }
  mesh.source = "built-in " + name;
  return mesh;
}

}  // namespace pfill

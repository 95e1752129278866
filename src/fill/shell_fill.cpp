// `fill --shell`: the inset mesh the inner fill runs in, and the inner
// spheres joined with the boundary particles (include/pfill/shell_fill.hpp).
#include "pfill/shell_fill.hpp"

#include <algorithm>
#include <cmath>

#include "fill/centre_grid.hpp"

namespace pfill {

Mesh inset_mesh(const Mesh& mesh, double inset, bool inward_oriented) {
  Mesh out = mesh;
  const size_t nv = mesh.positions.size();
  std::vector<Vec3> sum(nv);
  std::vector<double> min_cos(nv, 1.0);
  std::vector<Vec3> face_normal(mesh.triangles.size());
  const double orient = inward_oriented ? -1.0 : 1.0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 n = cross(mesh.positions[tri[1]] - mesh.positions[tri[0]], mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    const double l = length(n);
    if (!(l > 0)) continue;
    face_normal[t] = n * (orient / l);
    for (int k = 0; k < 3; ++k) {  // angle-weighted
      const Vec3 e1 = mesh.positions[tri[(k + 1) % 3]] - mesh.positions[tri[k]];
      const Vec3 e2 = mesh.positions[tri[(k + 2) % 3]] - mesh.positions[tri[k]];
      const double c = dot(e1, e2) / (length(e1) * length(e2));
      sum[tri[k]] = sum[tri[k]] + face_normal[t] * std::acos(std::clamp(c, -1.0, 1.0));
    }
  }
  std::vector<Vec3> dir(nv);
  for (size_t v = 0; v < nv; ++v) dir[v] = length(sum[v]) > 0 ? normalize(sum[v]) : Vec3();
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (uint32_t v : mesh.triangles[t]) min_cos[v] = std::min(min_cos[v], dot(face_normal[t], dir[v]));
  for (size_t v = 0; v < nv; ++v) {
    const double scale = 1.0 / std::clamp(min_cos[v], 1.0 / 3.0, 1.0);
    out.positions[v] = mesh.positions[v] - dir[v] * (inset * scale);
  }
  out.source = mesh.source;
  return out;
}

ShellFill join_shell(const ParticleSet& inner, const SurfaceSamples& shell, double max_overlap) {
  ShellFill out;
  double max_r = shell.radius;
  for (double r : inner.radii) max_r = std::max(max_r, r);
  const CentreGrid grid(shell.positions, 2 * max_r);
  std::vector<uint8_t> keep(inner.size(), 1);
  for (size_t i = 0; i < inner.size(); ++i) {
    const double r = inner.radii[i];
    grid.for_near(inner.positions[i], [&](uint32_t j) {
      if (length(shell.positions[j] - inner.positions[i]) < r + shell.radius - max_overlap * r) keep[i] = 0;
    });
  }
  ParticleSet& p = out.particles;
  uint64_t last_id = 0;
  for (size_t i = 0; i < inner.size(); ++i) {
    last_id = std::max(last_id, inner.id(i));
    if (!keep[i]) {
      ++out.removed;
      continue;
    }
    p.positions.push_back(inner.positions[i]);
    p.radii.push_back(inner.radii[i]);
    if (inner.has_colours()) p.colours.push_back(inner.colours[i]);
    if (inner.has_velocities()) p.velocities.push_back(inner.velocities[i]);
    p.ids.push_back(inner.id(i));
  }
  out.inner = p.size();
  for (size_t j = 0; j < shell.positions.size(); ++j) {
    p.positions.push_back(shell.positions[j]);
    p.radii.push_back(shell.radius);
    if (inner.has_colours()) p.colours.push_back({128, 128, 128});
    if (inner.has_velocities()) p.velocities.push_back({});
    p.ids.push_back(++last_id);
  }
  out.attributes.kinds.assign(out.inner, 0);
  out.attributes.kinds.resize(p.size(), 1);
  out.attributes.normals.assign(out.inner, Vec3());
  out.attributes.normals.insert(out.attributes.normals.end(), shell.normals.begin(), shell.normals.end());
  out.attributes.areas.assign(out.inner, 0.0);
  out.attributes.areas.insert(out.attributes.areas.end(), shell.areas.begin(), shell.areas.end());
  return out;
}

}  // namespace pfill

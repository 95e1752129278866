// Generated bad meshes for the hardening tests: parts that overlap, a
// surface that passes through itself, repeated faces, scaled and moved
// copies (pfill::Mesh in memory; tests/mesh_writers.hpp writes them out).
#pragma once
#include "pfill/mesh.hpp"
#include "pfill/shapes.hpp"

namespace pfill::test {

/// `b`'s triangles and vertices appended to `a` (a second part).
inline Mesh merged(Mesh a, const Mesh& b) {
  const auto base = static_cast<uint32_t>(a.positions.size());
  a.positions.insert(a.positions.end(), b.positions.begin(), b.positions.end());
  for (Triangle t : b.triangles) a.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
  a.corner_colours.clear();
  a.corner_uvs.clear();
  a.triangle_materials.clear();
  return a;
}

inline Mesh moved(Mesh m, const Vec3& by, double scale = 1.0) {
  for (Vec3& p : m.positions) p = p * scale + by;
  return m;
}

/// Two unit cubes, the second shifted by (0.5, 0.5, 0.5): the union's
/// volume is 2 - 0.125 = 1.875.
inline Mesh overlapping_cubes() {
  const Mesh cube = moved(make_cube(0.5, 2), {0.5, 0.5, 0.5});
  return merged(cube, moved(cube, {0.5, 0.5, 0.5}));
}

/// One connected surface that passes through itself: the two overlapping
/// cubes welded where their grids meet (at (1, 0.5, 0.5) and the like,
/// points on both surfaces), so they are one part that is no closed solid
/// on its own side of the crossing.
inline Mesh self_intersecting_cubes() {
  Mesh m = overlapping_cubes();
  weld_vertices(m);
  return m;
}

}  // namespace pfill::test

// The colour of a mesh's surface at a point given by triangle and
// barycentric coordinates: corner colours x material factor x texture, all in
// linear light (see colour.hpp).
#include <string>
#include <vector>

#include "pfill/colour.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

// Material of triangle t, or -1: an empty triangle_materials means
// "material 0 for all" when there is one.
int material_of(const Mesh& mesh, size_t t) {
  if (!mesh.triangle_materials.empty()) return static_cast<int>(mesh.triangle_materials[t]);
  return mesh.materials.empty() ? -1 : 0;
}

}  // namespace

void check_surface_colour_inputs(const Mesh& mesh) {
  std::vector<char> used(mesh.materials.size(), 0);
  if (mesh.triangle_materials.empty()) {
    if (!used.empty()) used[0] = 1;
  } else {
    for (uint32_t m : mesh.triangle_materials)
      if (m < used.size()) used[m] = 1;
  }
  for (size_t m = 0; m < mesh.materials.size(); ++m) {
    const int texture = mesh.materials[m].texture;
    if (!used[m] || texture < 0) continue;
    if (!mesh.has_uvs())
      throw Error(mesh.source + ": material " + std::to_string(m) +
                  " has a base colour texture but the mesh has no texture coordinates (UVs); "
                  "export the mesh with UVs, or colour with --colour depth or #RRGGBB");
    if (static_cast<size_t>(texture) >= mesh.textures.size())
      throw Error(mesh.source + ": material " + std::to_string(m) + " names texture " + std::to_string(texture) +
                  " of " + std::to_string(mesh.textures.size()));
    const Texture& tex = mesh.textures[texture];
    if (tex.width <= 0 || tex.height <= 0 || tex.rgba.size() != static_cast<size_t>(tex.width) * tex.height * 4)
      throw Error(mesh.source + ": texture '" + tex.name + "' is empty or its pixel data does not match its size");
  }
  if (mesh.has_colours() && mesh.corner_colours.size() != 3 * mesh.triangles.size())
    throw Error(mesh.source + ": corner colour count does not match the triangles (internal error)");
}

Rgba surface_colour(const Mesh& mesh, uint32_t triangle, double u, double v) {
  if (triangle >= mesh.triangles.size())
    throw Error(mesh.source + ": surface colour asked for triangle " + std::to_string(triangle) + " of " +
                std::to_string(mesh.triangles.size()));
  const double w[3] = {1 - u - v, u, v};
  const size_t corner = 3 * static_cast<size_t>(triangle);
  double c[4] = {1, 1, 1, 1};
  if (mesh.has_colours()) {
    for (int ch = 0; ch < 4; ++ch) {
      double sum = 0;
      for (int k = 0; k < 3; ++k) {
        const float value = mesh.corner_colours[corner + k][ch];
        sum += w[k] * (ch < 3 ? srgb_to_linear(value) : value);
      }
      c[ch] = sum;
    }
  }
  const int material = material_of(mesh, triangle);
  if (material >= 0) {
    const Material& m = mesh.materials[material];
    for (int ch = 0; ch < 4; ++ch) c[ch] *= m.base_colour_factor[ch];
    if (m.texture >= 0) {
      if (!mesh.has_uvs()) check_surface_colour_inputs(mesh);  // throws the message naming the mesh
      double s = 0, t = 0;
      for (int k = 0; k < 3; ++k) {
        s += w[k] * mesh.corner_uvs[corner + k][0];
        t += w[k] * mesh.corner_uvs[corner + k][1];
      }
      const Rgba texel = sample_texture(mesh.textures[m.texture], s, t);
      for (int ch = 0; ch < 4; ++ch) c[ch] *= texel[ch];
    }
  }
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2]), static_cast<float>(c[3])};
}

}  // namespace pfill

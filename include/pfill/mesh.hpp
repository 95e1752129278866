/// @file mesh.hpp
/// @brief The one triangle-mesh type of pfill, as every loader returns it.
///
/// Vertices are welded by position (loaders do it), so topology checks see
/// the real connectivity. Surface attributes that may differ across a seam
/// (UVs, colours) are therefore stored per triangle corner, not per vertex:
/// corner k of triangle t is entry 3*t+k. Colour transfer reads them with the
/// closest point's triangle index and barycentric coordinates.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

using Triangle = std::array<uint32_t, 3>;

/// The largest |coordinate| pfill accepts, in meshes and particle files.
/// Embree computes in single precision and aborts beyond about 1.8e18; this
/// leaves room for the rays and boxes built around the points.
constexpr double kMaxCoordinate = 1e15;
using Rgba = std::array<float, 4>;  ///< colour, components in [0, 1]
using Uv = std::array<float, 2>;

enum class WrapMode { Repeat, ClampToEdge, MirroredRepeat };

/// A decoded 8-bit RGBA image; row 0 is the top row (as glTF UVs expect:
/// v = 0 is the top edge).
struct Texture {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgba;  ///< width*height*4 bytes, sRGB-encoded
  WrapMode wrap_s = WrapMode::Repeat;
  WrapMode wrap_t = WrapMode::Repeat;
  std::string name;           ///< where it came from, for messages
};

/// The part of a material that colours particles.
struct Material {
  Rgba base_colour_factor{1, 1, 1, 1};  ///< linear, multiplies the texture
  int texture = -1;                     ///< index into Mesh::textures, or -1
};

struct Mesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;

  /// Per-corner colours (3 per triangle) in sRGB-encoded [0, 1], as a user
  /// sees them; loaders convert glTF's linear COLOR_0. Empty if none.
  std::vector<Rgba> corner_colours;
  /// Per-corner texture coordinates (3 per triangle); empty if none.
  std::vector<Uv> corner_uvs;

  std::vector<Texture> textures;
  std::vector<Material> materials;
  /// Material of each triangle; empty means material 0 (if any) for all.
  std::vector<uint32_t> triangle_materials;

  std::string source;  ///< file name or shape name, for messages
  /// Faces load_mesh turned so that each part's winding agrees (orient_faces).
  size_t turned_faces = 0;

  size_t vertex_count() const { return positions.size(); }
  size_t triangle_count() const { return triangles.size(); }
  bool has_colours() const { return !corner_colours.empty(); }
  bool has_uvs() const { return !corner_uvs.empty(); }

  Box3 bounds() const {
    Box3 b;
    for (const Vec3& p : positions) b.add(p);
    return b;
  }
};

/// Merges vertices whose positions are equal within `tolerance` (absolute;
/// 0 means bit-identical), remaps the triangles and drops the vertices no
/// triangle uses. Corner attributes are untouched (they are per corner).
/// Returns the number of vertices removed.
size_t weld_vertices(Mesh& mesh, double tolerance = 0.0);

/// Removes repeated faces (the same three vertices): a repeat wound the same
/// way is dropped, and a pair wound opposite ways (a sheet of no
/// thickness) goes altogether, so ray crossings and the winding number
/// count each face once. Returns the number of triangles removed.
/// Where two triangles walk a shared edge the same way (inconsistent
/// winding: the signed volume, and so the radius, would be wrong), turns
/// faces so that each connected part agrees with itself and faces outward
/// (inward for a part that others enclose: a cavity); parts that cannot be
/// oriented (non-orientable) stay as they are. Returns how many faces it
/// turned; 0 and no change for a consistent mesh. (src/mesh/orient_faces.cpp)
size_t orient_faces(Mesh& mesh);

size_t remove_duplicate_triangles(Mesh& mesh);

/// Reverses the winding of every triangle (and its corner attributes), for
/// meshes found to be inside-out.
void flip_orientation(Mesh& mesh);

/// Throws pfill::Error naming `mesh.source` if the mesh has no triangles, an
/// index out of range, a non-finite coordinate or one beyond kMaxCoordinate,
/// or attribute arrays of the wrong length.
void validate(const Mesh& mesh);

}  // namespace pfill

/// @file mesh_io.hpp
/// @brief Reading triangle meshes from files: glTF/GLB (tinygltf), the
/// report's SMF (our own parser), and OBJ, STL, PLY, OFF, FBX, DAE, 3DS and
/// the other formats assimp reads.
///
/// load_mesh() is the entry point: it picks the reader by extension, welds
/// duplicate vertices by position and validates the result. Every failure is
/// a pfill::Error whose message names the file and the problem; no reader
/// returns an empty mesh or asserts on bad input.
#pragma once
#include <string>
#include <vector>

#include "pfill/mesh.hpp"

namespace pfill {

struct LoadOptions {
  /// Weld vertices closer than this fraction of the bounding-box diagonal;
  /// 0 welds only bit-identical positions (what exporters that split at UV
  /// seams produce).
  double weld_tolerance = 0.0;
};

/// Reads `path` (format by extension, case-insensitive), welds and validates.
/// Sets Mesh::source to `path`. Throws pfill::Error naming the file on a
/// missing, unreadable, truncated or malformed file, out-of-range indices,
/// non-finite coordinates, zero triangles, an unsupported primitive mode or
/// an unknown extension; exceptions of the underlying libraries are turned
/// into pfill::Error with the file name.
Mesh load_mesh(const std::string& path, const LoadOptions& options = {});

/// The extensions load_mesh accepts, lower case with the dot (".obj", ...).
std::vector<std::string> supported_mesh_extensions();

/// glTF 2.0 (.gltf or .glb, told apart by content): the default scene's node
/// graph with its transforms, every triangle primitive merged (strips and fans
/// triangulated), COLOR_0 (converted to sRGB-encoded), the UV set of the base
/// colour texture, materials' base colour factor and texture. Not welded.
Mesh load_gltf(const std::string& path);

/// SMF (Garland's format, used by the report): `v`, `f` (polygons become
/// fans), `c` with `bind c vertex|face|corner`, `#` comments; other commands
/// are ignored. Errors name the line. Not welded.
Mesh load_smf(const std::string& path);

/// Any format assimp reads: triangulated, node transforms applied, meshes
/// merged, vertex colours and UVs of channel 0, diffuse/base colour texture
/// and factor. Not welded.
Mesh load_with_assimp(const std::string& path);

}  // namespace pfill

// Helpers shared by the mesh readers (internal to src/mesh): file checks,
// file bytes, image decoding and the linear-to-sRGB transfer function.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pfill/mesh.hpp"

namespace pfill::detail {

/// Throws pfill::Error naming `path` if it cannot be opened, is a folder or
/// is empty.
void require_readable_file(const std::string& path);

/// The whole file; throws pfill::Error naming `path` on failure.
std::vector<uint8_t> read_file_bytes(const std::string& path);

/// Folder part of `path` with a trailing '/', or "" for a bare file name.
std::string folder_of(const std::string& path);

/// Lower-case extension with the dot (".obj"), or "" when there is none.
std::string lower_extension(const std::string& path);

/// Decodes a PNG/JPEG/BMP/TGA/... image (stb_image) into 8-bit RGBA; throws
/// pfill::Error naming `name` if it cannot be decoded.
Texture decode_image(const uint8_t* bytes, size_t size, const std::string& name);
Texture decode_image_file(const std::string& path);

/// Throws pfill::Error naming `path` unless the PLY file's header is
/// well formed and its body matches the header exactly (load_ply_check.cpp).
void check_ply_structure(const std::string& path);

/// Throws pfill::Error naming `path`, the OBJ vertex number and the line
/// unless every `v` line holds three whole, finite numbers within
/// kMaxCoordinate; returns the box of the vertices, read in double
/// (load_obj_check.cpp).
Box3 check_obj_vertices(const std::string& path);

/// Throws pfill::Error naming the line when an OFF text file's face names a
/// vertex index out of range (load_off_check.cpp; assimp drops such faces).
void check_off_indices(const std::string& path);

/// The OBJ file's text with every vertex moved by -shift, in double.
std::string shift_obj_vertices(const std::string& path, const Vec3& shift);

}  // namespace pfill::detail

/// @file colour.hpp
/// @brief Colour transfer: each particle takes the colour of the mesh surface
/// at its closest point, or a colour by depth, or one given colour.
///
/// Conventions:
/// - Colours a user sees (Rgb8, Mesh::corner_colours, texture texels) are
///   sRGB-encoded; every blend (barycentric interpolation of corner colours,
///   bilinear texture filtering, products with the material factor) is done
///   in linear light and encoded back to sRGB once, at the end. So a particle
///   half way between a black and a white corner is linear 0.5 (sRGB 188),
///   not sRGB 128.
/// - Surface colour at a point = interpolated corner colours (if any)
///   x material base_colour_factor (linear) x bilinear texture sample at the
///   interpolated UV (if the material has a texture); alpha is ignored.
/// - Textures: row 0 is the top row and v = 0 is the top edge (glTF); texel
///   centres sit at (i + 0.5) / width; the wrap mode of each axis (Repeat,
///   ClampToEdge, MirroredRepeat) is applied to the integer texel indices
///   as OpenGL 4.6 section 8.14.2 does.
/// - Depth: unsigned distance to the surface divided by its maximum over the
///   points, through viridis (0 = at the surface, dark purple; 1 = deepest,
///   yellow).
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "pfill/boundary.hpp"
#include "pfill/mesh.hpp"
#include "pfill/srgb.hpp"
#include "pfill/particles.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

enum class ColourMode {
  Surface,   ///< the surface colour at the closest point (falls back to Depth)
  Depth,     ///< distance to the surface through a colour map
  None,      ///< no colours at all
  Constant,  ///< ColourOptions::constant for every particle
};

struct ColourOptions {
  ColourMode mode = ColourMode::Surface;
  Rgb8 constant{222, 139, 62};  ///< sRGB, used by ColourMode::Constant
};

/// "surface", "depth", "none" or "#RRGGBB" (hex, either case); throws
/// pfill::Error naming the accepted forms otherwise.
ColourOptions parse_colour_option(const std::string& text);

/// "surface", "depth", "none", "constant".
std::string colour_mode_name(ColourMode mode);

/// True when the mesh carries a colour of its own: corner colours, a material
/// with a texture, or a material whose base colour factor is not white.
bool has_surface_colour(const Mesh& mesh);

/// The default policy when the user names no mode: Surface when
/// has_surface_colour(mesh), else None (an uncoloured mesh gives uncoloured
/// particles; depth colouring is on request only).
ColourMode default_colour_mode(const Mesh& mesh);

struct ColourTransfer {
  std::vector<Rgb8> colours;  ///< one per point; empty for ColourMode::None
  ColourMode applied = ColourMode::None;  ///< differs from the request when Surface fell back to Depth
  std::string note;           ///< one line saying why `applied` differs; empty otherwise
};

/// Colours `points` from `boundary`'s mesh by `options.mode` (closest points
/// batched and in parallel). Surface on a mesh without surface colour falls
/// back to Depth and says so in `note`. Throws pfill::Error naming the mesh
/// when a material has a texture but the mesh has no UVs.
/// `deepest_of_all` (a set held in parts over processes): from the deepest
/// of these points to the deepest of every process's, which Depth's scale
/// then follows (collective); empty: these points' own.
ColourTransfer transfer_colours(const Boundary& boundary, const std::vector<Vec3>& points,
                                const ColourOptions& options,
                                const std::function<double(double)>& deepest_of_all = {});

/// transfer_colours on the particles' centres, stored in particles.colours
/// (cleared for None). Returns the note (empty when applied as asked).
std::string colour_particles(const Boundary& boundary, ParticleSet& particles, const ColourOptions& options,
                             const std::function<double(double)>& deepest_of_all = {});

// ---- The pieces, public for tests and for other colouring code ----

// srgb_to_linear and linear_to_srgb: include/pfill/srgb.hpp.
/// Encodes the linear RGB of `linear` (alpha ignored) to 8-bit sRGB, rounded.
Rgb8 encode_srgb8(const Rgba& linear);

/// Bilinear sample of `texture` at (s, t) with its wrap modes, in linear RGBA
/// (texels decoded from sRGB before filtering; alpha is filtered as is).
/// Throws pfill::Error naming the texture if it is empty or malformed.
Rgba sample_texture(const Texture& texture, double s, double t);

/// Linear RGB(A) of the surface at point (1-u-v) A + u B + v C of triangle
/// `triangle` (see the file comment); white where the mesh has no colour.
/// Throws pfill::Error as transfer_colours does for missing UVs.
Rgba surface_colour(const Mesh& mesh, uint32_t triangle, double u, double v);

/// Throws pfill::Error naming the mesh when a material has a texture but the
/// mesh has no UVs, or a texture is empty or malformed.
void check_surface_colour_inputs(const Mesh& mesh);

/// Viridis at `fraction` in [0, 1] (clamped); lightness grows with fraction.
Rgb8 depth_colour(double fraction);

}  // namespace pfill

/// @file render.hpp
/// @brief The preview renderer: ray-traces particles as spheres (Embree),
/// optionally inside the mesh drawn as a faint translucent shell, with a key
/// light, a fill light and ambient occlusion, and writes PNG images.
///
/// Conventions: y is up (as in glTF); the camera frames the box of the
/// particles and the shell automatically unless RenderOptions::camera is set.
/// A cut removes every sphere whose centre lies on the positive side of an
/// axis-aligned plane, and the part of the shell there, to show the inside.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "pfill/mesh.hpp"
#include "pfill/particles.hpp"

namespace pfill {

enum class View { ThreeQuarter, Front, Side, Top, Iso };

/// "three-quarter" (or "default"), "front", "side", "top", "iso"; throws
/// pfill::Error listing them otherwise.
View parse_view(const std::string& name);

struct Cut {
  int axis = 0;                 ///< 0 x, 1 y, 2 z
  std::optional<double> value;  ///< plane position; default: the centre of the scene box
};

/// "x", "y", "z", or "x=0.25" etc.; throws pfill::Error otherwise.
Cut parse_cut(const std::string& text);

struct Camera {
  Vec3 eye;
  Vec3 target;
  Vec3 up{0, 1, 0};
  double vertical_fov_degrees = 30;
};

/// A camera looking at `box` from the direction of `view`, placed as close as
/// it can be with the whole box in a picture of the given aspect (width /
/// height), with a small margin. An empty box frames the unit cube.
Camera frame_camera(const Box3& box, View view, double aspect);

/// Box of the particles (grown by their radii) and the shell's vertices.
Box3 scene_bounds(const ParticleSet& particles, const Mesh* shell);

struct RenderOptions {
  int width = 1024;
  int height = 768;
  View view = View::ThreeQuarter;
  std::optional<Camera> camera;  ///< overrides the automatic framing (e.g. one camera for all frames)
  std::optional<Cut> cut;
  Rgb8 particle_colour{222, 139, 62};  ///< sRGB, for particles without colours
  Rgb8 background_top{252, 252, 253};  ///< sRGB; the background is a vertical gradient
  Rgb8 background_bottom{214, 220, 230};
  Rgb8 shell_colour{120, 150, 200};
  double shell_opacity = 0.12;   ///< at normal incidence; grows towards the silhouette
  int ambient_occlusion_rays = 6;
  int samples_per_axis = 1;      ///< anti-aliasing: n x n samples per pixel
};

/// An 8-bit sRGB picture, rows top to bottom.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> rgb;  ///< width * height * 3
  Rgb8 at(int x, int y) const {
    const size_t i = 3 * (static_cast<size_t>(y) * width + x);
    return {rgb[i], rgb[i + 1], rgb[i + 2]};
  }
};

/// The background colour of row y of an image of `height` rows.
Rgb8 background_at(const RenderOptions& options, int y, int height);

/// Renders the particles (and `shell`, if not null). Throws pfill::Error for
/// a size outside 1..16384, an invalid particle set, a cut axis outside 0..2,
/// or an Embree failure.
Image render(const ParticleSet& particles, const Mesh* shell, const RenderOptions& options);

/// Writes `image` as PNG, atomically (see atomic_file.hpp).
void write_png(const Image& image, const std::filesystem::path& path);

}  // namespace pfill

// The colour mode a user names (`--colour surface|depth|none|#RRGGBB`) and
// the default when they name none.
#include <cctype>

#include "pfill/colour.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  const char l = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (l >= 'a' && l <= 'f') return l - 'a' + 10;
  return -1;
}

}  // namespace

ColourOptions parse_colour_option(const std::string& text) {
  std::string lower;
  for (char c : text) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  ColourOptions options;
  if (lower == "surface") {
    options.mode = ColourMode::Surface;
  } else if (lower == "depth") {
    options.mode = ColourMode::Depth;
  } else if (lower == "none") {
    options.mode = ColourMode::None;
  } else if (text.size() == 7 && text[0] == '#') {
    options.mode = ColourMode::Constant;
    for (int k = 0; k < 3; ++k) {
      const int hi = hex_digit(text[1 + 2 * k]), lo = hex_digit(text[2 + 2 * k]);
      if (hi < 0 || lo < 0)
        throw Error("colour '" + text + "': '#RRGGBB' needs six hex digits (0-9, a-f), e.g. #ff8800");
      options.constant[k] = static_cast<uint8_t>(16 * hi + lo);
    }
  } else {
    throw Error("colour '" + text + "' is not known: use surface, depth, none or #RRGGBB (e.g. #ff8800)");
  }
  return options;
}

std::string colour_mode_name(ColourMode mode) {
  switch (mode) {
    case ColourMode::Surface: return "surface";
    case ColourMode::Depth: return "depth";
    case ColourMode::None: return "none";
    case ColourMode::Constant: return "constant";
  }
  return "unknown";
}

bool has_surface_colour(const Mesh& mesh) {
  if (mesh.has_colours()) return true;
  for (const Material& m : mesh.materials)
    if (m.texture >= 0 || m.base_colour_factor[0] != 1 || m.base_colour_factor[1] != 1 ||
        m.base_colour_factor[2] != 1)
      return true;
  return false;
}

ColourMode default_colour_mode(const Mesh& mesh) {
  return has_surface_colour(mesh) ? ColourMode::Surface : ColourMode::None;
}

}  // namespace pfill

/// @file srgb.hpp
/// @brief The sRGB transfer functions (IEC 61966-2-1), one definition for
/// every part that converts colours: loaders (glTF's linear COLOR_0), colour
/// transfer (blending in linear light), the GLB writer and the renderer.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>

namespace pfill {

/// sRGB-encoded [0, 1] -> linear [0, 1] (input clamped).
inline float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// Linear [0, 1] -> sRGB-encoded [0, 1] (input clamped).
inline float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

/// An 8-bit sRGB channel -> linear [0, 1], computed in double.
inline float srgb8_to_linear(uint8_t c) {
  const double s = c / 255.0;
  return static_cast<float>(s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4));
}

}  // namespace pfill

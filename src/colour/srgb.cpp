// The sRGB transfer functions (IEC 61966-2-1) that colour blending goes
// through: decode to linear light, blend, encode once.
#include <algorithm>
#include <cmath>

#include "pfill/colour.hpp"

namespace pfill {

float srgb_to_linear(float encoded) {
  const float c = std::clamp(encoded, 0.0f, 1.0f);
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

Rgb8 encode_srgb8(const Rgba& linear) {
  Rgb8 out;
  for (int k = 0; k < 3; ++k) out[k] = static_cast<uint8_t>(std::lround(255.0f * linear_to_srgb(linear[k])));
  return out;
}

}  // namespace pfill

// Encoding blended linear colours to 8-bit sRGB (the transfer functions
// themselves are in include/pfill/srgb.hpp).
#include <algorithm>
#include <cmath>

#include "pfill/colour.hpp"

namespace pfill {

Rgb8 encode_srgb8(const Rgba& linear) {
  Rgb8 out;
  for (int k = 0; k < 3; ++k) out[k] = static_cast<uint8_t>(std::lround(255.0f * linear_to_srgb(linear[k])));
  return out;
}

}  // namespace pfill

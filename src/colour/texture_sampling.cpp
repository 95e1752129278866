// Bilinear texture filtering with glTF's sampler wrap modes, in linear light.
#include <array>
#include <cmath>

#include "pfill/colour.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

// sRGB byte -> linear, once (texels are looked up four per sample).
const std::array<float, 256>& srgb_decode_table() {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int i = 0; i < 256; ++i) t[i] = srgb_to_linear(static_cast<float>(i) / 255.0f);
    return t;
  }();
  return table;
}

// A texel index on one axis wrapped into 0..size-1 (OpenGL 4.6, 8.14.2).
int wrap_index(long long i, int size, WrapMode mode) {
  switch (mode) {
    case WrapMode::ClampToEdge:
      return static_cast<int>(i < 0 ? 0 : (i >= size ? size - 1 : i));
    case WrapMode::MirroredRepeat: {
      const long long period = 2LL * size;
      long long m = i % period;
      if (m < 0) m += period;
      return static_cast<int>(m < size ? m : period - 1 - m);
    }
    case WrapMode::Repeat:
    default: {
      long long m = i % size;
      if (m < 0) m += size;
      return static_cast<int>(m);
    }
  }
}

// The lower texel of the pair a coordinate falls between and the weight of
// the upper one. Far-out coordinates are brought near first (Clamp saturates,
// Repeat and Mirror are periodic) so the integer conversion cannot overflow.
void texel_pair(double coordinate, int size, WrapMode mode, long long& lower, double& weight) {
  double x = std::isfinite(coordinate) ? coordinate * size - 0.5 : 0.0;
  if (mode == WrapMode::ClampToEdge)
    x = std::fmin(std::fmax(x, -1.0), static_cast<double>(size));
  else if (std::fabs(x) > 1e9)
    x = std::fmod(x, 2.0 * size);
  const double f = std::floor(x);
  lower = static_cast<long long>(f);
  weight = x - f;
}

}  // namespace

Rgba sample_texture(const Texture& texture, double s, double t) {
  if (texture.width <= 0 || texture.height <= 0 ||
      texture.rgba.size() != static_cast<size_t>(texture.width) * texture.height * 4)
    throw Error("texture '" + texture.name + "' is empty or its pixel data does not match its size (" +
                std::to_string(texture.width) + "x" + std::to_string(texture.height) + ")");
  const std::array<float, 256>& decode = srgb_decode_table();
  long long x0 = 0, y0 = 0;
  double fx = 0, fy = 0;
  texel_pair(s, texture.width, texture.wrap_s, x0, fx);
  texel_pair(t, texture.height, texture.wrap_t, y0, fy);  // row 0 is the top, v = 0 the top edge
  const int xs[2] = {wrap_index(x0, texture.width, texture.wrap_s), wrap_index(x0 + 1, texture.width, texture.wrap_s)};
  const int ys[2] = {wrap_index(y0, texture.height, texture.wrap_t),
                     wrap_index(y0 + 1, texture.height, texture.wrap_t)};
  const double wx[2] = {1 - fx, fx}, wy[2] = {1 - fy, fy};
  double sum[4] = {0, 0, 0, 0};
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const double w = wx[i] * wy[j];
      if (w == 0) continue;
      const uint8_t* texel = &texture.rgba[4 * (static_cast<size_t>(ys[j]) * texture.width + xs[i])];
      for (int k = 0; k < 3; ++k) sum[k] += w * decode[texel[k]];
      sum[3] += w * (texel[3] / 255.0);  // alpha is linear already
    }
  return {static_cast<float>(sum[0]), static_cast<float>(sum[1]), static_cast<float>(sum[2]),
          static_cast<float>(sum[3])};
}

}  // namespace pfill

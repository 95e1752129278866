// The depth colour map: viridis (van der Walt and Smith, matplotlib), whose
// lightness grows monotonically and which reads in greyscale and for
// colour-blind viewers. Eleven stops, interpolated linearly in sRGB as the
// map itself is defined there.
#include <algorithm>
#include <cmath>

#include "pfill/colour.hpp"

namespace pfill {
namespace {

constexpr int kStops = 11;
// matplotlib viridis at 0, 0.1, ..., 1 (#440154 ... #fde725).
constexpr uint8_t kViridis[kStops][3] = {
    {68, 1, 84},    {72, 36, 117},  {65, 68, 135},  {53, 95, 141},   {42, 120, 142}, {33, 145, 140},
    {34, 168, 132}, {68, 191, 112}, {122, 209, 81}, {189, 223, 38}, {253, 231, 37}};

}  // namespace

Rgb8 depth_colour(double fraction) {
  const double t = (std::isfinite(fraction) ? std::clamp(fraction, 0.0, 1.0) : 0.0) * (kStops - 1);
  const int i = std::min(kStops - 2, static_cast<int>(t));
  const double f = t - i;
  Rgb8 c;
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<uint8_t>(std::lround(kViridis[i][k] * (1 - f) + kViridis[i + 1][k] * f));
  return c;
}

}  // namespace pfill

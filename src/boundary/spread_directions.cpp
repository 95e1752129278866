// Ray directions for the inside test (spread_directions.hpp).
#include "boundary/spread_directions.hpp"

#include <algorithm>
#include <cmath>

namespace pfill {

std::vector<Vec3> spread_directions(int count, double offset) {
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  const Vec3 axis = normalize(Vec3(1.0, std::sqrt(2.0), std::sqrt(3.0)));
  const double angle = 1.0, cs = std::cos(angle), sn = std::sin(angle);
  std::vector<Vec3> dirs;
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * i + offset;
    const Vec3 d(r * std::cos(phi), r * std::sin(phi), z);
    // Rodrigues rotation about `axis`.
    dirs.push_back(normalize(d * cs + cross(axis, d) * sn + axis * (dot(axis, d) * (1 - cs))));
  }
  return dirs;
}

}  // namespace pfill

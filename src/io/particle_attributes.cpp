// Checks of the boundary particles' attributes (include/pfill/particle_attributes.hpp).
#include "pfill/particle_attributes.hpp"

#include <cmath>

#include "pfill/error.hpp"

namespace pfill {

void validate(const ParticleAttributes& a, size_t particles, const std::string& source) {
  auto size_ok = [&](size_t size, const char* what) {
    if (size != 0 && size != particles)
      throw Error("'" + source + "': " + std::to_string(size) + " " + what + " for " + std::to_string(particles) +
                  " particles");
  };
  size_ok(a.kinds.size(), "kinds");
  size_ok(a.normals.size(), "normals");
  size_ok(a.areas.size(), "areas");
  for (uint8_t k : a.kinds)
    if (k > 1) throw Error("'" + source + "': particle kind " + std::to_string(k) + " (0 inner, 1 boundary)");
  for (const Vec3& n : a.normals)
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z))
      throw Error("'" + source + "': a normal is not finite");
  for (double v : a.areas)
    if (!std::isfinite(v)) throw Error("'" + source + "': an area is not finite");
}

}  // namespace pfill

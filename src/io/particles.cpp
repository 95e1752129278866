// The particle set's bounds, its order by id and its validation.
#include "pfill/particles.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "pfill/error.hpp"
#include "pfill/mesh.hpp"  // kMaxCoordinate

namespace pfill {

Box3 ParticleSet::bounds() const {
  Box3 box;
  for (size_t i = 0; i < positions.size(); ++i) {
    const double r = i < radii.size() ? radii[i] : 0.0;
    box.add(positions[i] - Vec3(r, r, r));
    box.add(positions[i] + Vec3(r, r, r));
  }
  return box;
}

ParticleSet in_id_order(const ParticleSet& s) {
  std::vector<size_t> order(s.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return s.id(a) < s.id(b); });
  ParticleSet sorted;
  for (size_t i : order) {
    sorted.positions.push_back(s.positions[i]);
    sorted.radii.push_back(s.radii[i]);
    sorted.ids.push_back(s.id(i));
    if (s.has_colours()) sorted.colours.push_back(s.colours[i]);
    if (s.has_velocities()) sorted.velocities.push_back(s.velocities[i]);
  }
  return sorted;
}

void validate(const ParticleSet& particles, const std::string& source) {
  const size_t n = particles.size();
  auto fail = [&](const std::string& what) {
    throw Error(source + ": invalid particle set: " + what);
  };
  if (particles.radii.size() != n)
    fail(std::to_string(n) + " positions but " + std::to_string(particles.radii.size()) + " radii");
  if (!particles.colours.empty() && particles.colours.size() != n)
    fail(std::to_string(n) + " positions but " + std::to_string(particles.colours.size()) +
         " colours (give one per particle or none)");
  if (!particles.velocities.empty() && particles.velocities.size() != n)
    fail(std::to_string(n) + " positions but " + std::to_string(particles.velocities.size()) +
         " velocities (give one per particle or none)");
  if (!particles.ids.empty() && particles.ids.size() != n)
    fail(std::to_string(n) + " positions but " + std::to_string(particles.ids.size()) +
         " ids (give one per particle or none)");
  for (size_t i = 0; i < n; ++i) {
    if (!is_finite(particles.positions[i]))
      fail("particle " + std::to_string(i) + " has a non-finite position");
    for (int k = 0; k < 3; ++k)
      if (std::fabs(particles.positions[i][k]) > kMaxCoordinate)
        fail("particle " + std::to_string(i) + " has a coordinate beyond the +-1e15 pfill computes with");
    const double r = particles.radii[i];
    if (!std::isfinite(r) || !(r > 0) || r > kMaxCoordinate)
      fail("particle " + std::to_string(i) + " has radius " + std::to_string(r) + " (must be > 0)");
    if (!particles.velocities.empty() && !is_finite(particles.velocities[i]))
      fail("particle " + std::to_string(i) + " has a non-finite velocity");
  }
}

}  // namespace pfill

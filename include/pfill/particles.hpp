/// @file particles.hpp
/// @brief The particle set a fill produces and every writer, reader and the
/// renderer take: structure of arrays, one entry per particle.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

using Rgb8 = std::array<uint8_t, 3>;  ///< sRGB-encoded colour, as a user sees it

struct ParticleSet {
  std::vector<Vec3> positions;   ///< centres
  std::vector<double> radii;     ///< one per particle, > 0
  std::vector<Rgb8> colours;     ///< sRGB; empty if the set has no colours
  std::vector<Vec3> velocities;  ///< empty if the set has no velocities
  /// Particle ids, stable through a fill (a fill numbers its particles 1, 2,
  /// ... in birth order); empty if the set has none (writers then write
  /// 1..N in file order).
  std::vector<uint64_t> ids;

  size_t size() const { return positions.size(); }
  bool empty() const { return positions.empty(); }
  bool has_colours() const { return !colours.empty(); }
  bool has_velocities() const { return !velocities.empty(); }
  bool has_ids() const { return !ids.empty(); }
  /// The id of particle i: ids[i], or i + 1 when the set has no ids.
  uint64_t id(size_t i) const { return ids.empty() ? i + 1 : ids[i]; }

  /// Box of the centres grown by each radius (empty box for no particles).
  Box3 bounds() const;

  void clear() { positions.clear(); radii.clear(); colours.clear(); velocities.clear(); ids.clear(); }
};

/// The set in the order of its ids (ParticleSet::id), every column along.
ParticleSet in_id_order(const ParticleSet& particles);

/// Throws pfill::Error naming `source` (a file name or "particles") when the
/// arrays differ in length (colours/velocities/ids may also be empty), or a
/// position, velocity or radius is not finite, or a radius is not > 0.
void validate(const ParticleSet& particles, const std::string& source = "particles");

}  // namespace pfill

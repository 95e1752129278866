/// @file particle_attributes.hpp
/// @brief Per-particle attributes of boundary particles (surface_sampling.hpp)
/// that the writers carry when given (ParticleWriteOptions::attributes): the
/// kind (inner or boundary, for `fill --shell`), the outward normal and the
/// area each boundary particle stands for.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "pfill/vec3.hpp"

namespace pfill {

enum class ParticleKind : uint8_t { Inner = 0, Boundary = 1 };

/// Each vector is empty (not written) or holds one entry per particle.
/// Inner particles have a zero normal and a zero area.
struct ParticleAttributes {
  std::vector<uint8_t> kinds;  ///< ParticleKind per particle: 0 inner, 1 boundary
  std::vector<Vec3> normals;   ///< unit, out of the solid (boundary particles)
  std::vector<double> areas;   ///< surface area a boundary particle stands for

  bool has_kinds() const { return !kinds.empty(); }
  bool has_normals() const { return !normals.empty(); }
  bool has_areas() const { return !areas.empty(); }
};

/// A kind as a file gives it (a number): 0 or 1, else 255 (validate() refuses it).
inline uint8_t kind_of(double value) { return value == 0 ? 0 : value == 1 ? 1 : 255; }

/// "inner" or "boundary".
inline const char* kind_name(uint8_t kind) { return kind == 1 ? "boundary" : "inner"; }

/// Throws pfill::Error naming `source` when a vector is neither empty nor of
/// `particles` entries, a kind is not 0 or 1, or a value is not finite.
void validate(const ParticleAttributes& attributes, size_t particles, const std::string& source);

}  // namespace pfill

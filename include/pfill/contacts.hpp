/// @file contacts.hpp
/// @brief The contact network of a particle set: the pairs of spheres that
/// touch (to within a gap), the spheres that touch the wall, and each
/// sphere's coordination. Data only; include/pfill/contact_network.hpp
/// finds them (the fill layer), the writers (particle_io.hpp) write them
/// beside the particles: PLY `edge` elements, VTP lines, LAMMPS `Bonds`,
/// a `coordination` attribute in every format, and a CSV of the contacts.
#pragma once
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "pfill/particles.hpp"
#include "pfill/vec3.hpp"

namespace pfill {

/// Spheres a and b (indices into the ParticleSet, a < b) touch: their gap
/// d - r_a - r_b (negative: they overlap) is at most the network's
/// gap_fraction times the smaller radius.
struct PairContact {
  uint32_t a = 0, b = 0;
  double gap = 0;
};

/// Sphere `particle` touches the surface: its gap to the surface (distance
/// of the centre to the surface less the radius; negative: it crosses it)
/// is at most gap_fraction of its radius. `point` is the closest surface
/// point, `normal` the unit surface normal there, out of the solid.
struct WallContact {
  uint32_t particle = 0;
  Vec3 point;
  Vec3 normal;
  double gap = 0;
};

struct ContactNetwork {
  double gap_fraction = 0.02;            ///< the largest gap that counts, as a fraction of the smaller radius
  std::vector<PairContact> pairs;        ///< sorted by (a, b)
  std::vector<WallContact> wall;         ///< sorted by particle; empty when no surface was given
  std::vector<uint32_t> coordination;    ///< per particle: its pair contacts (wall contacts not counted)

  double mean_coordination() const {
    return coordination.empty() ? 0.0 : 2.0 * static_cast<double>(pairs.size()) / coordination.size();
  }
};

/// The contacts as CSV, one line each: `a,b,gap,x,y,z,nx,ny,nz`. a and b are
/// the particles' ids (ParticleSet::id, as in the particle files); for a wall
/// contact b is 0 (ids start at 1). x,y,z is the contact point (for a pair
/// the middle of the gap along the line of centres; for the wall the closest
/// surface point) and nx,ny,nz the unit normal (from a to b; for the wall
/// out of the solid). Full double precision. Atomic, as every writer.
void write_contacts_csv(const ParticleSet& particles, const ContactNetwork& contacts,
                        const std::filesystem::path& path);

/// Throws pfill::Error naming `source` when the network does not fit the
/// particles (coordination of another length, a pair index out of range or
/// not a < b).
void validate(const ContactNetwork& contacts, size_t particles, const std::string& source);

}  // namespace pfill

// LAMMPS data file for atom_style sphere, so a DEM run starts from a fill
// with `read_data`: one atom type, each atom's diameter and density, the box
// around the mesh. LIGGGHTS reads the same layout.
#include <algorithm>
#include <cmath>
#include <string>

#include "io/chunked_records.hpp"
#include "io/number_text.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

namespace pfill {
namespace {

// The given box (the mesh's) with every sphere in it, grown by a margin so
// that no sphere touches a face of a non-periodic box.
Box3 simulation_box(const ParticleSet& particles, const Box3& given) {
  Box3 box = given;
  const Box3 spheres = particles.bounds();
  if (!spheres.empty()) box.add(spheres.lo), box.add(spheres.hi);
  if (box.empty()) box.add(Vec3(0, 0, 0));
  const Vec3 size = box.size();
  double margin = 0.05 * std::max({size.x, size.y, size.z});
  for (double r : particles.radii) margin = std::max(margin, r);
  if (!(margin > 0)) margin = 0.5;  // one point or nothing: a unit box
  box.lo = box.lo - Vec3(margin, margin, margin);
  box.hi = box.hi + Vec3(margin, margin, margin);
  return box;
}

}  // namespace

void write_lammps_data(const ParticleSet& particles, const std::filesystem::path& path,
                       const ParticleWriteOptions& options) {
  validate(particles, path.string());
  if (!(options.density > 0) || !std::isfinite(options.density))
    throw Error("cannot write '" + path.string() + "': the particle density must be > 0, not " +
                std::to_string(options.density));
  const bool velocities = options.velocities && particles.has_velocities();
  const Box3 box = simulation_box(particles, options.box);

  // With contacts: atom_style hybrid sphere bond (Atoms `id type x y z
  // diameter density molecule`), one bond per contact pair, one bond type.
  const ContactNetwork* bonds = options.contacts;
  // With kinds (fill --shell): atom type 1 inner, 2 boundary.
  const bool kinds = options.attributes && options.attributes->has_kinds();
  if (options.attributes) validate(*options.attributes, particles.size(), path.string());
  if (bonds) validate(*bonds, particles.size(), path.string());
  std::string head = "pfill particles: " + std::to_string(particles.size()) +
                     (bonds ? " spheres, " + std::to_string(bonds->pairs.size()) +
                                  " contacts as bonds (LAMMPS data file, atom_style hybrid sphere bond: id type x y z "
                                  "diameter density molecule)\n\n"
                            : std::string(" spheres (LAMMPS data file, atom_style sphere: id type diameter density x y z)\n\n")) +
                     std::to_string(particles.size()) + " atoms\n" + (kinds ? "2" : "1") + " atom types\n";
  if (bonds) head += std::to_string(bonds->pairs.size()) + " bonds\n1 bond types\n";
  head += "\n";
  const char* axes[3][2] = {{"xlo", "xhi"}, {"ylo", "yhi"}, {"zlo", "zhi"}};
  for (int a = 0; a < 3; ++a) {
    append_number(head, box.lo[a]);
    head += ' ';
    append_number(head, box.hi[a]);
    head += std::string(" ") + axes[a][0] + " " + axes[a][1] + "\n";
  }
  head += bonds ? "\nAtoms # hybrid sphere bond\n\n" : "\nAtoms # sphere\n\n";

  write_file_atomically(path, [&](AtomicFile& file) {
    file.write(head);
    write_records(file, particles.size(), 1 << 13, [&](std::string& chunk, size_t i) {
      chunk += std::to_string(particles.id(i));
      chunk += kinds ? (options.attributes->kinds[i] ? " 2" : " 1") : " 1";
      if (bonds)  // hybrid: x y z first, then the sub-styles' columns
        for (int k = 0; k < 3; ++k) {
          chunk += ' ';
          append_number(chunk, particles.positions[i][k]);
        }
      chunk += ' ';
      append_number(chunk, 2 * particles.radii[i]);
      chunk += ' ';
      append_number(chunk, options.density);
      if (!bonds)
        for (int k = 0; k < 3; ++k) {
          chunk += ' ';
          append_number(chunk, particles.positions[i][k]);
        }
      if (bonds) chunk += " 1";  // bond's molecule id: one body
      chunk += '\n';
    });
    if (bonds) {
      file.write("\nBonds\n\n");
      write_records(file, bonds->pairs.size(), 1 << 13, [&](std::string& chunk, size_t k) {
        const PairContact& c = bonds->pairs[k];
        chunk += std::to_string(k + 1) + " 1 " + std::to_string(particles.id(c.a)) + ' ' +
                 std::to_string(particles.id(c.b)) + '\n';
      });
    }
    if (!velocities) return;
    file.write("\nVelocities\n\n");
    write_records(file, particles.size(), 1 << 13, [&](std::string& chunk, size_t i) {
      chunk += std::to_string(particles.id(i));
      for (int k = 0; k < 3; ++k) {
        chunk += ' ';
        append_number(chunk, particles.velocities[i][k]);
      }
      chunk += " 0 0 0\n";  // angular velocity: a fill's spheres do not spin
    });
  });
}

}  // namespace pfill

// Whitespace `x y z r` text for Yade's ymport.text (and any tool that reads
// columns): `#` comment lines first, which ymport.text skips, then one line
// per particle, no blank lines (ymport.text fails on them).
#include <string>

#include "io/chunked_records.hpp"
#include "io/number_text.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/particle_io.hpp"

namespace pfill {

void write_xyzr(const ParticleSet& particles, const std::filesystem::path& path,
                const ParticleWriteOptions& options) {
  validate(particles, path.string());
  const bool velocities = options.velocities && particles.has_velocities();
  // Not "#format": ymport.text would take the next word as its format.
  const std::string head = "# pfill particles: " + std::to_string(particles.size()) +
                           " spheres; Yade: ymport.text(path) reads x y z r\n# x y z r id" +
                           (velocities ? " vx vy vz" : "") +
                           (options.contacts ? " coordination" : "") +
                           (options.attributes && options.attributes->has_kinds() ? " kind" : "") +
                           (options.attributes && options.attributes->has_normals() ? " nx ny nz" : "") +
                           (options.attributes && options.attributes->has_areas() ? " area" : "") + "\n";
  if (options.attributes) validate(*options.attributes, particles.size(), path.string());
  if (options.contacts) validate(*options.contacts, particles.size(), path.string());
  write_file_atomically(path, [&](AtomicFile& file) {
    file.write(head);
    write_records(file, particles.size(), 1 << 13, [&](std::string& chunk, size_t i) {
      for (int k = 0; k < 3; ++k) {
        append_number(chunk, particles.positions[i][k]);
        chunk += ' ';
      }
      append_number(chunk, particles.radii[i]);
      chunk += ' ';
      chunk += std::to_string(particles.id(i));
      if (velocities)
        for (int k = 0; k < 3; ++k) {
          chunk += ' ';
          append_number(chunk, particles.velocities[i][k]);
        }
      if (options.contacts) chunk += ' ' + std::to_string(options.contacts->coordination[i]);
      if (const ParticleAttributes* a = options.attributes) {
        if (a->has_kinds()) chunk += ' ' + std::to_string(a->kinds[i]);
        if (a->has_normals())
          for (int k = 0; k < 3; ++k) chunk += ' ', append_number(chunk, a->normals[i][k]);
        if (a->has_areas()) chunk += ' ', append_number(chunk, a->areas[i]);
      }
      chunk += '\n';
    });
  });
}

}  // namespace pfill

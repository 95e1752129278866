// The contact network as a CSV of contacts (include/pfill/contacts.hpp).
#include <cmath>
#include <string>

#include "io/chunked_records.hpp"
#include "io/number_text.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/contacts.hpp"
#include "pfill/error.hpp"

namespace pfill {

void validate(const ContactNetwork& contacts, size_t particles, const std::string& source) {
  if (contacts.coordination.size() != particles)
    throw Error("'" + source + "': the contacts are of " + std::to_string(contacts.coordination.size()) +
                " particles, not of these " + std::to_string(particles));
  for (const PairContact& c : contacts.pairs)
    if (!(c.a < c.b && c.b < particles))
      throw Error("'" + source + "': contact " + std::to_string(c.a) + "-" + std::to_string(c.b) +
                  " names no pair of these " + std::to_string(particles) + " particles");
  for (const WallContact& w : contacts.wall)
    if (w.particle >= particles)
      throw Error("'" + source + "': a wall contact names particle " + std::to_string(w.particle) + " of " +
                  std::to_string(particles));
}

void write_contacts_csv(const ParticleSet& particles, const ContactNetwork& contacts,
                        const std::filesystem::path& path) {
  validate(particles, path.string());
  validate(contacts, particles.size(), path.string());
  auto row = [&](std::string& chunk, uint64_t a, uint64_t b, double gap, const Vec3& x, const Vec3& n) {
    chunk += std::to_string(a);
    chunk += ',';
    chunk += std::to_string(b);
    chunk += ',';
    append_number(chunk, gap);
    for (int k = 0; k < 3; ++k) chunk += ',', append_number(chunk, x[k]);
    for (int k = 0; k < 3; ++k) chunk += ',', append_number(chunk, n[k]);
    chunk += '\n';
  };
  write_file_atomically(path, [&](AtomicFile& file) {
    file.write("a,b,gap,x,y,z,nx,ny,nz\n");
    write_records(file, contacts.pairs.size(), 1 << 13, [&](std::string& chunk, size_t k) {
      const PairContact& c = contacts.pairs[k];
      const Vec3 pa = particles.positions[c.a], pb = particles.positions[c.b];
      const double d = length(pb - pa);
      const Vec3 n = d > 0 ? (pb - pa) / d : Vec3(0, 0, 1);
      // The middle of the gap (or of the overlap) along the line of centres.
      const Vec3 x = pa + n * (particles.radii[c.a] + 0.5 * c.gap);
      row(chunk, particles.id(c.a), particles.id(c.b), c.gap, x, n);
    });
    write_records(file, contacts.wall.size(), 1 << 13, [&](std::string& chunk, size_t k) {
      const WallContact& w = contacts.wall[k];
      row(chunk, particles.id(w.particle), 0, w.gap, w.point, w.normal);
    });
  });
}

}  // namespace pfill

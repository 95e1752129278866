// CSV writer: x,y,z,radius[,r,g,b][,vx,vy,vz], one particle per line.
#include <charconv>
#include <string>

#include "pfill/atomic_file.hpp"
#include "pfill/particle_io.hpp"
#include "io/chunked_records.hpp"

namespace pfill {
namespace {

// Shortest decimal form that reads back to the same double (at most
// max_digits10 = 17 significant digits), so CSV round trips are exact.
void append_number(std::string& out, double v) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, v);
  out.append(buffer, result.ptr);
}

}  // namespace

void write_csv(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options) {
  validate(particles, path.string());
  const bool colours = particles.has_colours();
  const bool velocities = options.velocities && particles.has_velocities();

  std::string header = "x,y,z,radius";
  if (colours) header += ",r,g,b";
  if (velocities) header += ",vx,vy,vz";
  header += "\n";

  write_file_atomically(path, [&](AtomicFile& file) {
    file.write(header);
    write_records(file, particles.size(), 1 << 13, [&](std::string& chunk, size_t i) {
      const Vec3& p = particles.positions[i];
      append_number(chunk, p.x);
      chunk += ',';
      append_number(chunk, p.y);
      chunk += ',';
      append_number(chunk, p.z);
      chunk += ',';
      append_number(chunk, particles.radii[i]);
      if (colours) {
        for (uint8_t c : particles.colours[i]) {
          chunk += ',';
          chunk += std::to_string(static_cast<int>(c));
        }
      }
      if (velocities) {
        const Vec3& v = particles.velocities[i];
        for (int k = 0; k < 3; ++k) {
          chunk += ',';
          append_number(chunk, v[k]);
        }
      }
      chunk += '\n';
    });
  });
}

}  // namespace pfill

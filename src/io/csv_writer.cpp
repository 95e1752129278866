// CSV writer: x,y,z,radius[,r,g,b][,vx,vy,vz],id, one particle per line
// (Houdini names: x,y,z,pscale[,Cd.r,Cd.g,Cd.b][,v.x,v.y,v.z],id).
#include <charconv>
#include <string>

#include "pfill/atomic_file.hpp"
#include "pfill/particle_io.hpp"
#include "io/chunked_records.hpp"
#include "io/number_text.hpp"

namespace pfill {

void write_csv(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options) {
  validate(particles, path.string());
  const bool colours = particles.has_colours();
  const bool velocities = options.velocities && particles.has_velocities();
  const bool houdini = options.names == AttributeNames::Houdini;

  std::string header = houdini ? "x,y,z,pscale" : "x,y,z,radius";
  if (colours) header += houdini ? ",Cd.r,Cd.g,Cd.b" : ",r,g,b";
  if (velocities) header += houdini ? ",v.x,v.y,v.z" : ",vx,vy,vz";
  header += ",id";
  if (options.contacts) validate(*options.contacts, particles.size(), path.string());
  if (options.contacts) header += ",coordination";
  const ParticleAttributes* attributes = options.attributes;
  if (attributes) {
    validate(*attributes, particles.size(), path.string());
    if (attributes->has_kinds()) header += ",kind";
    if (attributes->has_normals()) header += ",nx,ny,nz";
    if (attributes->has_areas()) header += ",area";
  }
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
          if (houdini)
            append_number(chunk, c / 255.0);  // Houdini's Cd: floats 0..1
          else
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
      chunk += ',';
      chunk += std::to_string(particles.id(i));
      if (options.contacts) chunk += ',' + std::to_string(options.contacts->coordination[i]);
      if (attributes) {
        if (attributes->has_kinds()) chunk += ',' + std::to_string(attributes->kinds[i]);
        if (attributes->has_normals())
          for (int k = 0; k < 3; ++k) chunk += ',', append_number(chunk, attributes->normals[i][k]);
        if (attributes->has_areas()) chunk += ',', append_number(chunk, attributes->areas[i]);
      }
      chunk += '\n';
    });
  });
}

}  // namespace pfill

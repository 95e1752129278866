// Binary little-endian PLY writer: the particle format that Blender, MeshLab,
// CloudCompare, ParaView and Houdini all open.
#include <algorithm>
#include <string>

#include "io/byte_order.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/particle_io.hpp"
#include "io/chunked_records.hpp"

namespace pfill {

void write_ply(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options) {
  validate(particles, path.string());
  const bool colours = particles.has_colours();
  const bool velocities = options.velocities && particles.has_velocities();
  const bool houdini = options.names == AttributeNames::Houdini;
  // Far from the origin (survey, CAD coordinates) float32 would move spheres
  // by more than the overlaps the fill bounds: positions then go as doubles.
  const bool wide = positions_need_doubles(particles);

  std::string header =
      "ply\nformat binary_little_endian 1.0\ncomment written by pfill: spheres, radius in model units\n"
      "element vertex " + std::to_string(particles.size()) + "\n" +
      (wide ? "property double x\nproperty double y\nproperty double z\n"
            : "property float x\nproperty float y\nproperty float z\n");
  header += houdini ? "property float pscale\n" : "property float radius\n";
  if (colours)
    header += houdini ? "property float Cd.r\nproperty float Cd.g\nproperty float Cd.b\n"
                      : "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (velocities)
    header += houdini ? "property float v.x\nproperty float v.y\nproperty float v.z\n"
                      : "property float vx\nproperty float vy\nproperty float vz\n";
  header += "property uint id\n";
  const ParticleAttributes* attributes = options.attributes;
  if (attributes) {
    validate(*attributes, particles.size(), path.string());
    if (attributes->has_kinds()) header += "property uchar kind\n";
    if (attributes->has_normals()) header += "property float nx\nproperty float ny\nproperty float nz\n";
    if (attributes->has_areas()) header += "property float area\n";
  }
  const ContactNetwork* contacts = options.contacts;
  if (contacts) {
    validate(*contacts, particles.size(), path.string());
    header += "property ushort coordination\nelement edge " + std::to_string(contacts->pairs.size()) +
              "\nproperty int vertex1\nproperty int vertex2\nproperty float gap\n";
  }
  header += "end_header\n";

  write_file_atomically(path, [&](AtomicFile& file) {
    file.write(header);
    write_records(file, particles.size(), 1 << 14, [&](std::string& chunk, size_t i) {
      const Vec3& p = particles.positions[i];
      if (wide) {
        byte_order::append_f64_le(chunk, p.x);
        byte_order::append_f64_le(chunk, p.y);
        byte_order::append_f64_le(chunk, p.z);
      } else {
        byte_order::append_f32_le(chunk, static_cast<float>(p.x));
        byte_order::append_f32_le(chunk, static_cast<float>(p.y));
        byte_order::append_f32_le(chunk, static_cast<float>(p.z));
      }
      byte_order::append_f32_le(chunk, static_cast<float>(particles.radii[i]));
      if (colours && houdini) {
        for (uint8_t c : particles.colours[i]) byte_order::append_f32_le(chunk, c / 255.0f);
      } else if (colours) {
        chunk.append(reinterpret_cast<const char*>(particles.colours[i].data()), 3);
      }
      if (velocities) {
        const Vec3& v = particles.velocities[i];
        byte_order::append_f32_le(chunk, static_cast<float>(v.x));
        byte_order::append_f32_le(chunk, static_cast<float>(v.y));
        byte_order::append_f32_le(chunk, static_cast<float>(v.z));
      }
      byte_order::append_u32_le(chunk, static_cast<uint32_t>(particles.id(i)));
      if (attributes) {
        if (attributes->has_kinds()) chunk += static_cast<char>(attributes->kinds[i]);
        if (attributes->has_normals())
          for (int k = 0; k < 3; ++k) byte_order::append_f32_le(chunk, static_cast<float>(attributes->normals[i][k]));
        if (attributes->has_areas()) byte_order::append_f32_le(chunk, static_cast<float>(attributes->areas[i]));
      }
      if (contacts) {  // ushort, little-endian
        const uint32_t z = std::min<uint32_t>(contacts->coordination[i], 65535);
        chunk += static_cast<char>(z & 0xFF);
        chunk += static_cast<char>(z >> 8);
      }
    });
    if (contacts)  // the pairs as edges between the vertices (file order, from 0)
      write_records(file, contacts->pairs.size(), 1 << 14, [&](std::string& chunk, size_t k) {
        const PairContact& c = contacts->pairs[k];
        byte_order::append_u32_le(chunk, c.a);
        byte_order::append_u32_le(chunk, c.b);
        byte_order::append_f32_le(chunk, static_cast<float>(c.gap));
      });
  });
}

}  // namespace pfill

// VTK XML PolyData writer (.vtp) for ParaView: one vertex cell per particle,
// radius, id, colour and velocity as point data. Binary output uses VTK's
// "appended raw" layout: after '_', each array is a UInt64 byte count
// followed by its little-endian values.
#include <charconv>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "io/byte_order.hpp"
#include "pfill/atomic_file.hpp"
#include "pfill/particle_io.hpp"

namespace pfill {
namespace {

// One DataArray: its XML attributes and a function that appends value k of
// the array (binary or as text) to a buffer.
struct VtpArray {
  std::string type;        // VTK type name: Float64, Int64, UInt8
  std::string name;
  int components = 1;
  size_t values = 0;       // number of scalar values (tuples * components)
  size_t value_bytes = 0;  // bytes per scalar value
  std::function<void(std::string&, size_t)> append_binary;
  std::function<void(std::string&, size_t)> append_text;
};

void append_double_text(std::string& out, double v) {
  char buffer[32];
  out.append(buffer, std::to_chars(buffer, buffer + sizeof buffer, v).ptr);
}

VtpArray float64_array(std::string name, int components, size_t tuples,
                       std::function<double(size_t)> value) {
  VtpArray a{"Float64", std::move(name), components, tuples * components, 8, {}, {}};
  a.append_binary = [value](std::string& out, size_t k) { byte_order::append_f64_le(out, value(k)); };
  a.append_text = [value](std::string& out, size_t k) { append_double_text(out, value(k)); };
  return a;
}

VtpArray int64_array(std::string name, size_t count, std::function<int64_t(size_t)> value) {
  VtpArray a{"Int64", std::move(name), 1, count, 8, {}, {}};
  a.append_binary = [value](std::string& out, size_t k) {
    byte_order::append_u64_le(out, static_cast<uint64_t>(value(k)));
  };
  a.append_text = [value](std::string& out, size_t k) { out += std::to_string(value(k)); };
  return a;
}

void append_array_data(AtomicFile& file, const VtpArray& a, bool binary) {
  static constexpr size_t kChunk = 1 << 15;
  std::string chunk;
  for (size_t begin = 0; begin < a.values; begin += kChunk) {
    chunk.clear();
    const size_t end = std::min(a.values, begin + kChunk);
    for (size_t k = begin; k < end; ++k) {
      if (binary) {
        a.append_binary(chunk, k);
      } else {
        a.append_text(chunk, k);
        chunk += (k + 1) % 9 == 0 ? '\n' : ' ';
      }
    }
    file.write(chunk);
  }
}

}  // namespace

void write_vtp(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options) {
  validate(particles, path.string());
  const size_t n = particles.size();
  const bool binary = options.vtp_binary;

  const VtpArray points = float64_array("Points", 3, n, [&](size_t k) {
    return particles.positions[k / 3][static_cast<int>(k % 3)];
  });
  const VtpArray connectivity = int64_array("connectivity", n, [](size_t k) { return int64_t(k); });
  const VtpArray offsets = int64_array("offsets", n, [](size_t k) { return int64_t(k + 1); });
  std::vector<VtpArray> point_data;
  point_data.push_back(float64_array("radius", 1, n, [&](size_t k) { return particles.radii[k]; }));
  point_data.push_back(int64_array("id", n, [&](size_t k) { return static_cast<int64_t>(particles.id(k)); }));
  if (particles.has_colours()) {
    VtpArray colour{"UInt8", "colour", 3, n * 3, 1, {}, {}};
    colour.append_binary = [&](std::string& out, size_t k) {
      out += static_cast<char>(particles.colours[k / 3][k % 3]);
    };
    colour.append_text = [&](std::string& out, size_t k) {
      out += std::to_string(static_cast<int>(particles.colours[k / 3][k % 3]));
    };
    point_data.push_back(std::move(colour));
  }
  const ContactNetwork* contacts = options.contacts;
  if (contacts) {
    validate(*contacts, n, path.string());
    point_data.push_back(int64_array("coordination", n, [contacts](size_t k) {
      return static_cast<int64_t>(contacts->coordination[k]);
    }));
  }
  if (const ParticleAttributes* a = options.attributes) {
    validate(*a, n, path.string());
    if (a->has_kinds())
      point_data.push_back(int64_array("kind", n, [a](size_t k) { return static_cast<int64_t>(a->kinds[k]); }));
    if (a->has_normals())
      point_data.push_back(float64_array("normal", 3, n, [a](size_t k) { return a->normals[k / 3][static_cast<int>(k % 3)]; }));
    if (a->has_areas()) point_data.push_back(float64_array("area", 1, n, [a](size_t k) { return a->areas[k]; }));
  }
  const size_t lines = contacts ? contacts->pairs.size() : 0;  // one line cell per contact pair
  const VtpArray line_connectivity = int64_array("connectivity", 2 * lines, [contacts](size_t k) {
    const PairContact& c = contacts->pairs[k / 2];
    return static_cast<int64_t>(k % 2 ? c.b : c.a);
  });
  const VtpArray line_offsets = int64_array("offsets", lines, [](size_t k) { return int64_t(2 * (k + 1)); });
  if (options.velocities && particles.has_velocities())
    point_data.push_back(float64_array("velocity", 3, n, [&](size_t k) {
      return particles.velocities[k / 3][static_cast<int>(k % 3)];
    }));

  // The XML part; binary arrays only name their offset into the appended block.
  uint64_t appended_offset = 0;
  std::vector<const VtpArray*> order;
  auto data_array = [&](const VtpArray& a) {
    std::string xml = "        <DataArray type=\"" + a.type + "\" Name=\"" + a.name + "\"";
    if (a.components > 1) xml += " NumberOfComponents=\"" + std::to_string(a.components) + "\"";
    if (binary) {
      xml += " format=\"appended\" offset=\"" + std::to_string(appended_offset) + "\"/>\n";
      appended_offset += 8 + a.values * a.value_bytes;
      order.push_back(&a);
    } else {
      xml += " format=\"ascii\">\n";
    }
    return xml;
  };

  write_file_atomically(path, [&](AtomicFile& file) {
    file.write(
        "<?xml version=\"1.0\"?>\n"
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" "
        "header_type=\"UInt64\">\n  <PolyData>\n"
        "    <Piece NumberOfPoints=\"" + std::to_string(n) +
        "\" NumberOfVerts=\"" + std::to_string(n) +
        "\" NumberOfLines=\"" + std::to_string(lines) + "\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">\n");
    auto inline_array = [&](const VtpArray& a) {
      file.write(data_array(a));
      if (!binary) {
        append_array_data(file, a, false);
        file.write("\n        </DataArray>\n");
      }
    };
    file.write("      <PointData Scalars=\"radius\">\n");
    for (const VtpArray& a : point_data) inline_array(a);
    file.write("      </PointData>\n      <Points>\n");
    inline_array(points);
    file.write("      </Points>\n      <Verts>\n");
    inline_array(connectivity);
    inline_array(offsets);
    file.write("      </Verts>\n");
    if (lines) {
      file.write("      <Lines>\n");
      inline_array(line_connectivity);
      inline_array(line_offsets);
      file.write("      </Lines>\n");
    }
    file.write("    </Piece>\n  </PolyData>\n");
    if (binary) {
      file.write("  <AppendedData encoding=\"raw\">\n   _");
      for (const VtpArray* a : order) {
        std::string size;
        byte_order::append_u64_le(size, a->values * a->value_bytes);
        file.write(size);
        append_array_data(file, *a, true);
      }
      file.write("\n  </AppendedData>\n");
    }
    file.write("</VTKFile>\n");
  });
}

}  // namespace pfill

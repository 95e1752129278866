// PLY particle reader: ascii and binary (either byte order), vertex element
// only, tolerant of extra properties, extra elements and any scalar type.
// Every count and offset is checked against the file size before use, so a
// truncated or garbage file gives pfill::Error, not a crash or a huge
// allocation.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "io/read_file_bytes.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

namespace pfill {
namespace {

enum class PlyEncoding { Ascii, BinaryLittle, BinaryBig };

enum class ScalarType { Int8, Uint8, Int16, Uint16, Int32, Uint32, Float32, Float64 };

struct PlyProperty {
  std::string name;
  ScalarType type = ScalarType::Float32;
  bool is_list = false;
  ScalarType count_type = ScalarType::Uint8;  // lists only
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;
};

bool parse_scalar_type(const std::string& name, ScalarType& type) {
  static const std::pair<const char*, ScalarType> kTypes[] = {
      {"char", ScalarType::Int8},     {"int8", ScalarType::Int8},
      {"uchar", ScalarType::Uint8},   {"uint8", ScalarType::Uint8},
      {"short", ScalarType::Int16},   {"int16", ScalarType::Int16},
      {"ushort", ScalarType::Uint16}, {"uint16", ScalarType::Uint16},
      {"int", ScalarType::Int32},     {"int32", ScalarType::Int32},
      {"uint", ScalarType::Uint32},   {"uint32", ScalarType::Uint32},
      {"float", ScalarType::Float32}, {"float32", ScalarType::Float32},
      {"double", ScalarType::Float64}, {"float64", ScalarType::Float64}};
  for (const auto& [text, value] : kTypes)
    if (name == text) {
      type = value;
      return true;
    }
  return false;
}

size_t type_size(ScalarType t) {
  switch (t) {
    case ScalarType::Int8: case ScalarType::Uint8: return 1;
    case ScalarType::Int16: case ScalarType::Uint16: return 2;
    case ScalarType::Int32: case ScalarType::Uint32: case ScalarType::Float32: return 4;
    case ScalarType::Float64: return 8;
  }
  return 0;
}

// The largest value of an integer type, to scale integer colours to 0..255.
double type_max(ScalarType t) {
  switch (t) {
    case ScalarType::Int8: return 127;
    case ScalarType::Uint8: return 255;
    case ScalarType::Int16: return 32767;
    case ScalarType::Uint16: return 65535;
    case ScalarType::Int32: return 2147483647.0;
    case ScalarType::Uint32: return 4294967295.0;
    default: return 1.0;  // float colours are in [0, 1]
  }
}

class PlyParser {
 public:
  PlyParser(std::string path, std::string bytes) : path_(std::move(path)), bytes_(std::move(bytes)) {}

  ParticleSet parse(const ParticleReadOptions& options) {
    parse_header();
    for (const PlyElement& element : elements_) {
      if (element.name == "vertex") return read_vertices(element, options);
      skip_element(element);
    }
    fail("it has no 'vertex' element");
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw Error("cannot read PLY '" + path_ + "': " + why);
  }

  void parse_header() {
    static constexpr size_t kMaxHeader = 1 << 20;
    size_t line_start = 0;
    int line_number = 0;
    bool saw_format = false;
    for (;;) {
      const size_t line_end = bytes_.find('\n', line_start);
      if (line_end == std::string::npos || line_end > kMaxHeader)
        fail(line_number == 0 ? "the file is empty or not a PLY file"
                              : "the header has no 'end_header' line (truncated or not a PLY file)");
      std::string line = bytes_.substr(line_start, line_end - line_start);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      line_start = line_end + 1;
      ++line_number;
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      if (line_number == 1) {
        if (keyword != "ply") fail("it does not start with 'ply' (not a PLY file)");
        continue;
      }
      if (keyword == "end_header") break;
      if (keyword == "comment" || keyword == "obj_info" || keyword.empty()) continue;
      if (keyword == "format") {
        std::string format;
        words >> format;
        if (format == "ascii") encoding_ = PlyEncoding::Ascii;
        else if (format == "binary_little_endian") encoding_ = PlyEncoding::BinaryLittle;
        else if (format == "binary_big_endian") encoding_ = PlyEncoding::BinaryBig;
        else fail("unknown format '" + excerpt(format) + "'");
        saw_format = true;
      } else if (keyword == "element") {
        PlyElement element;
        long double count = -1;
        words >> element.name >> count;
        if (!words || count < 0 || count > 1e15L)
          fail("bad element line " + std::to_string(line_number) + ": '" + excerpt(line) + "'");
        element.count = static_cast<uint64_t>(count);
        elements_.push_back(element);
      } else if (keyword == "property") {
        if (elements_.empty()) fail("a property before any element (line " + std::to_string(line_number) + ")");
        PlyProperty property;
        std::string type;
        words >> type;
        if (type == "list") {
          std::string count_type, item_type;
          words >> count_type >> item_type >> property.name;
          property.is_list = true;
          if (!parse_scalar_type(count_type, property.count_type) ||
              !parse_scalar_type(item_type, property.type))
            fail("bad list property on line " + std::to_string(line_number) + ": '" + excerpt(line) + "'");
        } else {
          words >> property.name;
          if (!parse_scalar_type(type, property.type))
            fail("unknown property type '" + excerpt(type) + "' on line " + std::to_string(line_number));
        }
        if (property.name.empty()) fail("a property without a name on line " + std::to_string(line_number));
        elements_.back().properties.push_back(property);
      } else {
        fail("unexpected header line " + std::to_string(line_number) + ": '" + excerpt(line) + "'");
      }
    }
    if (!saw_format) fail("the header has no 'format' line");
    cursor_ = line_start;
  }

  // --- binary values -------------------------------------------------------
  double read_binary(ScalarType type) {
    const size_t size = type_size(type);
    if (bytes_.size() - cursor_ < size) fail("the data is truncated (the header promises more)");
    unsigned char raw[8];
    std::memcpy(raw, bytes_.data() + cursor_, size);
    cursor_ += size;
    static const bool host_little = [] {
      const uint16_t one = 1;
      unsigned char first;
      std::memcpy(&first, &one, 1);
      return first == 1;
    }();
    if ((encoding_ == PlyEncoding::BinaryLittle) != host_little) std::reverse(raw, raw + size);
    switch (type) {
      case ScalarType::Int8: { int8_t v; std::memcpy(&v, raw, 1); return v; }
      case ScalarType::Uint8: return raw[0];
      case ScalarType::Int16: { int16_t v; std::memcpy(&v, raw, 2); return v; }
      case ScalarType::Uint16: { uint16_t v; std::memcpy(&v, raw, 2); return v; }
      case ScalarType::Int32: { int32_t v; std::memcpy(&v, raw, 4); return v; }
      case ScalarType::Uint32: { uint32_t v; std::memcpy(&v, raw, 4); return v; }
      case ScalarType::Float32: { float v; std::memcpy(&v, raw, 4); return v; }
      case ScalarType::Float64: { double v; std::memcpy(&v, raw, 8); return v; }
    }
    return 0;
  }

  // --- ascii values --------------------------------------------------------
  double read_ascii() {
    while (cursor_ < bytes_.size() && std::isspace(static_cast<unsigned char>(bytes_[cursor_]))) ++cursor_;
    if (cursor_ >= bytes_.size()) fail("the data is truncated (the header promises more values)");
    const char* begin = bytes_.c_str() + cursor_;
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin || (*end != '\0' && !std::isspace(static_cast<unsigned char>(*end))))
      fail("a value that is not a number near byte " + std::to_string(cursor_));
    cursor_ += static_cast<size_t>(end - begin);
    return v;
  }

  double read_value(ScalarType type) {
    return encoding_ == PlyEncoding::Ascii ? read_ascii() : read_binary(type);
  }

  // Reads one property of one element instance; lists are skipped and give 0.
  double read_property(const PlyProperty& property) {
    if (!property.is_list) return read_value(property.type);
    const double count = read_value(property.count_type);
    if (!(count >= 0) || count > 1e9) fail("a list with a bad length (corrupted data)");
    for (uint64_t i = 0; i < static_cast<uint64_t>(count); ++i) read_value(property.type);
    return 0;
  }

  // Before allocating, checks the element can fit in the remaining bytes:
  // at least one byte per binary value, two (digit and space) per ascii one.
  void check_fits(const PlyElement& element) const {
    long double min_bytes = 0;
    for (const PlyProperty& property : element.properties)
      min_bytes += encoding_ == PlyEncoding::Ascii ? 2 : (property.is_list ? type_size(property.count_type)
                                                                            : type_size(property.type));
    min_bytes = min_bytes * element.count - (encoding_ == PlyEncoding::Ascii ? 1 : 0);
    if (min_bytes > static_cast<long double>(bytes_.size() - cursor_))
      fail("the data is truncated: the header promises " + std::to_string(element.count) + " " +
           element.name + " entries but the file is too short for them");
  }

  void skip_element(const PlyElement& element) {
    check_fits(element);
    for (uint64_t i = 0; i < element.count; ++i)
      for (const PlyProperty& property : element.properties) read_property(property);
  }

  ParticleSet read_vertices(const PlyElement& element, const ParticleReadOptions& options) {
    auto find = [&](std::initializer_list<const char*> names) -> int {
      for (const char* name : names)
        for (size_t k = 0; k < element.properties.size(); ++k)
          if (element.properties[k].name == name && !element.properties[k].is_list) return static_cast<int>(k);
      return -1;
    };
    const int x = find({"x"}), y = find({"y"}), z = find({"z"});
    if (x < 0 || y < 0 || z < 0) fail("its vertex element lacks x, y or z");
    const int radius = find({"radius", "pscale"});  // pscale: --attribute-names houdini
    if (radius < 0 && !(options.default_radius > 0))
      fail("its vertices have no 'radius' property: give a default radius (e.g. --radius R)");
    const int red = find({"red", "diffuse_red", "r", "Cd.r"}), green = find({"green", "diffuse_green", "g", "Cd.g"}),
              blue = find({"blue", "diffuse_blue", "b", "Cd.b"});
    const bool colours = red >= 0 && green >= 0 && blue >= 0;
    const int vx = find({"vx", "v.x"}), vy = find({"vy", "v.y"}), vz = find({"vz", "v.z"});
    const bool velocities = vx >= 0 && vy >= 0 && vz >= 0;
    const int id = find({"id"});
    // Boundary particles' attributes (fill --shell, pfill surface).
    ParticleAttributes* attributes = options.attributes;
    const int kind = find({"kind"}), nx = find({"nx"}), ny = find({"ny"}), nz = find({"nz"}), area = find({"area"});
    const bool normals = nx >= 0 && ny >= 0 && nz >= 0;

    check_fits(element);
    const size_t n = static_cast<size_t>(element.count);
    ParticleSet particles;
    particles.positions.resize(n);
    particles.radii.assign(n, options.default_radius);
    if (colours) particles.colours.resize(n);
    if (velocities) particles.velocities.resize(n);
    if (id >= 0) particles.ids.resize(n);
    if (attributes) {
      *attributes = {};
      if (kind >= 0) attributes->kinds.resize(n);
      if (normals) attributes->normals.resize(n);
      if (area >= 0) attributes->areas.resize(n);
    }

    std::vector<double> values(element.properties.size());
    auto colour = [&](int k) {
      const ScalarType type = element.properties[k].type;
      const double scaled = values[k] * 255.0 / type_max(type);
      return static_cast<uint8_t>(std::lround(std::clamp(scaled, 0.0, 255.0)));
    };
    for (size_t i = 0; i < n; ++i) {
      for (size_t k = 0; k < element.properties.size(); ++k) values[k] = read_property(element.properties[k]);
      particles.positions[i] = Vec3(values[x], values[y], values[z]);
      if (radius >= 0) particles.radii[i] = values[radius];
      if (colours) {
        if (!std::isfinite(values[red]) || !std::isfinite(values[green]) || !std::isfinite(values[blue]))
          fail("vertex " + std::to_string(i) + " has a non-finite colour");
        particles.colours[i] = {colour(red), colour(green), colour(blue)};
      }
      if (velocities) particles.velocities[i] = Vec3(values[vx], values[vy], values[vz]);
      if (id >= 0) particles.ids[i] = values[id] >= 0 && values[id] < 1.8e19 ? static_cast<uint64_t>(values[id]) : 0;
      if (attributes) {
        if (kind >= 0) attributes->kinds[i] = kind_of(values[kind]);
        if (normals) attributes->normals[i] = Vec3(values[nx], values[ny], values[nz]);
        if (area >= 0) attributes->areas[i] = values[area];
      }
    }
    validate(particles, path_);
    if (attributes) validate(*attributes, n, path_);
    return particles;
  }

  std::string path_;
  std::string bytes_;
  PlyEncoding encoding_ = PlyEncoding::Ascii;
  std::vector<PlyElement> elements_;
  size_t cursor_ = 0;
};

}  // namespace

ParticleSet read_ply(const std::filesystem::path& path, const ParticleReadOptions& options) {
  PlyParser parser(path.string(), read_file_bytes(path));
  return parser.parse(options);
}

}  // namespace pfill

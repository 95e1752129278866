// CSV particle reader: the header names the columns (x,y,z and optionally
// radius, r,g,b or red,green,blue, vx,vy,vz, in any order); other columns
// are ignored. Errors name the file and the line.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "io/read_file_bytes.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"

namespace pfill {
namespace {

std::string trim(std::string s) {
  auto space = [](unsigned char c) { return std::isspace(c) || c == '"' || c == '\''; };
  while (!s.empty() && space(static_cast<unsigned char>(s.back()))) s.pop_back();
  size_t start = 0;
  while (start < s.size() && space(static_cast<unsigned char>(s[start]))) ++start;
  return s.substr(start);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  size_t start = 0;
  for (;;) {
    const size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string::npos ? std::string::npos : comma - start)));
    if (comma == std::string::npos) return fields;
    start = comma + 1;
  }
}

}  // namespace

ParticleSet read_csv(const std::filesystem::path& path, const ParticleReadOptions& options) {
  const std::string bytes = read_file_bytes(path);
  const std::string name = path.string();
  auto fail = [&](const std::string& why) -> void { throw Error("cannot read CSV '" + name + "': " + why); };

  size_t cursor = 0;
  size_t line_number = 0;
  auto next_line = [&](std::string& line) {
    while (cursor < bytes.size()) {
      size_t end = bytes.find('\n', cursor);
      if (end == std::string::npos) end = bytes.size();
      line = bytes.substr(cursor, end - cursor);
      cursor = end + 1;
      ++line_number;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!trim(line).empty()) return true;
    }
    return false;
  };

  std::string line;
  if (!next_line(line)) fail("the file is empty (expected a header such as x,y,z,radius)");
  std::vector<std::string> header = split(line);
  for (std::string& column : header)
    std::transform(column.begin(), column.end(), column.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  auto column = [&](std::initializer_list<const char*> names) -> int {
    for (const char* wanted : names)
      for (size_t k = 0; k < header.size(); ++k)
        if (header[k] == wanted) return static_cast<int>(k);
    return -1;
  };
  const int x = column({"x"}), y = column({"y"}), z = column({"z"});
  if (x < 0 || y < 0 || z < 0)
    fail("the header '" + excerpt(line) + "' lacks x, y or z (the first line must name the columns)");
  const int radius = column({"radius", "pscale"});  // pscale, cd.*, v.*: --attribute-names houdini
  if (radius < 0 && !(options.default_radius > 0))
    fail("there is no 'radius' column: give a default radius (e.g. --radius R)");
  const int r = column({"r", "red", "cd.r"}), g = column({"g", "green", "cd.g"}), b = column({"b", "blue", "cd.b"});
  const bool colours = r >= 0 && g >= 0 && b >= 0;
  const double colour_scale = colours && header[r] == "cd.r" ? 255.0 : 1.0;  // Houdini's Cd: floats 0..1
  const int vx = column({"vx", "v.x"}), vy = column({"vy", "v.y"}), vz = column({"vz", "v.z"});
  const bool velocities = vx >= 0 && vy >= 0 && vz >= 0;
  const int id = column({"id"});
  // Boundary particles' attributes, read when asked for.
  ParticleAttributes* attributes = options.attributes;
  const int kind = attributes ? column({"kind"}) : -1, area = attributes ? column({"area"}) : -1;
  const int nx = attributes ? column({"nx"}) : -1, ny = column({"ny"}), nz = column({"nz"});
  const bool normals = nx >= 0 && ny >= 0 && nz >= 0;
  if (attributes) *attributes = {};
  const size_t needed = static_cast<size_t>(std::max({x, y, z, radius, colours ? std::max({r, g, b}) : -1,
                                                      velocities ? std::max({vx, vy, vz}) : -1, id, kind, area,
                                                      normals ? std::max({nx, ny, nz}) : -1})) + 1;

  ParticleSet particles;
  while (next_line(line)) {
    const std::vector<std::string> fields = split(line);
    if (fields.size() < needed)
      fail("line " + std::to_string(line_number) + " has " + std::to_string(fields.size()) +
           " fields, the header needs " + std::to_string(needed));
    auto number = [&](int k) {
      const std::string& text = fields[k];
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0')
        fail("line " + std::to_string(line_number) + ": '" + excerpt(text) + "' in column '" + excerpt(header[k]) +
             "' is not a number");
      return v;
    };
    particles.positions.emplace_back(number(x), number(y), number(z));
    particles.radii.push_back(radius >= 0 ? number(radius) : options.default_radius);
    if (colours) {
      Rgb8 c{};
      const int columns[3] = {r, g, b};
      for (int k = 0; k < 3; ++k) {
        const double v = number(columns[k]) * colour_scale;
        if (!(v >= 0 && v <= 255))
          fail("line " + std::to_string(line_number) + ": colour " + excerpt(fields[columns[k]]) +
               " is outside 0..255");
        c[k] = static_cast<uint8_t>(std::lround(v));
      }
      particles.colours.push_back(c);
    }
    if (velocities) particles.velocities.emplace_back(number(vx), number(vy), number(vz));
    if (id >= 0) {
      const double v = number(id);
      if (!(v >= 0 && v < 1.8e19 && v == std::floor(v)))
        fail("line " + std::to_string(line_number) + ": id " + fields[id] + " is not a whole number >= 0");
      particles.ids.push_back(static_cast<uint64_t>(v));
    }
    if (kind >= 0) attributes->kinds.push_back(kind_of(number(kind)));
    if (normals) attributes->normals.emplace_back(number(nx), number(ny), number(nz));
    if (area >= 0) attributes->areas.push_back(number(area));
  }
  validate(particles, name);
  if (attributes) validate(*attributes, particles.size(), name);
  return particles;
}

}  // namespace pfill

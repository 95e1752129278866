// Readers for the particle formats pfill writes beyond PLY and CSV (GLB, VTP,
// LAMMPS data, Yade text), so `pfill check` measures any file a fill wrote.
// Each checks counts and offsets against the file before use: a truncated
// or foreign file gives pfill::Error, not a crash.
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "io/read_file_bytes.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/srgb.hpp"

namespace fs = std::filesystem;

namespace pfill {
namespace {

[[noreturn]] void bad(const fs::path& path, const std::string& what) {
  throw Error("cannot read '" + path.string() + "': " + what);
}

void finish(ParticleSet& s, const fs::path& path, const ParticleReadOptions& options) {
  if (s.radii.empty() && !s.positions.empty()) {
    if (!(options.default_radius > 0)) bad(path, "the file has no radii; give one (--radius)");
    s.radii.assign(s.positions.size(), options.default_radius);
  }
  for (size_t i = 0; i < s.size(); ++i) {
    const Vec3& p = s.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !std::isfinite(s.radii[i]) ||
        !(s.radii[i] > 0))
      bad(path, "particle " + std::to_string(i + 1) + " has a position or radius that is not a finite number > 0");
  }
}

// The boundary particles' attributes from columns of n entries (empty:
// absent; normals 3 per particle), checked.
void set_attributes(ParticleAttributes* a, size_t n, const std::vector<double>& kinds,
                    const std::vector<double>& normals, const std::vector<double>& areas, const fs::path& path) {
  if (!a) return;
  *a = {};
  for (double k : kinds) a->kinds.push_back(kind_of(k));
  for (size_t i = 0; i + 2 < normals.size(); i += 3)
    a->normals.emplace_back(normals[i], normals[i + 1], normals[i + 2]);
  a->areas = areas;
  if (!normals.empty() && normals.size() != 3 * n) bad(path, "its normals differ in length from its points");
  validate(*a, n, path.string());
}

template <class T>
T load(const std::string& bytes, size_t at) {
  T v;
  std::memcpy(&v, bytes.data() + at, sizeof v);
  return v;
}

uint8_t srgb8_of(double linear) {
  const double v = std::lround(255.0 * linear_to_srgb(static_cast<float>(std::min(1.0, std::max(0.0, linear)))));
  return static_cast<uint8_t>(v);
}

}  // namespace

ParticleSet read_glb(const fs::path& path, const ParticleReadOptions& options) {
  const std::string bytes = read_file_bytes(path);
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0) bad(path, "not a binary glTF (.glb) file");
  nlohmann::json gltf;
  std::string binary;
  bool have_json = false;
  for (size_t at = 12; at + 8 <= bytes.size();) {
    const uint32_t length = load<uint32_t>(bytes, at), kind = load<uint32_t>(bytes, at + 4);
    if (length > bytes.size() - at - 8) bad(path, "a chunk runs past the end of the file");
    const std::string chunk = bytes.substr(at + 8, length);
    if (kind == 0x4E4F534A) {
      gltf = nlohmann::json::parse(chunk, nullptr, false);
      if (gltf.is_discarded() || !gltf.is_object()) bad(path, "its JSON chunk does not parse");
      have_json = true;
    } else if (kind == 0x004E4942) {
      binary = chunk;
    }
    at += 8 + static_cast<size_t>(length);
  }
  if (!have_json) bad(path, "no JSON chunk");
  ParticleSet s;
  try {
    const nlohmann::json& meshes = gltf.value("meshes", nlohmann::json::array());
    int mesh_index = -1;
    nlohmann::json primitive;
    for (size_t m = 0; m < meshes.size() && mesh_index < 0; ++m)
      for (const auto& p : meshes[m].value("primitives", nlohmann::json::array()))
        if (p.value("mode", 4) == 0 && p["attributes"].contains("POSITION")) {
          primitive = p;
          mesh_index = static_cast<int>(m);
          break;
        }
    if (mesh_index < 0) {
      if (meshes.empty()) return s;  // pfill's GLB of no particles
      bad(path, "no POINTS primitive (is it a pfill particle file?)");
    }
    Vec3 origin;
    for (const auto& node : gltf.value("nodes", nlohmann::json::array()))
      if (node.value("mesh", -1) == mesh_index && node.contains("translation")) {
        origin = {node["translation"][0].get<double>(), node["translation"][1].get<double>(),
                  node["translation"][2].get<double>()};
        break;
      }
    auto floats = [&](const char* name, size_t width) {
      const auto& a = gltf.at("accessors").at(primitive["attributes"][name].get<size_t>());
      if (a.value("componentType", 0) != 5126) bad(path, std::string(name) + " is not float");
      const auto& view = gltf.at("bufferViews").at(a.at("bufferView").get<size_t>());
      const size_t count = a.at("count").get<size_t>();
      const size_t start = view.value("byteOffset", size_t(0)) + a.value("byteOffset", size_t(0));
      const size_t row = 4 * width, stride = view.value("byteStride", size_t(0)) ? view["byteStride"].get<size_t>() : row;
      if (count > 0 && (start > binary.size() || (count - 1) > (binary.size() - start) / stride ||
                        start + (count - 1) * stride + row > binary.size()))
        bad(path, std::string("accessor ") + name + " runs past the binary chunk");
      std::vector<double> out(count * width);
      for (size_t i = 0; i < count; ++i)
        for (size_t k = 0; k < width; ++k) out[i * width + k] = load<float>(binary, start + i * stride + 4 * k);
      return out;
    };
    const std::vector<double> p = floats("POSITION", 3);
    const size_t n = p.size() / 3;
    for (size_t i = 0; i < n; ++i)
      s.positions.push_back(Vec3{p[3 * i], p[3 * i + 1], p[3 * i + 2]} + origin);
    if (primitive["attributes"].contains("_RADIUS")) s.radii = floats("_RADIUS", 1);
    if (primitive["attributes"].contains("_ID"))
      for (double id : floats("_ID", 1)) s.ids.push_back(static_cast<uint64_t>(std::llround(id)));
    if (primitive["attributes"].contains("COLOR_0")) {
      const std::vector<double> c = floats("COLOR_0", 3);
      for (size_t i = 0; i < c.size() / 3; ++i)
        s.colours.push_back({srgb8_of(c[3 * i]), srgb8_of(c[3 * i + 1]), srgb8_of(c[3 * i + 2])});
    }
    if ((!s.radii.empty() && s.radii.size() != n) || (!s.ids.empty() && s.ids.size() != n) ||
        (!s.colours.empty() && s.colours.size() != n))
      bad(path, "its attributes differ in length");
    if (options.attributes) {
      auto optional = [&](const char* name, size_t width) {
        return primitive["attributes"].contains(name) ? floats(name, width) : std::vector<double>();
      };
      set_attributes(options.attributes, n, optional("_KIND", 1), optional("_NORMAL", 3), optional("_AREA", 1), path);
    }
  } catch (const nlohmann::json::exception& e) {
    bad(path, std::string("not pfill's glTF layout (") + e.what() + ")");
  }
  finish(s, path, options);
  return s;
}

ParticleSet read_vtp(const fs::path& path, const ParticleReadOptions& options) {
  const std::string bytes = read_file_bytes(path);
  const size_t appended = bytes.find("<AppendedData");
  const std::string head = bytes.substr(0, appended);
  auto attribute = [](const std::string& tag, const std::string& name) {
    const size_t at = tag.find(" " + name + "=\"");
    if (at == std::string::npos) return std::string();
    const size_t start = at + name.size() + 3, end = tag.find('"', start);
    return end == std::string::npos ? std::string() : tag.substr(start, end - start);
  };
  const size_t piece = head.find("<Piece");
  if (piece == std::string::npos || head.find("PolyData") == std::string::npos) bad(path, "not VTK PolyData");
  size_t n = 0;
  try {
    n = std::stoull(attribute(head.substr(piece, head.find('>', piece) - piece), "NumberOfPoints"));
  } catch (const std::exception&) {
    bad(path, "no NumberOfPoints");
  }
  if (n > bytes.size()) bad(path, "more points than the file has bytes");
  size_t data = std::string::npos;
  if (appended != std::string::npos) {
    data = bytes.find('_', appended);
    if (data == std::string::npos) bad(path, "AppendedData holds no '_'");
    ++data;
  }
  // One array by name: its values as doubles.
  auto array = [&](const std::string& name, size_t width, bool required) {
    std::vector<double> out;
    const size_t at = head.find("Name=\"" + name + "\"");
    if (at == std::string::npos) {
      if (required) bad(path, "no " + name + " array");
      return out;
    }
    const size_t open = head.rfind("<DataArray", at), close = head.find('>', at);
    const std::string tag = head.substr(open, close - open);
    const std::string type = attribute(tag, "type"), format = attribute(tag, "format");
    const size_t size = type == "Float64" || type == "Int64" || type == "UInt64" ? 8
                        : type == "Float32" || type == "Int32" || type == "UInt32" ? 4
                        : type == "UInt8" ? 1 : 0;
    if (size == 0) bad(path, name + " has type '" + excerpt(type) + "', which pfill does not read");
    const size_t count = n * width;
    out.resize(count);
    if (format == "appended") {
      if (data == std::string::npos) bad(path, "no AppendedData for " + name);
      size_t offset = 0;
      try {
        offset = std::stoull(attribute(tag, "offset"));
      } catch (const std::exception&) {
        bad(path, name + " has no offset");
      }
      const size_t start = data + offset + 8;  // UInt64 header: the byte count
      if (offset > bytes.size() || start > bytes.size() || count > (bytes.size() - start) / size)
        bad(path, name + " runs past the end of the file");
      for (size_t k = 0; k < count; ++k) {
        const size_t b = start + k * size;
        out[k] = type == "Float64" ? load<double>(bytes, b)
                 : type == "Float32" ? load<float>(bytes, b)
                 : type == "Int64" ? static_cast<double>(load<int64_t>(bytes, b))
                 : type == "UInt64" ? static_cast<double>(load<uint64_t>(bytes, b))
                 : type == "Int32" ? load<int32_t>(bytes, b)
                 : type == "UInt32" ? load<uint32_t>(bytes, b) : static_cast<unsigned char>(bytes[b]);
      }
    } else if (format == "ascii") {
      const size_t end = head.find("</DataArray>", close);
      std::istringstream text(head.substr(close + 1, end - close - 1));
      for (size_t k = 0; k < count; ++k)
        if (!(text >> out[k])) bad(path, name + " has fewer than " + std::to_string(count) + " numbers");
    } else {
      bad(path, name + " is in format '" + excerpt(format) + "', which pfill does not read");
    }
    return out;
  };
  ParticleSet s;
  const std::vector<double> p = array("Points", 3, true);
  for (size_t i = 0; i < n; ++i) s.positions.push_back({p[3 * i], p[3 * i + 1], p[3 * i + 2]});
  s.radii = array("radius", 1, false);
  for (double id : array("id", 1, false)) s.ids.push_back(static_cast<uint64_t>(id));
  if (options.attributes)
    set_attributes(options.attributes, n, array("kind", 1, false), array("normal", 3, false), array("area", 1, false),
                   path);
  finish(s, path, options);
  return s;
}

ParticleSet read_lammps_data(const fs::path& path, const ParticleReadOptions& options) {
  std::istringstream in(read_file_bytes(path));
  std::string line;
  size_t atoms = 0;
  bool counted = false;
  ParticleSet s;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string first, second;
    words >> first >> second;
    if (second == "atoms" && !counted) {
      try {
        atoms = std::stoull(first);
      } catch (const std::exception&) {
        bad(path, "the atom count '" + excerpt(first) + "' is not a number");
      }
      counted = true;
    }
    if (first != "Atoms") continue;
    if (!counted) bad(path, "the Atoms section comes before the atom count");
    if (line.find("sphere") == std::string::npos && line.find('#') != std::string::npos)
      bad(path, "the Atoms section is not atom_style sphere");
    while (s.size() < atoms && std::getline(in, line)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      std::istringstream fields(line);
      double id = 0, type = 0, diameter = 0, density = 0;
      Vec3 p;
      if (!(fields >> id >> type >> diameter >> density >> p.x >> p.y >> p.z))
        bad(path, "an Atoms line is not `id type diameter density x y z`: '" + excerpt(line) + "'");
      s.ids.push_back(static_cast<uint64_t>(id));
      s.radii.push_back(diameter / 2);
      s.positions.push_back(p);
    }
    break;
  }
  if (!counted) bad(path, "no atom count: not a LAMMPS data file");
  if (options.attributes) *options.attributes = {};  // atom types are not kinds in every file
  if (s.size() != atoms) bad(path, "the Atoms section holds " + std::to_string(s.size()) + " of " +
                                       std::to_string(atoms) + " atoms");
  finish(s, path, options);
  return s;
}

ParticleSet read_xyzr(const fs::path& path, const ParticleReadOptions& options) {
  std::istringstream in(read_file_bytes(path));
  std::string line;
  ParticleSet s;
  size_t number = 0;
  // pfill's comment line `# x y z r id ...` names the columns past the fourth.
  std::vector<std::string> names;
  std::vector<double> kinds, normals, areas;
  auto column = [&](const char* name) {
    const auto at = std::find(names.begin(), names.end(), name);
    return at == names.end() ? -1 : static_cast<int>(at - names.begin());
  };
  int kind = -1, nx = -1, area = -1;
  while (std::getline(in, line)) {
    ++number;
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos) continue;
    if (line[start] == '#') {
      std::istringstream words(line.substr(start + 1));
      std::vector<std::string> w{std::istream_iterator<std::string>(words), std::istream_iterator<std::string>()};
      if (w.size() >= 4 && w[0] == "x" && w[1] == "y" && w[2] == "z" && w[3] == "r") {
        names = w;
        kind = column("kind"), nx = column("nx"), area = column("area");
      }
      continue;
    }
    std::istringstream fields(line);
    std::vector<double> v;
    for (double x; fields >> x;) v.push_back(x);
    if (v.size() < 4) bad(path, "line " + std::to_string(number) + " is not `x y z r`: '" + excerpt(line) + "'");
    s.positions.push_back({v[0], v[1], v[2]});
    s.radii.push_back(v[3]);
    if (v.size() > 4) s.ids.push_back(static_cast<uint64_t>(v[4]));
    auto at = [&](int k) {
      if (static_cast<size_t>(k) >= v.size())
        bad(path, "line " + std::to_string(number) + " lacks columns its header names");
      return v[k];
    };
    if (kind >= 0) kinds.push_back(at(kind));
    if (nx >= 0) normals.insert(normals.end(), {at(nx), at(nx + 1), at(nx + 2)});
    if (area >= 0) areas.push_back(at(area));
  }
  if (!s.ids.empty() && s.ids.size() != s.size()) s.ids.clear();
  set_attributes(options.attributes, s.size(), kinds, normals, areas, path);
  finish(s, path, options);
  return s;
}

}  // namespace pfill

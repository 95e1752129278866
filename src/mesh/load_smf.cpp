// Reader of SMF, the simple text format the report used (Garland's QSlim
// format): vertices, polygons, colours with a binding, comments.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"

namespace pfill {
namespace {

enum class Binding { Unset, Vertex, Face, Corner };

struct SmfReader {
  std::string path;
  size_t line_number = 0;

  [[noreturn]] void fail(const std::string& problem) const {
    throw Error(path + ":" + std::to_string(line_number) + ": " + problem);
  }

  // A whole token as a finite double; anything else names the line.
  double number(const std::string& token) const {
    const char* begin = token.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end == begin || *end != '\0') fail("malformed number '" + excerpt(token) + "'");
    if (!std::isfinite(v)) fail("NaN or infinite value '" + excerpt(token) + "'");
    return v;
  }
};

}  // namespace

Mesh load_smf(const std::string& path) {
  detail::require_readable_file(path);
  std::ifstream in(path);
  SmfReader reader{path};

  Mesh mesh;
  mesh.source = path;
  std::vector<std::array<double, 3>> colours;
  std::vector<size_t> face_sizes;                   // corner count of each source face, for colours
  std::vector<size_t> triangle_face;                // source face of each triangle
  std::vector<std::array<size_t, 3>> triangle_corner;  // corner indices within the face
  Binding binding = Binding::Unset;

  std::string line;
  while (std::getline(in, line)) {
    ++reader.line_number;
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string command;
    if (!(words >> command)) continue;  // blank line
    std::vector<std::string> args;
    for (std::string w; words >> w;) args.push_back(w);

    if (command == "v") {
      if (args.size() < 3) reader.fail("vertex needs 3 coordinates, found " + std::to_string(args.size()));
      mesh.positions.push_back({reader.number(args[0]), reader.number(args[1]), reader.number(args[2])});
    } else if (command == "f") {
      if (args.size() < 3) reader.fail("face needs at least 3 vertex indices, found " + std::to_string(args.size()));
      std::vector<uint32_t> polygon;
      for (const std::string& a : args) {
        const double v = reader.number(a);
        if (v != std::floor(v)) reader.fail("vertex index '" + excerpt(a) + "' is not an integer");
        // Faces may only use vertices defined above them (1-based).
        if (v < 1 || v > static_cast<double>(mesh.positions.size()))
          reader.fail("vertex index " + a + " out of range (1.." + std::to_string(mesh.positions.size()) + ")");
        polygon.push_back(static_cast<uint32_t>(v) - 1);
      }
      const size_t face = face_sizes.size();
      for (size_t k = 1; k + 1 < polygon.size(); ++k) {  // fan about the first corner
        mesh.triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
        triangle_face.push_back(face);
        triangle_corner.push_back({0, k, k + 1});
      }
      face_sizes.push_back(polygon.size());
    } else if (command == "c") {
      if (args.size() < 3) reader.fail("colour needs 3 components, found " + std::to_string(args.size()));
      colours.push_back({reader.number(args[0]), reader.number(args[1]), reader.number(args[2])});
    } else if (command == "bind") {
      if (args.size() < 2) reader.fail("bind needs an attribute and a mode, e.g. 'bind c vertex'");
      if (args[0] != "c") continue;  // normals and texture coordinates are not used
      if (args[1] == "vertex") binding = Binding::Vertex;
      else if (args[1] == "face") binding = Binding::Face;
      else if (args[1] == "corner") binding = Binding::Corner;
      else reader.fail("unknown colour binding '" + excerpt(args[1]) + "' (use vertex, face or corner)");
    }
    // Every other command (n, r, begin, end, trans, ...) does not change the surface we need.
  }
  if (in.bad()) throw Error(path + ": reading failed after line " + std::to_string(reader.line_number));
  reader.line_number = 0;

  if (!colours.empty()) {
    size_t corners = 0;
    for (size_t n : face_sizes) corners += n;
    if (binding == Binding::Unset)  // no bind line: guess from the count
      binding = colours.size() == mesh.positions.size() ? Binding::Vertex
                : colours.size() == face_sizes.size() ? Binding::Face
                                                        : Binding::Vertex;
    const size_t expected = binding == Binding::Vertex ? mesh.positions.size()
                            : binding == Binding::Face ? face_sizes.size()
                                                       : corners;
    if (colours.size() != expected)
      throw Error(path + ": " + std::to_string(colours.size()) + " colours for " + std::to_string(expected) +
                  (binding == Binding::Vertex ? " vertices" : binding == Binding::Face ? " faces" : " corners") +
                  " (bind c " +
                  (binding == Binding::Vertex ? "vertex" : binding == Binding::Face ? "face" : "corner") + ")");
    // Colours are either in [0, 1] or in 0..255; anything above 1 means the latter.
    double largest = 0;
    for (const auto& c : colours)
      for (double v : c) largest = std::max(largest, v);
    const double scale = largest > 1.0 ? 1.0 / 255.0 : 1.0;
    auto rgba = [&](size_t i) {
      const auto& c = colours[i];
      return Rgba{static_cast<float>(std::clamp(c[0] * scale, 0.0, 1.0)),
                  static_cast<float>(std::clamp(c[1] * scale, 0.0, 1.0)),
                  static_cast<float>(std::clamp(c[2] * scale, 0.0, 1.0)), 1.0f};
    };
    std::vector<size_t> face_first_corner(face_sizes.size(), 0);
    for (size_t f = 1; f < face_sizes.size(); ++f)
      face_first_corner[f] = face_first_corner[f - 1] + face_sizes[f - 1];
    mesh.corner_colours.reserve(3 * mesh.triangles.size());
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const size_t i = binding == Binding::Vertex ? mesh.triangles[t][k]
                         : binding == Binding::Face ? triangle_face[t]
                                                    : face_first_corner[triangle_face[t]] + triangle_corner[t][k];
        mesh.corner_colours.push_back(rgba(i));
      }
  }

  if (mesh.triangles.empty()) throw Error(path + ": no triangles: the file has no faces ('f' lines); pfill needs a triangle surface");
  validate(mesh);
  return mesh;
}

}  // namespace pfill

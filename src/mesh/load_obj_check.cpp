// OBJ vertex lines, read here in double before assimp reads the file: a
// check (assimp's number parser stops at the first character that is not
// part of a number, so it reads "0/881192" as 0, and its vertex order is
// lost by the time a NaN is found; here every `v` coordinate must be a
// whole, finite number, and errors name the OBJ vertex, 1-based as OBJ
// counts, and the line), and a shift towards the origin for meshes far
// from it (assimp keeps positions in single precision).
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh.hpp"

namespace pfill::detail {

namespace {

// Calls `vertex(number, line, tokens)` for each `v` line of `text`; tokens
// are the line's words after the `v`.
template <typename F>
void for_each_vertex_line(const std::string& text, F vertex_line) {
  size_t line_number = 0, vertex = 0;
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    ++line_number;
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
    ++vertex;
    std::vector<std::string> tokens;
    for (size_t i = 1; i < line.size();) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
      size_t j = i;
      while (j < line.size() && line[j] != ' ' && line[j] != '\t' && line[j] != '\r') ++j;
      if (j > i) tokens.push_back(line.substr(i, j - i));
      i = j;
    }
    vertex_line(vertex, line_number, tokens);
  }
}

}  // namespace

Box3 check_obj_vertices(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  Box3 box;
  for_each_vertex_line(std::string(bytes.begin(), bytes.end()), [&](size_t vertex, size_t line_number,
                                                                    const std::vector<std::string>& tokens) {
    const std::string where =
        path + ": vertex " + std::to_string(vertex) + " (line " + std::to_string(line_number) + ")";
    if (tokens.size() < 3) throw Error(where + " has " + std::to_string(tokens.size()) + " coordinates, not 3");
    for (size_t k = 0; k < tokens.size() && k < 3; ++k) {
      char* stop = nullptr;
      const double v = std::strtod(tokens[k].c_str(), &stop);
      if (stop == tokens[k].c_str() || *stop != '\0')
        throw Error(where + ": '" + excerpt(tokens[k]) + "' is not a number; repair or re-export the mesh");
      if (!std::isfinite(v))
        throw Error(where + " has a NaN or infinite coordinate; repair or re-export the mesh");
      if (std::fabs(v) > kMaxCoordinate)
        throw Error(where + " has a coordinate of " + excerpt(tokens[k]) + ", beyond the +-1e15 pfill computes "
                    "with; rescale the mesh");
    }
    box.add({std::strtod(tokens[0].c_str(), nullptr), std::strtod(tokens[1].c_str(), nullptr),
             std::strtod(tokens[2].c_str(), nullptr)});
  });
  return box;
}

std::string shift_obj_vertices(const std::string& path, const Vec3& shift) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  const std::string text(bytes.begin(), bytes.end());
  std::string out;
  out.reserve(text.size() + text.size() / 4);
  for (size_t start = 0; start < text.size();) {
    size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.size() >= 2 && line[0] == 'v' && (line[1] == ' ' || line[1] == '\t')) {
      const char* cursor = line.c_str() + 1;
      char number[40];
      out += 'v';
      for (int k = 0; k < 3; ++k) {
        char* stop = nullptr;
        const double v = std::strtod(cursor, &stop);
        cursor = stop;
        std::snprintf(number, sizeof number, " %.17g", v - shift[k]);
        out += number;
      }
      out += cursor;  // colours or w, as they were
    } else {
      out += line;
    }
    out += '\n';
  }
  return out;
}

}  // namespace pfill::detail

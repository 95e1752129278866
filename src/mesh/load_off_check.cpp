// OFF face lines, checked before assimp reads the file: assimp drops a face
// whose index is out of range (-7, or past the vertex count) without a word,
// so a fill got 2 of 4 triangles and failed later with "no particles"
// (issue 33). OBJ and PLY already say "index out of range"; so does OFF now.
#include <sstream>
#include <string>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"

namespace pfill::detail {

void check_off_indices(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  std::istringstream in(std::string(bytes.begin(), bytes.end()));
  std::string line;
  size_t line_number = 0;
  // The next line that holds something other than a comment.
  auto next = [&](std::string& out) {
    while (std::getline(in, line)) {
      ++line_number;
      const size_t hash = line.find('#');
      out = line.substr(0, hash);
      if (out.find_first_not_of(" \t\r") != std::string::npos) return true;
    }
    return false;
  };
  std::string text;
  if (!next(text)) return;  // empty: the loader says so
  std::istringstream head(text);
  std::string keyword;
  head >> keyword;
  if (keyword.size() < 3 || keyword.compare(keyword.size() - 3, 3, "OFF") != 0) return;  // not OFF text: leave it to assimp
  if (keyword != "OFF") return;  // COFF, NOFF, STOFF, 4OFF ...: other layouts; assimp reads them as it can
  std::string rest;
  if (head >> rest) {
    if (rest == "BINARY") return;
    head.clear();
    head.str(text.substr(text.find("OFF") + 3));
  } else if (!next(text)) {
    return;
  } else {
    head.clear();
    head.str(text);
  }
  long long vertices = -1, faces = -1;
  if (!(head >> vertices >> faces) || vertices < 0 || faces < 0)
    throw Error(path + ":" + std::to_string(line_number) + ": the OFF header needs the vertex and face counts");
  for (long long v = 0; v < vertices; ++v)
    if (!next(text)) throw Error(path + ": the file ends after " + std::to_string(v) + " of its " +
                                 std::to_string(vertices) + " vertices");
  for (long long f = 0; f < faces; ++f) {
    if (!next(text)) throw Error(path + ": the file ends after " + std::to_string(f) + " of its " +
                                 std::to_string(faces) + " faces");
    std::istringstream face(text);
    long long corners = 0;
    if (!(face >> corners) || corners < 0)
      throw Error(path + ":" + std::to_string(line_number) + ": a face line must start with its corner count");
    for (long long k = 0; k < corners; ++k) {
      long long index = 0;
      if (!(face >> index))
        throw Error(path + ":" + std::to_string(line_number) + ": face " + std::to_string(f) + " has fewer than " +
                    std::to_string(corners) + " vertex indices");
      if (index < 0 || index >= vertices)
        throw Error(path + ":" + std::to_string(line_number) + ": vertex index " + std::to_string(index) +
                    " out of range (the file has " + std::to_string(vertices) + " vertices, numbered from 0)");
    }
  }
}

}  // namespace pfill::detail

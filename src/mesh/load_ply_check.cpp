// A structural check of PLY files, run before assimp reads one: assimp 5.2's
// PLY reader hangs or crashes on malformed headers and on bodies whose list
// counts or token counts do not match the header (measured with the fuzz test
// in tests/test_bad_input.cpp: 35 of 200 corrupted files). This walks the
// header and the body exactly as the header describes them, keeping no
// values, and throws pfill::Error at the first mismatch.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"

namespace pfill::detail {
namespace {

// Byte size of a PLY scalar type, 0 if unknown.
int ply_type_size(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

bool ply_type_is_integer(const std::string& type) {
  return type != "float" && type != "float32" && type != "double" && type != "float64";
}

struct PlyProperty {
  std::string type;        // scalar type, or the item type of a list
  std::string count_type;  // empty unless a list
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> properties;
};

enum class PlyFormat { Ascii, LittleEndian, BigEndian };

class PlyChecker {
 public:
  PlyChecker(const std::vector<uint8_t>& bytes, const std::string& path) : bytes_(bytes), path_(path) {}

  void check() {
    const size_t body = read_header();
    if (format_ == PlyFormat::Ascii) check_ascii_body(body);
    else check_binary_body(body);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const {
    throw Error(path_ + ": malformed PLY file: " + problem + "; re-export the mesh");
  }

  // Next header line (without \r\n) starting at `at`; false at the end of the file.
  bool next_line(size_t& at, std::string& line) const {
    if (at >= bytes_.size()) return false;
    const void* nl = std::memchr(bytes_.data() + at, '\n', bytes_.size() - at);
    const size_t end = nl ? static_cast<size_t>(static_cast<const uint8_t*>(nl) - bytes_.data()) : bytes_.size();
    line.assign(reinterpret_cast<const char*>(bytes_.data()) + at, end - at);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    at = end + 1;
    return true;
  }

  // Returns the offset of the body.
  size_t read_header() {
    size_t at = 0;
    std::string line;
    if (!next_line(at, line) || line != "ply") fail("the first line is not 'ply'");
    bool have_format = false;
    for (int number = 2;; ++number) {
      if (!next_line(at, line)) fail("the header has no 'end_header' line");
      std::istringstream words(line);
      std::string keyword;
      words >> keyword;
      const std::string where = "header line " + std::to_string(number);
      if (keyword == "end_header") break;
      if (keyword == "comment" || keyword == "obj_info" || keyword.empty()) continue;
      if (keyword == "format") {
        std::string kind, version;
        words >> kind >> version;
        if (kind == "ascii") format_ = PlyFormat::Ascii;
        else if (kind == "binary_little_endian") format_ = PlyFormat::LittleEndian;
        else if (kind == "binary_big_endian") format_ = PlyFormat::BigEndian;
        else fail(where + " names an unknown format '" + excerpt(kind) + "'");
        if (version != "1.0") fail(where + ": unsupported version '" + excerpt(version) + "'");
        have_format = true;
      } else if (keyword == "element") {
        PlyElement e;
        std::string count;
        words >> e.name >> count;
        if (e.name.empty() || !parse_count(count, e.count)) fail(where + ": bad element line");
        elements_.push_back(e);
      } else if (keyword == "property") {
        if (elements_.empty()) fail(where + ": property before any element");
        PlyProperty p;
        std::string first, name;
        words >> first;
        if (first == "list") {
          words >> p.count_type >> p.type >> name;
          if (ply_type_size(p.count_type) == 0 || !ply_type_is_integer(p.count_type))
            fail(where + ": bad list count type '" + excerpt(p.count_type) + "'");
        } else {
          p.type = first;
          words >> name;
        }
        if (ply_type_size(p.type) == 0 || name.empty()) fail(where + ": bad property line");
        elements_.back().properties.push_back(p);
      } else {
        fail(where + " starts with an unknown keyword '" + excerpt(keyword) + "'");
      }
      std::string extra;
      if (keyword != "format" && keyword != "element" && keyword != "property") continue;
      if (words >> extra) fail(where + " has extra words");
    }
    if (!have_format) fail("the header has no 'format' line");
    return at;
  }

  static bool parse_count(const std::string& text, size_t& value) {
    if (text.empty() || text.size() > 12) return false;
    for (char c : text)
      if (c < '0' || c > '9') return false;
    value = std::strtoull(text.c_str(), nullptr, 10);
    return true;
  }

  // ASCII: one instance per line; every token a number; list counts match.
  void check_ascii_body(size_t at) {
    std::string line;
    size_t line_number = 0;
    for (const PlyElement& e : elements_)
      for (size_t i = 0; i < e.count; ++i) {
        do {
          if (!next_line(at, line))
            fail("the file ends in element '" + e.name + "' after " + std::to_string(i) + " of " +
                 std::to_string(e.count) + " (truncated)");
          ++line_number;
        } while (line.find_first_not_of(" \t") == std::string::npos);
        std::istringstream words(line);
        for (const PlyProperty& p : e.properties) {
          size_t items = 1;
          if (!p.count_type.empty()) {
            const double n = number(words, e, i);
            if (n < 0 || n != std::floor(n) || n > 1e6) fail("bad list length in element '" + e.name + "'");
            check_face_size(e, i, static_cast<int64_t>(n));
            items = static_cast<size_t>(n);
          }
          for (size_t k = 0; k < items; ++k) number(words, e, i);
        }
        std::string extra;
        if (words >> extra) fail("extra values in element '" + e.name + "' " + std::to_string(i));
      }
  }

  double number(std::istringstream& words, const PlyElement& e, size_t i) const {
    std::string token;
    if (!(words >> token)) fail("too few values in element '" + e.name + "' " + std::to_string(i));
    char* end = nullptr;
    const double v = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') fail("malformed number '" + excerpt(token) + "' in element '" + e.name + "'");
    return v;
  }

  // Binary: walk every instance; list lengths must be sane and fit the file.
  void check_binary_body(size_t at) {
    for (const PlyElement& e : elements_) {
      size_t fixed = 0;  // bytes of an instance without list items
      bool has_list = false;
      for (const PlyProperty& p : e.properties) {
        fixed += static_cast<size_t>(ply_type_size(p.count_type.empty() ? p.type : p.count_type));
        has_list = has_list || !p.count_type.empty();
      }
      if (fixed > 0 && e.count > (bytes_.size() - at) / fixed)
        fail("element '" + e.name + "' needs more bytes than the file has (truncated or corrupt)");
      if (!has_list) {
        at += fixed * e.count;
        continue;
      }
      for (size_t i = 0; i < e.count; ++i)
        for (const PlyProperty& p : e.properties) {
          if (p.count_type.empty()) {
            advance(at, static_cast<size_t>(ply_type_size(p.type)), e);
            continue;
          }
          const size_t size = static_cast<size_t>(ply_type_size(p.count_type));
          advance(at, 0, e);
          if (bytes_.size() - at < size) fail("the file ends inside element '" + e.name + "' (truncated)");
          const int64_t n = read_count(at, p.count_type);
          at += size;
          if (n < 0 || n > 1000000) fail("bad list length " + std::to_string(n) + " in element '" + e.name + "'");
          check_face_size(e, i, n);
          advance(at, static_cast<size_t>(n) * static_cast<size_t>(ply_type_size(p.type)), e);
        }
    }
  }

  // A face of fewer than three corners is no polygon (assimp's
  // triangulation aborts on one with none).
  void check_face_size(const PlyElement& e, size_t i, int64_t corners) const {
    if (e.name == "face" && corners < 3)
      fail("face " + std::to_string(i) + " has " + std::to_string(corners) + " corners; a face needs at least 3");
  }

  void advance(size_t& at, size_t size, const PlyElement& e) const {
    if (bytes_.size() - at < size) fail("the file ends inside element '" + e.name + "' (truncated)");
    at += size;
  }

  int64_t read_count(size_t at, const std::string& type) const {
    const int size = ply_type_size(type);
    uint8_t raw[8] = {};
    std::memcpy(raw, bytes_.data() + at, static_cast<size_t>(size));
    if (format_ == PlyFormat::BigEndian)
      for (int k = 0; k < size / 2; ++k) std::swap(raw[k], raw[size - 1 - k]);
    const bool is_signed = type == "char" || type == "int8" || type == "short" || type == "int16" ||
                           type == "int" || type == "int32";
    switch (size) {
      case 1: return is_signed ? static_cast<int8_t>(raw[0]) : raw[0];
      case 2: { uint16_t v; std::memcpy(&v, raw, 2); return is_signed ? static_cast<int16_t>(v) : v; }
      default: { uint32_t v; std::memcpy(&v, raw, 4); return is_signed ? static_cast<int32_t>(v) : static_cast<int64_t>(v); }
    }
  }

  const std::vector<uint8_t>& bytes_;
  std::string path_;
  PlyFormat format_ = PlyFormat::Ascii;
  std::vector<PlyElement> elements_;
};

}  // namespace

void check_ply_structure(const std::string& path) {
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  PlyChecker(bytes, path).check();
}

}  // namespace pfill::detail

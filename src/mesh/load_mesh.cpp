// load_mesh: picks the reader by extension, welds, validates, and turns
// every foreign exception into a pfill::Error that names the file.
#include <assimp/Importer.hpp>

#include <algorithm>
#include <new>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"

namespace pfill {
namespace {

const char* const kListedExtensions[] = {".gltf", ".glb", ".smf", ".obj", ".stl", ".ply",
                                         ".off",  ".fbx", ".dae", ".3ds"};

bool assimp_reads(const std::string& extension) {
  if (extension.size() < 2) return false;
  Assimp::Importer importer;
  return importer.IsExtensionSupported(extension);
}

Mesh read_by_extension(const std::string& path, const std::string& extension) {
  if (extension == ".gltf" || extension == ".glb") return load_gltf(path);
  if (extension == ".smf") return load_smf(path);
  if (assimp_reads(extension)) return load_with_assimp(path);
  std::string list;
  for (const char* e : kListedExtensions) list += std::string(list.empty() ? "" : " ") + e;
  throw Error(path + ": unknown mesh format '" + (extension.empty() ? std::string("(no extension)") : extension) +
              "'; supported: " + list + " and the other formats assimp reads");
}

// Messages quote file contents (assimp and tinygltf do); keep them one
// printable line of valid UTF-8 whatever bytes the file held.
std::string printable(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    size_t length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (size_t k = 1; valid && k < length; ++k) valid = (static_cast<unsigned char>(text[i + k]) >> 6) == 0x2;
    if (!valid) {
      out += '?';
      ++i;
    } else if (length == 1) {
      out += (c < 0x20 || c == 0x7F) ? ' ' : static_cast<char>(c);
      ++i;
    } else {
      out.append(text, i, length);
      i += length;
    }
  }
  return out;
}

}  // namespace

std::vector<std::string> supported_mesh_extensions() {
  std::vector<std::string> list(std::begin(kListedExtensions), std::end(kListedExtensions));
  Assimp::Importer importer;
  std::string assimp_list;  // "*.3ds;*.obj;..."
  importer.GetExtensionList(assimp_list);
  size_t start = 0;
  while (start < assimp_list.size()) {
    size_t end = assimp_list.find(';', start);
    if (end == std::string::npos) end = assimp_list.size();
    std::string e = assimp_list.substr(start, end - start);
    if (e.rfind("*", 0) == 0) e.erase(0, 1);
    if (!e.empty() && e != ".gltf" && e != ".glb" && std::find(list.begin(), list.end(), e) == list.end())
      list.push_back(e);
    start = end + 1;
  }
  return list;
}

Mesh load_mesh(const std::string& path, const LoadOptions& options) {
  try {
    detail::require_readable_file(path);  // first: a FIFO must not block any reader
    Mesh mesh = read_by_extension(path, detail::lower_extension(path));
    mesh.source = path;
    const double diagonal = mesh.bounds().diagonal();
    weld_vertices(mesh, options.weld_tolerance > 0 ? options.weld_tolerance * diagonal : 0.0);
    if (remove_duplicate_triangles(mesh) > 0) weld_vertices(mesh);  // drops the vertices left unused
    validate(mesh);
    mesh.turned_faces = orient_faces(mesh);
    return mesh;
  } catch (const Error& e) {
    throw Error(printable(e.what()));
  } catch (const std::bad_alloc&) {
    throw Error(path + ": out of memory while reading; the file is corrupt or too large for this machine");
  } catch (const std::exception& e) {
    throw Error(printable(path + ": cannot be read: " + excerpt(e.what(), 160)));
  }
}

}  // namespace pfill

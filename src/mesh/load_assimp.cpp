// Reader of OBJ, STL, PLY, OFF, FBX, DAE, 3DS and every other format assimp
// imports: triangulated by assimp, node transforms applied here, all meshes
// merged into one pfill::Mesh.
#include <assimp/DefaultIOSystem.h>
#include <assimp/DefaultLogger.hpp>
#include <assimp/MemoryIOWrapper.h>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <cctype>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"

namespace pfill {
namespace {

double linear_part_determinant(const aiMatrix4x4& t) {
  return static_cast<double>(t.a1) * (static_cast<double>(t.b2) * t.c3 - static_cast<double>(t.b3) * t.c2) -
         static_cast<double>(t.a2) * (static_cast<double>(t.b1) * t.c3 - static_cast<double>(t.b3) * t.c1) +
         static_cast<double>(t.a3) * (static_cast<double>(t.b1) * t.c2 - static_cast<double>(t.b2) * t.c1);
}

WrapMode wrap_mode(int assimp_mode) {
  switch (assimp_mode) {
    case aiTextureMapMode_Clamp: return WrapMode::ClampToEdge;
    case aiTextureMapMode_Mirror: return WrapMode::MirroredRepeat;
    default: return WrapMode::Repeat;
  }
}

// Some assimp readers repair bad input and only log it (the OFF reader clamps
// an out-of-range index to the last vertex). While one import runs, this
// collects assimp's error messages so that such repairs become errors. The
// assimp logger is process-wide, hence the lock around each import.
class ImportErrorLog : public Assimp::LogStream {
 public:
  ImportErrorLog() {
    Assimp::DefaultLogger::create(nullptr, Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(this, Assimp::Logger::Err);
  }
  ~ImportErrorLog() override {
    Assimp::DefaultLogger::get()->detachStream(this, Assimp::Logger::Err);
    Assimp::DefaultLogger::kill();
  }
  ImportErrorLog(const ImportErrorLog&) = delete;
  ImportErrorLog& operator=(const ImportErrorLog&) = delete;

  void write(const char* message) override {
    if (messages_.size() < 8) messages_.emplace_back(message ? message : "");
  }
  /// The first error that reports a repaired index, or "".
  std::string index_repair() const {
    for (std::string m : messages_)
      if (m.find("out of range") != std::string::npos || m.find("out of bounds") != std::string::npos) {
        while (!m.empty() && (m.back() == '\n' || m.back() == ' ')) m.pop_back();
        if (m.rfind("Error, T", 0) == 0 && m.find(": ") != std::string::npos) m.erase(0, m.find(": ") + 2);
        return m;
      }
    return "";
  }

 private:
  std::vector<std::string> messages_;
};

// Serves one file from memory (an OBJ with its vertices shifted) and every
// other one (its .mtl, textures) from disk.
class ShiftedFileSystem : public Assimp::DefaultIOSystem {
 public:
  ShiftedFileSystem(std::string path, std::string text) : path_(std::move(path)), text_(std::move(text)) {}
  Assimp::IOStream* Open(const char* file, const char* mode) override {
    if (file && (path_ == file || ComparePaths(path_.c_str(), file)))
      return new Assimp::MemoryIOStream(reinterpret_cast<const uint8_t*>(text_.data()), text_.size());
    return Assimp::DefaultIOSystem::Open(file, mode);
  }

 private:
  std::string path_, text_;
};

std::mutex& assimp_import_lock() {
  static std::mutex lock;
  return lock;
}

class AssimpReader {
 public:
  AssimpReader(const aiScene& scene, const std::string& path, const Vec3& shift)
      : scene_(scene), path_(path), shift_(shift) {
    mesh_.source = path;
  }

  Mesh read() {
    add_node(*scene_.mRootNode, aiMatrix4x4{}, 0);
    if (mesh_.triangles.empty())
      fail("no triangles found (" + std::to_string(scene_.mNumMeshes) +
           " meshes); the file is empty, truncated or holds only points and lines");
    if (!any_colour_) mesh_.corner_colours.clear();
    if (!any_uv_) mesh_.corner_uvs.clear();
    finish_materials();
    validate(mesh_);
    return std::move(mesh_);
  }

 private:
  // Triangles of assimp's default material (kNoMaterial) get a white one,
  // unless no triangle has a real material.
  void finish_materials() {
    if (mesh_.materials.empty()) {
      mesh_.triangle_materials.clear();
      return;
    }
    const auto white = static_cast<uint32_t>(mesh_.materials.size());
    bool used = false;
    for (uint32_t& m : mesh_.triangle_materials)
      if (m == kNoMaterial) { m = white; used = true; }
    if (used) mesh_.materials.push_back(Material{});
  }

  [[noreturn]] void fail(const std::string& problem) const { throw Error(path_ + ": " + problem); }

  void add_node(const aiNode& node, const aiMatrix4x4& parent, int depth) {
    if (depth > 1000) fail("the node graph is deeper than 1000 levels");
    const aiMatrix4x4 world = parent * node.mTransformation;
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      if (!node.mMeshes || node.mMeshes[i] >= scene_.mNumMeshes || !scene_.mMeshes[node.mMeshes[i]])
        fail("a node names a missing mesh");
      add_mesh(*scene_.mMeshes[node.mMeshes[i]], world);
    }
    for (unsigned i = 0; i < node.mNumChildren; ++i)
      if (node.mChildren && node.mChildren[i]) add_node(*node.mChildren[i], world, depth + 1);
  }

  void add_mesh(const aiMesh& m, const aiMatrix4x4& world) {
    if (!m.mVertices || m.mNumVertices == 0) return;
    const size_t base = mesh_.positions.size();
    if (base + m.mNumVertices > UINT32_MAX) fail("too many vertices for 32-bit indices");
    for (unsigned i = 0; i < m.mNumVertices; ++i) {
      const aiVector3D& p = m.mVertices[i];
      mesh_.positions.push_back(
          {world.a1 * static_cast<double>(p.x) + world.a2 * static_cast<double>(p.y) + world.a3 * static_cast<double>(p.z) + world.a4,
           world.b1 * static_cast<double>(p.x) + world.b2 * static_cast<double>(p.y) + world.b3 * static_cast<double>(p.z) + world.b4,
           world.c1 * static_cast<double>(p.x) + world.c2 * static_cast<double>(p.y) + world.c3 * static_cast<double>(p.z) + world.c4});
      mesh_.positions.back() += shift_;
    }
    const bool flip = linear_part_determinant(world) < 0;  // mirrored: keep outward orientation
    const bool colours = m.HasVertexColors(0);
    const bool uvs = m.HasTextureCoords(0);
    any_colour_ = any_colour_ || colours;
    any_uv_ = any_uv_ || uvs;
    const int material = material_index(m.mMaterialIndex);
    if (!m.mFaces) return;
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3 || !face.mIndices) continue;  // points and lines left by the triangulation
      unsigned corner[3] = {face.mIndices[0], face.mIndices[flip ? 2 : 1], face.mIndices[flip ? 1 : 2]};
      for (unsigned v : corner)
        if (v >= m.mNumVertices)
          fail("face " + std::to_string(f) + " of mesh '" + m.mName.C_Str() + "' has vertex index " +
               std::to_string(v) + " out of range (" + std::to_string(m.mNumVertices) + " vertices)");
      mesh_.triangles.push_back({static_cast<uint32_t>(base + corner[0]), static_cast<uint32_t>(base + corner[1]),
                                 static_cast<uint32_t>(base + corner[2])});
      for (unsigned v : corner) {
        if (colours) {
          const aiColor4D& c = m.mColors[0][v];
          mesh_.corner_colours.push_back({c.r, c.g, c.b, c.a});
        } else {
          mesh_.corner_colours.push_back({1, 1, 1, 1});
        }
        mesh_.corner_uvs.push_back(uvs ? Uv{m.mTextureCoords[0][v].x, m.mTextureCoords[0][v].y} : Uv{0, 0});
      }
      mesh_.triangle_materials.push_back(material < 0 ? kNoMaterial : static_cast<uint32_t>(material));
    }
  }

  // Our material for an assimp material; -1 for assimp's own default
  // material, which stands for "no material in the file".
  int material_index(unsigned assimp_material) {
    if (assimp_material >= scene_.mNumMaterials || !scene_.mMaterials[assimp_material]) return -1;
    auto found = materials_.find(assimp_material);
    if (found != materials_.end()) return found->second;
    const aiMaterial& am = *scene_.mMaterials[assimp_material];
    int ours = -1;
    if (am.GetName() != aiString(AI_DEFAULT_MATERIAL_NAME)) {
      Material m;
      aiColor4D colour;
      if (am.Get(AI_MATKEY_BASE_COLOR, colour) == AI_SUCCESS || am.Get(AI_MATKEY_COLOR_DIFFUSE, colour) == AI_SUCCESS)
        m.base_colour_factor = {colour.r, colour.g, colour.b, colour.a};
      aiString file;
      aiTextureMapMode modes[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
      for (aiTextureType type : {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE})
        if (am.GetTextureCount(type) > 0 &&
            am.GetTexture(type, 0, &file, nullptr, nullptr, nullptr, nullptr, modes) == AI_SUCCESS) {
          m.texture = load_texture(file.C_Str(), modes);
          break;
        }
      mesh_.materials.push_back(m);
      ours = static_cast<int>(mesh_.materials.size() - 1);
    }
    materials_.emplace(assimp_material, ours);
    return ours;
  }

  int load_texture(const std::string& file, const aiTextureMapMode modes[2]) {
    Texture texture;
    if (const aiTexture* embedded = scene_.GetEmbeddedTexture(file.c_str())) {
      const std::string name = path_ + " embedded texture " + file;
      if (!embedded->pcData) throw Error(name + ": texture has no data");
      if (embedded->mHeight == 0) {  // compressed (PNG, JPEG, ...) of mWidth bytes
        texture = detail::decode_image(reinterpret_cast<const uint8_t*>(embedded->pcData), embedded->mWidth, name);
      } else {  // raw BGRA texels
        texture.width = static_cast<int>(embedded->mWidth);
        texture.height = static_cast<int>(embedded->mHeight);
        texture.name = name;
        const size_t n = static_cast<size_t>(embedded->mWidth) * embedded->mHeight;
        texture.rgba.resize(4 * n);
        for (size_t i = 0; i < n; ++i) {
          const aiTexel& t = embedded->pcData[i];
          texture.rgba[4 * i + 0] = t.r;
          texture.rgba[4 * i + 1] = t.g;
          texture.rgba[4 * i + 2] = t.b;
          texture.rgba[4 * i + 3] = t.a;
        }
      }
    } else {
      std::string relative = file;
      for (char& c : relative) if (c == '\\') c = '/';  // files written on Windows
      const std::string full = !relative.empty() && relative[0] == '/' ? relative : detail::folder_of(path_) + relative;
      try {
        texture = detail::decode_image_file(full);
      } catch (const Error& e) {
        throw Error(path_ + ": its texture cannot be read: " + e.what() +
                    " (put the image next to the mesh or remove the texture from the material)");
      }
    }
    texture.wrap_s = wrap_mode(modes[0]);
    texture.wrap_t = wrap_mode(modes[1]);
    mesh_.textures.push_back(std::move(texture));
    return static_cast<int>(mesh_.textures.size() - 1);
  }

  const aiScene& scene_;
  std::string path_;
  Vec3 shift_;  ///< added back to every position (see ShiftedFileSystem)
  Mesh mesh_;
  bool any_colour_ = false;
  bool any_uv_ = false;
  static constexpr uint32_t kNoMaterial = UINT32_MAX;
  std::map<unsigned, int> materials_;
};

}  // namespace

Mesh load_with_assimp(const std::string& path) {
  detail::require_readable_file(path);
  {  // assimp's PLY reader trusts its input; check PLY files (found by content, as assimp finds them) first
    std::ifstream in(path, std::ios::binary);
    char magic[3] = {};
    // assimp takes "pLy" for PLY too, and its reader spins forever on such
    // a truncated header (the fuzz loop found "pLy\nformat ascii 1.0\ncomment wri").
    const bool ply_magic = in.read(magic, 3) && std::tolower(magic[0]) == 'p' && std::tolower(magic[1]) == 'l' &&
                           std::tolower(magic[2]) == 'y';
    if (ply_magic || detail::lower_extension(path) == ".ply") detail::check_ply_structure(path);
  }
  if (detail::lower_extension(path) == ".off") detail::check_off_indices(path);
  Assimp::Importer importer;
  Vec3 shift;
  if (detail::lower_extension(path) == ".obj") {
    // Far from the origin, single precision would lose the mesh's shape
    // (spot moved by 1e6 lands on a grid of 0.06): assimp reads it moved to
    // the origin, and the shift comes back in double.
    const Box3 box = detail::check_obj_vertices(path);
    if (!box.empty() && length(box.centre()) > 100 * box.diagonal()) {
      shift = box.centre();
      importer.SetIOHandler(new ShiftedFileSystem(path, detail::shift_obj_vertices(path, shift)));
    }
  }
  // Drop points and lines; pfill fills the volume a triangle surface bounds.
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  // No step that reorients or invents geometry: the surface is used as given.
  // No aiProcess_JoinIdenticalVertices: it merges within an absolute
  // epsilon, which collapses distinct vertices of a small mesh; load_mesh
  // welds bit-identical positions instead, whatever the scale.
  const unsigned flags = aiProcess_Triangulate | aiProcess_SortByPType |
                         aiProcess_FlipUVs /* v = 0 at the top, as glTF and pfill::Texture */ |
                         aiProcess_ValidateDataStructure;
  const aiScene* scene = nullptr;
  {
    std::lock_guard<std::mutex> hold(assimp_import_lock());
    ImportErrorLog log;
    scene = importer.ReadFile(path, flags);
    if (const std::string repair = log.index_repair(); !repair.empty())
      throw Error(path + ": index out of range (" + repair + "); repair or re-export the mesh");
  }
  if (!scene) {
    std::string why = importer.GetErrorString();
    for (char& c : why) if (c == '\n') c = ' ';
    why = excerpt(why, 160);  // assimp's messages may quote the rest of the file
    // Files with no faces at all (or only points and lines, which we drop) fail
    // assimp's validation; say it plainly.
    if (why.find("no faces") != std::string::npos || why.find("mNumMeshes is 0") != std::string::npos ||
        why.find("No meshes remaining") != std::string::npos)
      throw Error(path + ": no triangles found (" + why + "); the file is empty, truncated or has no faces");
    throw Error(path + ": cannot be read (" + (why.empty() ? std::string("unknown reason") : why) + ")");
  }
  if (!scene->mRootNode || scene->mNumMeshes == 0 || !scene->mMeshes)
    throw Error(path + ": no triangles found; the file is empty, truncated or holds only points and lines");
  return AssimpReader(*scene, path, shift).read();
}

}  // namespace pfill

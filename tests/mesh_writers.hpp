// Test helpers: write a pfill::Mesh as OBJ, STL (ascii, binary), PLY (ascii,
// binary), OFF, SMF and glTF/GLB, so loader tests need no files; plus a small
// builder of glTF models with hand-made accessors.
#pragma once
#include <tiny_gltf.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "pfill/mesh.hpp"

namespace pfill::test {

/// A fresh, empty folder under the system temp folder, removed on destruction.
class TempDir {
 public:
  explicit TempDir(const std::string& tag) {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("pfill_" + tag + "_" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string file(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

inline std::vector<uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_bytes(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                              static_cast<std::streamsize>(bytes.size()));
}

/// Signed volume from the triangles (divergence theorem); positive when outward.
inline double signed_volume(const Mesh& m) {
  double v = 0;
  for (const Triangle& t : m.triangles)
    v += dot(m.positions[t[0]], cross(m.positions[t[1]], m.positions[t[2]]));
  return v / 6.0;
}

/// The mesh with every coordinate rounded to float, as assimp stores it.
inline Mesh rounded_to_float(Mesh m) {
  for (Vec3& p : m.positions)
    p = {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
  return m;
}

inline std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline void write_obj(const Mesh& m, const std::string& path) {
  std::string s = "# written by the pfill tests\n";
  for (const Vec3& p : m.positions) s += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
  for (const Triangle& t : m.triangles)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  write_text(path, s);
}

inline Vec3 face_normal(const Mesh& m, const Triangle& t) {
  return normalize(cross(m.positions[t[1]] - m.positions[t[0]], m.positions[t[2]] - m.positions[t[0]]));
}

inline void write_stl_ascii(const Mesh& m, const std::string& path) {
  std::string s = "solid pfill\n";
  for (const Triangle& t : m.triangles) {
    const Vec3 n = face_normal(m, t);
    s += "facet normal " + num(n.x) + " " + num(n.y) + " " + num(n.z) + "\n outer loop\n";
    for (uint32_t v : t) {
      const Vec3& p = m.positions[v];
      s += "  vertex " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
    }
    s += " endloop\nendfacet\n";
  }
  write_text(path, s + "endsolid pfill\n");
}

template <typename T>
void append_raw(std::vector<uint8_t>& out, T v) {
  const size_t at = out.size();
  out.resize(at + sizeof v);
  std::memcpy(out.data() + at, &v, sizeof v);
}

inline void write_stl_binary(const Mesh& m, const std::string& path) {
  std::vector<uint8_t> out(80, 0);
  const char header[] = "binary STL written by the pfill tests";
  std::memcpy(out.data(), header, sizeof header - 1);
  append_raw(out, static_cast<uint32_t>(m.triangles.size()));
  for (const Triangle& t : m.triangles) {
    const Vec3 n = face_normal(m, t);
    for (double c : {n.x, n.y, n.z}) append_raw(out, static_cast<float>(c));
    for (uint32_t v : t)
      for (int k = 0; k < 3; ++k) append_raw(out, static_cast<float>(m.positions[v][k]));
    append_raw(out, static_cast<uint16_t>(0));
  }
  write_bytes(path, out);
}

inline std::string ply_header(const Mesh& m, const std::string& format) {
  return "ply\nformat " + format + " 1.0\ncomment written by the pfill tests\nelement vertex " +
         std::to_string(m.positions.size()) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(m.triangles.size()) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

inline void write_ply_ascii(const Mesh& m, const std::string& path) {
  std::string s = ply_header(m, "ascii");
  for (const Vec3& p : m.positions) s += num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
  for (const Triangle& t : m.triangles)
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  write_text(path, s);
}

inline void write_ply_binary(const Mesh& m, const std::string& path) {
  const std::string header = ply_header(m, "binary_little_endian");
  std::vector<uint8_t> out(header.begin(), header.end());
  for (const Vec3& p : m.positions)
    for (int k = 0; k < 3; ++k) append_raw(out, static_cast<float>(p[k]));
  for (const Triangle& t : m.triangles) {
    append_raw(out, static_cast<uint8_t>(3));
    for (uint32_t v : t) append_raw(out, static_cast<int32_t>(v));
  }
  write_bytes(path, out);
}

inline void write_off(const Mesh& m, const std::string& path) {
  std::string s = "OFF\n" + std::to_string(m.positions.size()) + " " + std::to_string(m.triangles.size()) + " 0\n";
  for (const Vec3& p : m.positions) s += num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
  for (const Triangle& t : m.triangles)
    s += "3 " + std::to_string(t[0]) + " " + std::to_string(t[1]) + " " + std::to_string(t[2]) + "\n";
  write_text(path, s);
}

/// SMF; with `vertex_colours` (one per vertex, 0..1) adds `bind c vertex`.
inline void write_smf(const Mesh& m, const std::string& path, const std::vector<Rgba>& vertex_colours = {}) {
  std::string s = "# SMF written by the pfill tests\n";
  if (!vertex_colours.empty()) s += "bind c vertex\n";
  for (const Vec3& p : m.positions) s += "v " + num(p.x) + " " + num(p.y) + " " + num(p.z) + "\n";
  for (const Rgba& c : vertex_colours) s += "c " + num(c[0]) + " " + num(c[1]) + " " + num(c[2]) + "\n";
  for (const Triangle& t : m.triangles)
    s += "f " + std::to_string(t[0] + 1) + " " + std::to_string(t[1] + 1) + " " + std::to_string(t[2] + 1) + "\n";
  write_text(path, s);
}

/// Builds glTF models accessor by accessor into one buffer.
class GltfBuilder {
 public:
  GltfBuilder() {
    model_.asset.version = "2.0";
    model_.buffers.emplace_back();
  }

  /// Appends raw bytes as a buffer view (4-byte aligned); returns its index.
  int add_view(const std::vector<uint8_t>& bytes, size_t stride = 0) {
    std::vector<unsigned char>& data = model_.buffers[0].data;
    while (data.size() % 4) data.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = bytes.size();
    view.byteStride = stride;
    data.insert(data.end(), bytes.begin(), bytes.end());
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size() - 1);
  }

  int add_accessor(int view, size_t offset, int component_type, int type, size_t count, bool normalized = false) {
    tinygltf::Accessor a;
    a.bufferView = view;
    a.byteOffset = offset;
    a.componentType = component_type;
    a.type = type;
    a.count = count;
    a.normalized = normalized;
    model_.accessors.push_back(a);
    return static_cast<int>(model_.accessors.size() - 1);
  }

  /// Tightly packed float VEC3 positions, with the min/max glTF requires.
  int add_positions(const std::vector<Vec3>& points) {
    std::vector<uint8_t> bytes;
    std::vector<double> lo(3, 1e300), hi(3, -1e300);
    for (const Vec3& p : points)
      for (int k = 0; k < 3; ++k) {
        append_raw(bytes, static_cast<float>(p[k]));
        lo[k] = std::min(lo[k], static_cast<double>(static_cast<float>(p[k])));
        hi[k] = std::max(hi[k], static_cast<double>(static_cast<float>(p[k])));
      }
    const int a = add_accessor(add_view(bytes), 0, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, points.size());
    model_.accessors[a].minValues = lo;
    model_.accessors[a].maxValues = hi;
    return a;
  }

  template <typename Index>
  int add_indices(const std::vector<uint32_t>& indices, int component_type) {
    std::vector<uint8_t> bytes;
    for (uint32_t i : indices) append_raw(bytes, static_cast<Index>(i));
    return add_accessor(add_view(bytes), 0, component_type, TINYGLTF_TYPE_SCALAR, indices.size());
  }

  int add_mesh(const std::string& name, std::vector<tinygltf::Primitive> primitives) {
    tinygltf::Mesh m;
    m.name = name;
    m.primitives = std::move(primitives);
    model_.meshes.push_back(m);
    return static_cast<int>(model_.meshes.size() - 1);
  }

  int add_node(tinygltf::Node node) {
    model_.nodes.push_back(std::move(node));
    return static_cast<int>(model_.nodes.size() - 1);
  }

  /// Makes the default scene of the given root nodes.
  void set_scene(std::vector<int> roots) {
    tinygltf::Scene s;
    s.nodes = std::move(roots);
    model_.scenes = {s};
    model_.defaultScene = 0;
  }

  tinygltf::Model& model() { return model_; }

  /// Saves as .gltf (buffers embedded as data URIs) or .glb; false on failure.
  bool save(const std::string& path, bool binary) {
    if (model_.buffers.size() == 1 && model_.buffers[0].data.empty()) model_.buffers.clear();  // no geometry
    tinygltf::TinyGLTF writer;
    return writer.WriteGltfSceneToFile(&model_, path, true, true, !binary, binary);
  }

 private:
  tinygltf::Model model_;
};

inline tinygltf::Primitive triangle_primitive(int positions, int indices = -1, int mode = TINYGLTF_MODE_TRIANGLES) {
  tinygltf::Primitive p;
  p.attributes["POSITION"] = positions;
  p.indices = indices;
  p.mode = mode;
  return p;
}

/// Writes `m` as a one-primitive glTF (uint32 indices) under a node that has
/// no transform.
inline bool write_gltf(const Mesh& m, const std::string& path, bool binary) {
  GltfBuilder b;
  std::vector<uint32_t> indices;
  for (const Triangle& t : m.triangles) indices.insert(indices.end(), t.begin(), t.end());
  const int pos = b.add_positions(m.positions);
  const int idx = b.add_indices<uint32_t>(indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  tinygltf::Node node;
  node.mesh = b.add_mesh("mesh", {triangle_primitive(pos, idx)});
  b.set_scene({b.add_node(node)});
  return b.save(path, binary);
}

}  // namespace pfill::test

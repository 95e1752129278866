// glTF 2.0 reader: tinygltf parses the file; this file walks the scene graph
// and turns every triangle primitive into pfill::Mesh, checking every
// accessor against its buffer on the way (tinygltf does not).
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <map>

#include "mesh/load_support.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/srgb.hpp"

namespace pfill {
namespace {

// Column-major 4x4, as glTF stores node matrices.
struct Mat4 {
  double m[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  double at(int row, int col) const { return m[col * 4 + row]; }
};

Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 4; ++col) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a.at(row, k) * b.at(k, col);
      r.m[col * 4 + row] = s;
    }
  return r;
}

Vec3 transform_point(const Mat4& t, const Vec3& p) {
  return {t.at(0, 0) * p.x + t.at(0, 1) * p.y + t.at(0, 2) * p.z + t.at(0, 3),
          t.at(1, 0) * p.x + t.at(1, 1) * p.y + t.at(1, 2) * p.z + t.at(1, 3),
          t.at(2, 0) * p.x + t.at(2, 1) * p.y + t.at(2, 2) * p.z + t.at(2, 3)};
}

double linear_part_determinant(const Mat4& t) {
  return t.at(0, 0) * (t.at(1, 1) * t.at(2, 2) - t.at(1, 2) * t.at(2, 1)) -
         t.at(0, 1) * (t.at(1, 0) * t.at(2, 2) - t.at(1, 2) * t.at(2, 0)) +
         t.at(0, 2) * (t.at(1, 0) * t.at(2, 1) - t.at(1, 1) * t.at(2, 0));
}

int component_size(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int component_count(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    default: return 0;  // matrices are never vertex attributes we read
  }
}

template <typename T>
T read_unaligned(const uint8_t* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// An accessor checked against its buffer view and buffer: every element it
// names lies inside the buffer.
struct AccessorView {
  const uint8_t* data = nullptr;  // first element
  size_t stride = 0;
  size_t count = 0;
  int components = 0;
  int component_type = 0;
  bool normalized = false;

  // Component c of element i as a number; normalized integers map to [0, 1]
  // or [-1, 1] as the glTF spec says.
  double value(size_t i, int c) const {
    const uint8_t* p = data + i * stride + static_cast<size_t>(c) * component_size(component_type);
    switch (component_type) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: return read_unaligned<float>(p);
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *p / 255.0 : *p;
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        const double v = static_cast<int8_t>(*p);
        return normalized ? std::fmax(v / 127.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        const double v = read_unaligned<uint16_t>(p);
        return normalized ? v / 65535.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        const double v = read_unaligned<int16_t>(p);
        return normalized ? std::fmax(v / 32767.0, -1.0) : v;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        const double v = read_unaligned<uint32_t>(p);
        return normalized ? v / 4294967295.0 : v;
      }
      case TINYGLTF_COMPONENT_TYPE_INT: return read_unaligned<int32_t>(p);
      default: return 0;
    }
  }

  uint32_t index(size_t i) const {
    const uint8_t* p = data + i * stride;
    switch (component_type) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return read_unaligned<uint16_t>(p);
      default: return read_unaligned<uint32_t>(p);
    }
  }
};

class GltfReader {
 public:
  GltfReader(const tinygltf::Model& model, const std::string& path) : model_(model), path_(path) {
    mesh_.source = path;
  }

  Mesh read() {
    check_required_extensions();
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const int scene = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (scene >= static_cast<int>(model_.scenes.size()))
        fail("default scene " + std::to_string(scene) + " does not exist");
      roots = model_.scenes[scene].nodes;
    } else {
      // No scene: every node that is nobody's child is a root.
      std::vector<bool> is_child(model_.nodes.size(), false);
      for (const tinygltf::Node& n : model_.nodes)
        for (int c : n.children)
          if (c >= 0 && c < static_cast<int>(is_child.size())) is_child[c] = true;
      for (size_t i = 0; i < model_.nodes.size(); ++i)
        if (!is_child[i]) roots.push_back(static_cast<int>(i));
    }
    for (int node : roots) add_node(node, Mat4{}, 0);

    if (mesh_.triangles.empty())
      fail("the scene has no triangles (" + std::to_string(model_.meshes.size()) + " meshes, " +
           std::to_string(model_.nodes.size()) + " nodes); pfill needs a triangle surface");
    if (!any_colour_) mesh_.corner_colours.clear();
    if (!any_uv_) mesh_.corner_uvs.clear();
    validate(mesh_);
    return std::move(mesh_);
  }

 private:
  [[noreturn]] void fail(const std::string& problem) const { throw Error(path_ + ": " + problem); }

  void check_required_extensions() const {
    for (const std::string& e : model_.extensionsRequired)
      if (e == "KHR_draco_mesh_compression" || e == "EXT_meshopt_compression" || e == "KHR_texture_basisu" ||
          e == "EXT_texture_webp")
        fail("needs the glTF extension " + e + ", which pfill does not read; re-export without compression");
  }

  void add_node(int index, const Mat4& parent, int depth) {
    if (index < 0 || index >= static_cast<int>(model_.nodes.size()))
      fail("node index " + std::to_string(index) + " out of range (" + std::to_string(model_.nodes.size()) +
           " nodes)");
    // A valid node graph is a forest, so its depth is at most the node count.
    if (depth > static_cast<int>(model_.nodes.size())) fail("the node graph has a cycle");
    const tinygltf::Node& node = model_.nodes[index];
    const Mat4 world = parent * local_transform(node, index);
    if (node.mesh >= 0) add_mesh(node.mesh, world);
    for (int child : node.children) add_node(child, world, depth + 1);
  }

  Mat4 local_transform(const tinygltf::Node& node, int index) const {
    Mat4 t;
    const std::string where = "node " + std::to_string(index);
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) fail(where + " has a matrix of " + std::to_string(node.matrix.size()) + " numbers, not 16");
      for (int i = 0; i < 16; ++i) t.m[i] = node.matrix[i];
      return t;
    }
    // T * R * S
    Mat4 translation, rotation, scale;
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) fail(where + " has a translation that is not 3 numbers");
      for (int i = 0; i < 3; ++i) translation.m[12 + i] = node.translation[i];
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) fail(where + " has a rotation that is not a quaternion");
      double x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
      const double norm = std::sqrt(x * x + y * y + z * z + w * w);
      if (!(norm > 0) || !std::isfinite(norm)) fail(where + " has a zero or non-finite rotation quaternion");
      x /= norm; y /= norm; z /= norm; w /= norm;
      const double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - z * w),     2 * (x * z + y * w),
                           2 * (x * y + z * w),     1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
                           2 * (x * z - y * w),     2 * (y * z + x * w),     1 - 2 * (x * x + y * y)};
      for (int row = 0; row < 3; ++row)
        for (int col = 0; col < 3; ++col) rotation.m[col * 4 + row] = r[row * 3 + col];
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) fail(where + " has a scale that is not 3 numbers");
      for (int i = 0; i < 3; ++i) scale.m[i * 5] = node.scale[i];
    }
    return translation * rotation * scale;
  }

  AccessorView accessor(int index, const std::string& what) const {
    if (index < 0 || index >= static_cast<int>(model_.accessors.size()))
      fail(what + ": accessor " + std::to_string(index) + " out of range");
    const tinygltf::Accessor& a = model_.accessors[index];
    const std::string where = what + " (accessor " + std::to_string(index) + ")";
    if (a.sparse.isSparse) fail(where + " is a sparse accessor, which pfill does not read; re-export without sparse data");
    if (a.bufferView < 0 || a.bufferView >= static_cast<int>(model_.bufferViews.size()))
      fail(where + " has no valid buffer view");
    const tinygltf::BufferView& view = model_.bufferViews[a.bufferView];
    if (view.buffer < 0 || view.buffer >= static_cast<int>(model_.buffers.size()))
      fail(where + ": buffer view " + std::to_string(a.bufferView) + " names a missing buffer");
    const tinygltf::Buffer& buffer = model_.buffers[view.buffer];
    if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
      fail(where + ": buffer view " + std::to_string(a.bufferView) + " runs past the end of its buffer (" +
           std::to_string(buffer.data.size()) + " bytes); the file is truncated or corrupt");

    AccessorView v;
    v.components = component_count(a.type);
    v.component_type = a.componentType;
    v.normalized = a.normalized;
    const int size = component_size(a.componentType);
    if (v.components == 0 || size == 0) fail(where + " has an unsupported type or component type");
    const size_t element = static_cast<size_t>(size) * v.components;
    v.stride = view.byteStride == 0 ? element : view.byteStride;
    if (v.stride < element) fail(where + ": byte stride " + std::to_string(v.stride) + " is smaller than an element");
    v.count = a.count;
    // Bounds: offset + (count - 1) * stride + element <= view length, without overflow.
    if (a.byteOffset > view.byteLength) fail(where + ": byte offset lies past the end of its buffer view");
    const size_t room = view.byteLength - a.byteOffset;
    if (v.count > 0 && (room < element || (v.count - 1) > (room - element) / v.stride))
      fail(where + ": " + std::to_string(v.count) + " elements run past the end of buffer view " +
           std::to_string(a.bufferView) + "; the file is truncated or corrupt");
    v.data = buffer.data.data() + view.byteOffset + a.byteOffset;
    return v;
  }

  void add_mesh(int index, const Mat4& world) {
    if (index < 0 || index >= static_cast<int>(model_.meshes.size()))
      fail("mesh index " + std::to_string(index) + " out of range (" + std::to_string(model_.meshes.size()) +
           " meshes)");
    const tinygltf::Mesh& m = model_.meshes[index];
    for (size_t p = 0; p < m.primitives.size(); ++p)
      add_primitive(m.primitives[p], "primitive " + std::to_string(p) + " of mesh '" +
                                         (m.name.empty() ? std::to_string(index) : m.name) + "'",
                    world);
  }

  void add_primitive(const tinygltf::Primitive& prim, const std::string& where, const Mat4& world) {
    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP && mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      static const char* names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP"};
      fail(where + " is " + (mode <= 3 ? names[mode] : "mode " + std::to_string(mode)) + "; pfill needs triangles");
    }

    const auto position_it = prim.attributes.find("POSITION");
    if (position_it == prim.attributes.end()) fail(where + " has no POSITION attribute");
    const AccessorView positions = accessor(position_it->second, where + " POSITION");
    if (positions.components != 3) fail(where + " POSITION is not VEC3");

    // The vertex order of the primitive, before assembling triangles.
    std::vector<uint32_t> order;
    if (prim.indices >= 0) {
      const AccessorView indices = accessor(prim.indices, where + " indices");
      if (indices.components != 1 || (indices.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
                                      indices.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                      indices.component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        fail(where + " indices are not unsigned byte, short or int scalars");
      order.resize(indices.count);
      for (size_t i = 0; i < indices.count; ++i) {
        order[i] = indices.index(i);
        if (order[i] >= positions.count)
          fail(where + ": index " + std::to_string(order[i]) + " out of range (" + std::to_string(positions.count) +
               " vertices)");
      }
    } else {
      if (positions.count > UINT32_MAX) fail(where + " has too many vertices");
      order.resize(positions.count);
      for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<uint32_t>(i);
    }

    std::vector<std::array<uint32_t, 3>> local;  // triangles in primitive vertex numbers
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (order.size() % 3 != 0)
        fail(where + " has " + std::to_string(order.size()) + " vertex references, not a multiple of 3");
      for (size_t i = 0; i + 2 < order.size(); i += 3) local.push_back({order[i], order[i + 1], order[i + 2]});
    } else {
      for (size_t i = 0; i + 2 < order.size(); ++i) {
        std::array<uint32_t, 3> t = mode == TINYGLTF_MODE_TRIANGLE_FAN ? std::array<uint32_t, 3>{order[i + 1], order[i + 2], order[0]}
                                    : i % 2 == 0 ? std::array<uint32_t, 3>{order[i], order[i + 1], order[i + 2]}
                                                 : std::array<uint32_t, 3>{order[i + 1], order[i], order[i + 2]};
        // Strips join pieces with repeated vertices; those triangles are not surface.
        if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2]) local.push_back(t);
      }
    }

    // Vertices: appended transformed; the weld in load_mesh joins primitives.
    const size_t base = mesh_.positions.size();
    if (base + positions.count > UINT32_MAX) fail("too many vertices for 32-bit indices");
    for (size_t i = 0; i < positions.count; ++i)
      mesh_.positions.push_back(
          transform_point(world, {positions.value(i, 0), positions.value(i, 1), positions.value(i, 2)}));

    const bool flip = linear_part_determinant(world) < 0;  // mirrored: keep outward orientation
    for (auto t : local) {
      if (flip) std::swap(t[1], t[2]);
      mesh_.triangles.push_back({static_cast<uint32_t>(base + t[0]), static_cast<uint32_t>(base + t[1]),
                                 static_cast<uint32_t>(base + t[2])});
    }

    add_colours(prim, where, positions.count, local, flip);
    const int material = material_index(prim.material, where);
    add_uvs(prim, where, positions.count, local, flip, material);
    if (material >= 0) mesh_.triangle_materials.insert(mesh_.triangle_materials.end(), local.size(), material);
  }

  // Corner k of each triangle, honouring the flip.
  template <typename F>
  void for_each_corner(const std::vector<std::array<uint32_t, 3>>& local, bool flip, F&& f) {
    for (const auto& t : local) {
      f(t[0]);
      f(flip ? t[2] : t[1]);
      f(flip ? t[1] : t[2]);
    }
  }

  void add_colours(const tinygltf::Primitive& prim, const std::string& where, size_t vertex_count,
                   const std::vector<std::array<uint32_t, 3>>& local, bool flip) {
    // Corners before this primitive without colours are white.
    mesh_.corner_colours.resize(3 * (mesh_.triangles.size() - local.size()), Rgba{1, 1, 1, 1});
    const auto it = prim.attributes.find("COLOR_0");
    if (it == prim.attributes.end()) {
      mesh_.corner_colours.resize(3 * mesh_.triangles.size(), Rgba{1, 1, 1, 1});
      return;
    }
    const AccessorView c = accessor(it->second, where + " COLOR_0");
    if (c.components != 3 && c.components != 4) fail(where + " COLOR_0 is not VEC3 or VEC4");
    if (c.count < vertex_count) fail(where + " COLOR_0 has fewer elements than POSITION");
    any_colour_ = true;
    for_each_corner(local, flip, [&](uint32_t v) {
      mesh_.corner_colours.push_back({linear_to_srgb(static_cast<float>(c.value(v, 0))),
                                      linear_to_srgb(static_cast<float>(c.value(v, 1))),
                                      linear_to_srgb(static_cast<float>(c.value(v, 2))),
                                      c.components == 4 ? static_cast<float>(c.value(v, 3)) : 1.0f});
    });
  }

  void add_uvs(const tinygltf::Primitive& prim, const std::string& where, size_t vertex_count,
               const std::vector<std::array<uint32_t, 3>>& local, bool flip, int material) {
    mesh_.corner_uvs.resize(3 * (mesh_.triangles.size() - local.size()), Uv{0, 0});
    // Read the UV set the base colour texture uses (TEXCOORD_0 unless it says otherwise).
    int set = 0;
    if (prim.material >= 0 && material >= 0)
      set = std::max(0, model_.materials[prim.material].pbrMetallicRoughness.baseColorTexture.texCoord);
    const std::string name = "TEXCOORD_" + std::to_string(set);
    const auto it = prim.attributes.find(name);
    if (it == prim.attributes.end()) {
      mesh_.corner_uvs.resize(3 * mesh_.triangles.size(), Uv{0, 0});
      return;
    }
    const AccessorView uv = accessor(it->second, where + " " + name);
    if (uv.components != 2) fail(where + " " + name + " is not VEC2");
    if (uv.count < vertex_count) fail(where + " " + name + " has fewer elements than POSITION");
    any_uv_ = true;
    for_each_corner(local, flip, [&](uint32_t v) {
      mesh_.corner_uvs.push_back({static_cast<float>(uv.value(v, 0)), static_cast<float>(uv.value(v, 1))});
    });
  }

  // Our material index for a glTF material index; -1 when the file has no
  // materials at all, so meshes without any keep triangle_materials empty.
  int material_index(int gltf_material, const std::string& where) {
    if (model_.materials.empty()) return -1;
    if (gltf_material >= static_cast<int>(model_.materials.size()))
      fail(where + " uses material " + std::to_string(gltf_material) + " of " +
           std::to_string(model_.materials.size()));
    auto found = materials_.find(gltf_material);
    if (found != materials_.end()) return found->second;
    // A primitive without a material (-1) gets the default: white, no texture.
    Material m;
    if (gltf_material >= 0) {
      const tinygltf::PbrMetallicRoughness& pbr = model_.materials[gltf_material].pbrMetallicRoughness;
      if (pbr.baseColorFactor.size() == 4)
        for (int i = 0; i < 4; ++i) m.base_colour_factor[i] = static_cast<float>(pbr.baseColorFactor[i]);
      if (pbr.baseColorTexture.index >= 0) m.texture = texture_index(pbr.baseColorTexture.index);
    }
    mesh_.materials.push_back(m);
    const int ours = static_cast<int>(mesh_.materials.size() - 1);
    materials_.emplace(gltf_material, ours);
    return ours;
  }

  int texture_index(int gltf_texture) {
    auto found = textures_.find(gltf_texture);
    if (found != textures_.end()) return found->second;
    const std::string where = "texture " + std::to_string(gltf_texture);
    if (gltf_texture >= static_cast<int>(model_.textures.size())) fail(where + " does not exist");
    const tinygltf::Texture& t = model_.textures[gltf_texture];
    if (t.source < 0 || t.source >= static_cast<int>(model_.images.size()))
      fail(where + " has no image pfill can read (only PNG/JPEG sources are supported)");
    const tinygltf::Image& image = model_.images[t.source];
    const std::string name = path_ + " image " + std::to_string(t.source) + (image.uri.empty() ? "" : " (" + image.uri + ")");
    const size_t bytes_per = image.bits == 16 ? 2 : 1;
    if (image.width <= 0 || image.height <= 0 || image.component < 1 || image.component > 4 ||
        (image.bits != 8 && image.bits != 16) ||
        image.image.size() != static_cast<size_t>(image.width) * image.height * image.component * bytes_per)
      throw Error(name + ": texture image could not be decoded; check that the image is present and is PNG or JPEG");

    Texture texture;
    texture.width = image.width;
    texture.height = image.height;
    texture.name = name;
    const size_t pixels = static_cast<size_t>(image.width) * image.height;
    texture.rgba.resize(pixels * 4);
    for (size_t p = 0; p < pixels; ++p) {
      uint8_t c[4] = {0, 0, 0, 255};
      for (int k = 0; k < image.component; ++k)
        c[k] = image.image[(p * image.component + k) * bytes_per + (bytes_per - 1)];  // high byte of 16-bit
      if (image.component <= 2) {  // grey (+ alpha)
        c[3] = image.component == 2 ? c[1] : 255;
        c[1] = c[2] = c[0];
      }
      std::memcpy(&texture.rgba[p * 4], c, 4);
    }
    if (t.sampler >= 0) {
      if (t.sampler >= static_cast<int>(model_.samplers.size())) fail(where + " uses a missing sampler");
      auto wrap = [](int mode) {
        return mode == TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE     ? WrapMode::ClampToEdge
               : mode == TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT ? WrapMode::MirroredRepeat
                                                               : WrapMode::Repeat;
      };
      texture.wrap_s = wrap(model_.samplers[t.sampler].wrapS);
      texture.wrap_t = wrap(model_.samplers[t.sampler].wrapT);
    }
    mesh_.textures.push_back(std::move(texture));
    const int ours = static_cast<int>(mesh_.textures.size() - 1);
    textures_.emplace(gltf_texture, ours);
    return ours;
  }

  const tinygltf::Model& model_;
  std::string path_;
  Mesh mesh_;
  bool any_colour_ = false;
  bool any_uv_ = false;
  std::map<int, int> materials_;  // glTF material (-1: none) -> ours
  std::map<int, int> textures_;   // glTF texture -> ours
};

}  // namespace

Mesh load_gltf(const std::string& path) {
  const std::vector<uint8_t> bytes = detail::read_file_bytes(path);
  if (bytes.size() > UINT32_MAX) throw Error(path + ": file larger than 4 GiB; glTF files cannot be that large");
  tinygltf::TinyGLTF parser;
  tinygltf::Model model;
  std::string error, warning;
  const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
  const std::string base_dir = detail::folder_of(path);
  const bool ok =
      binary ? parser.LoadBinaryFromMemory(&model, &error, &warning, bytes.data(), static_cast<unsigned>(bytes.size()),
                                           base_dir)
             : parser.LoadASCIIFromString(&model, &error, &warning, reinterpret_cast<const char*>(bytes.data()),
                                          static_cast<unsigned>(bytes.size()), base_dir);
  if (!ok) {
    std::string why = error.empty() ? warning : error;
    while (!why.empty() && (why.back() == '\n' || why.back() == ' ')) why.pop_back();
    for (char& c : why) if (c == '\n') c = ';';
    throw Error(path + ": not a valid glTF " + (binary ? "binary (GLB)" : "JSON") + " file: " +
                (why.empty() ? "tinygltf gave no reason" : excerpt(why, 160)));
  }
  return GltfReader(model, path).read();
}

}  // namespace pfill

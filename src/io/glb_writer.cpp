// glTF binary writer through tinygltf: particles as a POINTS primitive with
// the radius as a custom attribute, optionally as instanced spheres
// (EXT_mesh_gpu_instancing). tinygltf stays inside this file.
#include <tiny_gltf.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "pfill/atomic_file.hpp"
#include "pfill/error.hpp"
#include "pfill/particle_io.hpp"
#include "pfill/shapes.hpp"
#include "pfill/srgb.hpp"

namespace pfill {
namespace {

constexpr int kArrayBuffer = 34962;         // bufferView target: vertex data
constexpr int kElementArrayBuffer = 34963;  // bufferView target: indices

// Builds the single buffer and its views/accessors.
class GltfBuilder {
 public:
  explicit GltfBuilder(tinygltf::Model& model) : model_(model) {
    model_.buffers.emplace_back();
  }

  // Adds tightly packed float tuples (components per element) as a view and
  // an accessor; returns the accessor index. min/max are set when asked
  // (POSITION requires them), from the stored float values.
  int add_floats(const std::vector<float>& values, int components, int target, bool with_bounds) {
    const int view = add_view(values.data(), values.size() * sizeof(float), target);
    tinygltf::Accessor accessor;
    accessor.bufferView = view;
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    accessor.count = values.size() / components;
    accessor.type = components == 1 ? TINYGLTF_TYPE_SCALAR
                  : components == 3 ? TINYGLTF_TYPE_VEC3 : TINYGLTF_TYPE_VEC4;
    if (with_bounds && accessor.count > 0) {
      accessor.minValues.assign(components, std::numeric_limits<double>::infinity());
      accessor.maxValues.assign(components, -std::numeric_limits<double>::infinity());
      for (size_t i = 0; i < values.size(); ++i) {
        const int c = static_cast<int>(i % components);
        accessor.minValues[c] = std::min(accessor.minValues[c], double(values[i]));
        accessor.maxValues[c] = std::max(accessor.maxValues[c], double(values[i]));
      }
    }
    model_.accessors.push_back(std::move(accessor));
    return static_cast<int>(model_.accessors.size() - 1);
  }

  int add_indices(const std::vector<uint32_t>& indices) {
    const int view = add_view(indices.data(), indices.size() * sizeof(uint32_t), kElementArrayBuffer);
    tinygltf::Accessor accessor;
    accessor.bufferView = view;
    accessor.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.count = indices.size();
    accessor.type = TINYGLTF_TYPE_SCALAR;
    model_.accessors.push_back(std::move(accessor));
    return static_cast<int>(model_.accessors.size() - 1);
  }

 private:
  // target 0: no target (instance attributes are not vertex data).
  int add_view(const void* data, size_t bytes, int target) {
    std::vector<unsigned char>& buffer = model_.buffers[0].data;
    while (buffer.size() % 4) buffer.push_back(0);  // 4-byte alignment of every view
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = buffer.size();
    view.byteLength = bytes;
    view.target = target;
    const auto* bytes_in = static_cast<const unsigned char*>(data);
    buffer.insert(buffer.end(), bytes_in, bytes_in + bytes);
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size() - 1);
  }

  tinygltf::Model& model_;
};

void add_sphere_instances(tinygltf::Model& model, GltfBuilder& builder, const ParticleSet& particles,
                          const std::vector<float>& positions, const std::vector<float>& colours,
                          int subdivisions) {
  double mean_radius = 0;
  for (double r : particles.radii) mean_radius += r;
  mean_radius /= static_cast<double>(particles.size());

  // The base sphere has the mean radius, so viewers without the extension
  // show one particle-sized sphere, not a unit ball.
  const Mesh sphere = make_icosphere(1.0, subdivisions);
  std::vector<float> vertices, normals;
  for (const Vec3& p : sphere.positions) {
    const Vec3 n = normalize(p);
    for (int k = 0; k < 3; ++k) {
      vertices.push_back(static_cast<float>(n[k] * mean_radius));
      normals.push_back(static_cast<float>(n[k]));
    }
  }
  std::vector<uint32_t> indices;
  for (const Triangle& t : sphere.triangles) indices.insert(indices.end(), t.begin(), t.end());

  tinygltf::Material material;
  material.name = "particle";
  material.pbrMetallicRoughness.baseColorFactor = {0.8, 0.8, 0.8, 1.0};
  if (!colours.empty()) material.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.6;
  model.materials.push_back(material);

  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.attributes["POSITION"] = builder.add_floats(vertices, 3, kArrayBuffer, true);
  primitive.attributes["NORMAL"] = builder.add_floats(normals, 3, kArrayBuffer, false);
  primitive.indices = builder.add_indices(indices);
  primitive.material = static_cast<int>(model.materials.size() - 1);
  tinygltf::Mesh mesh;
  mesh.name = "particle sphere";
  mesh.primitives.push_back(primitive);
  model.meshes.push_back(mesh);

  std::vector<float> scales;
  scales.reserve(particles.size() * 3);
  for (double r : particles.radii) {
    const float s = static_cast<float>(r / mean_radius);
    scales.insert(scales.end(), {s, s, s});
  }
  tinygltf::Value::Object attributes;
  attributes["TRANSLATION"] = tinygltf::Value(builder.add_floats(positions, 3, 0, false));
  attributes["SCALE"] = tinygltf::Value(builder.add_floats(scales, 3, 0, false));
  if (!colours.empty())  // three.js reads per-instance colours from _COLOR_0
    attributes["_COLOR_0"] = tinygltf::Value(builder.add_floats(colours, 3, 0, false));
  tinygltf::Value::Object extension;
  extension["attributes"] = tinygltf::Value(std::move(attributes));

  tinygltf::Node node;
  node.name = "particle spheres";
  node.mesh = static_cast<int>(model.meshes.size() - 1);
  node.extensions["EXT_mesh_gpu_instancing"] = tinygltf::Value(std::move(extension));
  model.nodes.push_back(node);
  model.scenes[0].nodes.push_back(static_cast<int>(model.nodes.size() - 1));
  // Used, not required: viewers without it still open the file.
  model.extensionsUsed.push_back("EXT_mesh_gpu_instancing");
}

}  // namespace

void write_glb(const ParticleSet& particles, const std::filesystem::path& path,
               const ParticleWriteOptions& options) {
  validate(particles, path.string());
  if (options.spheres && (options.sphere_subdivisions < 0 || options.sphere_subdivisions > 4))
    throw Error("cannot write '" + path.string() + "': sphere subdivisions must be 0..4, not " +
                std::to_string(options.sphere_subdivisions));

  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "pfill";
  model.scenes.emplace_back();
  model.scenes[0].name = "pfill particles";  // also keeps an empty scene an object, not null
  model.defaultScene = 0;
  GltfBuilder builder(model);

  std::vector<float> positions, radii, colours, ids, velocities;
  positions.reserve(particles.size() * 3);
  // POSITION is float32: far from the origin the points are stored about
  // their box's centre and the nodes carry it as their translation (doubles
  // in the JSON), which every glTF reader applies.
  const Vec3 origin = positions_need_doubles(particles) ? particles.bounds().centre() : Vec3{};
  for (const Vec3& p : particles.positions)
    positions.insert(positions.end(), {float(p.x - origin.x), float(p.y - origin.y), float(p.z - origin.z)});
  radii.assign(particles.radii.begin(), particles.radii.end());
  for (size_t i = 0; i < particles.size(); ++i) ids.push_back(static_cast<float>(particles.id(i)));
  if (options.velocities)
    for (const Vec3& v : particles.velocities) velocities.insert(velocities.end(), {float(v.x), float(v.y), float(v.z)});
  for (const Rgb8& c : particles.colours)
    colours.insert(colours.end(), {srgb8_to_linear(c[0]), srgb8_to_linear(c[1]), srgb8_to_linear(c[2])});

  // An empty set still gives a valid file: a scene with no nodes.
  if (!particles.empty()) {
    tinygltf::Primitive points;
    points.mode = TINYGLTF_MODE_POINTS;
    points.attributes["POSITION"] = builder.add_floats(positions, 3, kArrayBuffer, true);
    if (!colours.empty()) points.attributes["COLOR_0"] = builder.add_floats(colours, 3, kArrayBuffer, false);
    points.attributes["_RADIUS"] = builder.add_floats(radii, 1, kArrayBuffer, false);
    points.attributes["_ID"] = builder.add_floats(ids, 1, kArrayBuffer, false);
    if (!velocities.empty()) points.attributes["_VELOCITY"] = builder.add_floats(velocities, 3, kArrayBuffer, false);
    if (options.contacts) {  // each particle's contact count (contacts.hpp), as _COORDINATION
      validate(*options.contacts, particles.size(), path.string());
      const std::vector<float> coordination(options.contacts->coordination.begin(), options.contacts->coordination.end());
      points.attributes["_COORDINATION"] = builder.add_floats(coordination, 1, kArrayBuffer, false);
    }
    if (const ParticleAttributes* a = options.attributes) {  // boundary particles: _KIND, _NORMAL, _AREA
      validate(*a, particles.size(), path.string());
      if (a->has_kinds())
        points.attributes["_KIND"] = builder.add_floats(std::vector<float>(a->kinds.begin(), a->kinds.end()), 1, kArrayBuffer, false);
      if (a->has_normals()) {
        std::vector<float> normals;
        for (const Vec3& v : a->normals) normals.insert(normals.end(), {float(v.x), float(v.y), float(v.z)});
        points.attributes["_NORMAL"] = builder.add_floats(normals, 3, kArrayBuffer, false);
      }
      if (a->has_areas())
        points.attributes["_AREA"] = builder.add_floats(std::vector<float>(a->areas.begin(), a->areas.end()), 1, kArrayBuffer, false);
    }
    tinygltf::Mesh mesh;
    mesh.name = "particles";
    mesh.primitives.push_back(points);
    model.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = "particles";
    node.mesh = 0;
    if (origin.x != 0 || origin.y != 0 || origin.z != 0) node.translation = {origin.x, origin.y, origin.z};
    model.nodes.push_back(node);
    model.scenes[0].nodes.push_back(0);
    if (options.spheres) {
      add_sphere_instances(model, builder, particles, positions, colours, options.sphere_subdivisions);
      model.nodes.back().translation = model.nodes[0].translation;
    }
  }
  model.buffers[0].data.resize((model.buffers[0].data.size() + 3) / 4 * 4, 0);
  if (model.buffers[0].data.empty()) model.buffers.clear();  // a buffer must not be empty

  std::ostringstream stream;
  tinygltf::TinyGLTF gltf;
  if (!gltf.WriteGltfSceneToStream(&model, stream, false, true))
    throw Error("cannot write '" + path.string() + "': tinygltf failed to serialise the model");
  const std::string bytes = stream.str();
  write_file_atomically(path, [&](AtomicFile& file) { file.write(bytes); });
}

}  // namespace pfill

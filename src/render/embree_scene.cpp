// Embree owners for the renderer: errors go through the device's error
// callback into pfill::Error.
#include "render/embree_scene.hpp"

#include <cstring>

#include "pfill/error.hpp"

namespace pfill {
namespace {

void record_error(void* user, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(user);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}

}  // namespace

EmbreeDevice::EmbreeDevice() {
  device_ = rtcNewDevice(nullptr);
  if (!device_)
    throw Error("cannot start Embree (rtcNewDevice failed: error " +
                std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(device_, record_error, &last_error_);
}

EmbreeDevice::~EmbreeDevice() { rtcReleaseDevice(device_); }

void EmbreeDevice::check(const char* what) const {
  const RTCError code = rtcGetDeviceError(device_);
  if (code != RTC_ERROR_NONE || !last_error_.empty()) {
    const std::string message = last_error_.empty() ? "Embree error " + std::to_string(int(code)) : last_error_;
    last_error_.clear();
    throw Error(std::string("renderer: ") + what + " failed: " + message);
  }
}

EmbreeScene::EmbreeScene(const EmbreeDevice& device) : device_(device) {
  scene_ = rtcNewScene(device_.get());
  device_.check("creating a scene");
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
}

EmbreeScene::~EmbreeScene() { rtcReleaseScene(scene_); }

void EmbreeScene::add_spheres(const std::vector<std::array<float, 4>>& spheres) {
  if (spheres.empty()) return;
  RTCGeometry geometry = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, 4 * sizeof(float), spheres.size()));
  if (!vertices) {
    rtcReleaseGeometry(geometry);
    device_.check("allocating the sphere buffer");
    throw Error("renderer: Embree could not allocate " + std::to_string(spheres.size()) + " spheres");
  }
  std::memcpy(vertices, spheres.data(), spheres.size() * 4 * sizeof(float));
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
  ++geometries_;
  device_.check("adding spheres");
}

void EmbreeScene::add_triangles(const Mesh& mesh) {
  if (mesh.triangles.empty()) return;
  RTCGeometry geometry = rtcNewGeometry(device_.get(), RTC_GEOMETRY_TYPE_TRIANGLE);
  // Embree may read 16 bytes from the last vertex: one spare vertex of padding.
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size() + 1));
  auto* indices = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), mesh.triangles.size()));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    device_.check("allocating the mesh buffers");
    throw Error("renderer: Embree could not allocate the mesh '" + mesh.source + "'");
  }
  for (size_t i = 0; i < mesh.positions.size(); ++i)
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.positions[i][k]);
  for (int k = 0; k < 3; ++k) vertices[3 * mesh.positions.size() + k] = 0.0f;
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const uint32_t v = mesh.triangles[t][k];
      if (v >= mesh.positions.size()) {
        rtcReleaseGeometry(geometry);
        throw Error("renderer: mesh '" + mesh.source + "' has a vertex index out of range in triangle " +
                    std::to_string(t));
      }
      indices[3 * t + k] = v;
    }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(scene_, geometry);
  rtcReleaseGeometry(geometry);
  ++geometries_;
  device_.check("adding the mesh");
}

void EmbreeScene::commit() {
  rtcCommitScene(scene_);
  device_.check("building the scene");
}

}  // namespace pfill

// Embree behind two small owners for the renderer: a device whose errors
// become pfill::Error, and a scene of spheres or triangles. Private to
// src/render.
#pragma once
#include <embree3/rtcore.h>

#include <array>
#include <string>
#include <vector>

#include "pfill/mesh.hpp"

namespace pfill {

class EmbreeDevice {
 public:
  EmbreeDevice();
  ~EmbreeDevice();
  EmbreeDevice(const EmbreeDevice&) = delete;
  EmbreeDevice& operator=(const EmbreeDevice&) = delete;

  RTCDevice get() const { return device_; }
  /// Throws pfill::Error with Embree's message if an Embree call failed.
  void check(const char* what) const;

 private:
  RTCDevice device_ = nullptr;
  mutable std::string last_error_;
};

/// One committed Embree scene; geometry ids are in order of addition.
class EmbreeScene {
 public:
  explicit EmbreeScene(const EmbreeDevice& device);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  /// Spheres as (x, y, z, radius), one primitive per entry.
  void add_spheres(const std::vector<std::array<float, 4>>& spheres);
  /// The mesh's triangles (all of them).
  void add_triangles(const Mesh& mesh);
  void commit();
  bool empty() const { return geometries_ == 0; }

  RTCScene get() const { return scene_; }

 private:
  const EmbreeDevice& device_;
  RTCScene scene_ = nullptr;
  int geometries_ = 0;
};

}  // namespace pfill

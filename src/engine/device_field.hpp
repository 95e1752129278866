// The wall's signed distance field on the device (kernels/field.cl): a
// float buffer, or with EngineParams::field_image a CL_R / CL_FLOAT 3D
// image; its origin (with 1 / spacing) and dims (with whether there are walls).
#pragma once
#include <CL/opencl.hpp>

#include "pfill/device/device.hpp"
#include "pfill/grid.hpp"

namespace pfill {

class DeviceField {
 public:
  /// No walls yet (a 2x2x2 placeholder, dims.w = 0).
  DeviceField(Device& device, bool as_image);
  /// Checks and uploads `field` (walls on). `borrow`: on CPU devices the
  /// buffer uses `field`'s values in place (Engine::share_field).
  void set(const ScalarGrid& field, bool borrow = false);

  bool as_image() const { return as_image_; }
  const cl::Buffer& buffer() const { return buffer_; }
  const cl::Image3D& image() const { return image_; }
  cl_float4 origin{};  // (origin, 1 / spacing)
  cl_int4 dims{};      // (nx, ny, nz, has walls)

 private:
  cl::Image3D make_image(int nx, int ny, int nz, const float* values) const;

  Device& device_;
  bool as_image_;
  cl::Buffer buffer_;
  cl::Image3D image_;
};

}  // namespace pfill

// The wall's distance field on the device (see device_field.hpp).
#include "engine/device_field.hpp"

#include <algorithm>
#include <string>
#include <vector>

#include "pfill/device/device_error.hpp"
#include "pfill/error.hpp"

namespace pfill {

DeviceField::DeviceField(Device& device, bool as_image) : device_(device), as_image_(as_image) {
  buffer_ = device_.make_buffer(sizeof(float), "sdf (none)");
  dims.s[0] = dims.s[1] = dims.s[2] = 2;
  dims.s[3] = 0;
  if (as_image_) {
    const std::vector<float> none(8, 0.0f);
    image_ = make_image(2, 2, 2, none.data());
  }
}

void DeviceField::set(const ScalarGrid& field, bool borrow) {
  if (field.dims[0] < 2 || field.dims[1] < 2 || field.dims[2] < 2)
    throw Error("engine: the distance field needs at least 2 samples along each axis");
  if (field.values.size() != static_cast<size_t>(field.dims[0]) * field.dims[1] * field.dims[2])
    throw Error("engine: the distance field has " + std::to_string(field.values.size()) +
                " values for its dimensions; rebuild it");
  if (!(field.spacing > 0)) throw Error("engine: the distance field's spacing must be > 0");
  if (as_image_) {
    image_ = make_image(field.dims[0], field.dims[1], field.dims[2], field.values.data());
  } else if (borrow && device_.info().type == "CPU") {
    // The device's memory is the host's: the kernels read the caller's
    // values in place (read-only), not a second copy of up to 256 MiB.
    cl_int err = CL_SUCCESS;
    buffer_ = cl::Buffer(device_.context(), CL_MEM_READ_ONLY | CL_MEM_USE_HOST_PTR, field.bytes(),
                         const_cast<float*>(field.values.data()), &err);
    check_cl(err, "clCreateBuffer", "sdf (shared)");
  } else {
    buffer_ = device_.make_buffer(field.bytes(), "sdf");
    check_cl(device_.queue().enqueueWriteBuffer(buffer_, CL_TRUE, 0, field.bytes(), field.values.data()),
             "clEnqueueWriteBuffer", "sdf");
  }
  origin.s[0] = static_cast<float>(field.origin.x);
  origin.s[1] = static_cast<float>(field.origin.y);
  origin.s[2] = static_cast<float>(field.origin.z);
  origin.s[3] = static_cast<float>(1 / field.spacing);
  for (int a = 0; a < 3; ++a) dims.s[a] = field.dims[a];
  dims.s[3] = 1;
}

// The field as a CL_R / CL_FLOAT 3D image, checked against the device's
// 3D image limits and formats.
cl::Image3D DeviceField::make_image(int nx, int ny, int nz, const float* values) const {
  const cl::Device& dev = device_.device();
  const size_t w = dev.getInfo<CL_DEVICE_IMAGE3D_MAX_WIDTH>(), h = dev.getInfo<CL_DEVICE_IMAGE3D_MAX_HEIGHT>(),
               d = dev.getInfo<CL_DEVICE_IMAGE3D_MAX_DEPTH>();
  if (static_cast<size_t>(nx) > w || static_cast<size_t>(ny) > h || static_cast<size_t>(nz) > d)
    throw Error("engine: the distance field (" + std::to_string(nx) + "x" + std::to_string(ny) + "x" +
                std::to_string(nz) + ") exceeds the device's 3D image limit " + std::to_string(w) + "x" +
                std::to_string(h) + "x" + std::to_string(d) + "; unset EngineParams::field_image");
  std::vector<cl::ImageFormat> formats;
  check_cl(device_.context().getSupportedImageFormats(CL_MEM_READ_ONLY, CL_MEM_OBJECT_IMAGE3D, &formats),
           "clGetSupportedImageFormats", "sdf image");
  const bool r_float = std::any_of(formats.begin(), formats.end(), [](const cl::ImageFormat& f) {
    return f.image_channel_order == CL_R && f.image_channel_data_type == CL_FLOAT;
  });
  if (!r_float)
    throw Error("engine: device '" + device_.info().name +
                "' has no CL_R / CL_FLOAT 3D image format; unset EngineParams::field_image");
  cl_int err = CL_SUCCESS;
  cl::Image3D image(device_.context(), CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, cl::ImageFormat(CL_R, CL_FLOAT),
                    static_cast<size_t>(nx), static_cast<size_t>(ny), static_cast<size_t>(nz), 0, 0,
                    const_cast<float*>(values), &err);
  check_cl(err, "clCreateImage", "sdf image");
  return image;
}

}  // namespace pfill

/// @file device_error.hpp
/// @brief The one exception type of the OpenCL device layer, and the helpers
/// that turn an OpenCL status code into it.
#pragma once
#include <string>

#include "pfill/error.hpp"

namespace pfill {

/// An OpenCL call failed. what() names the call, the status's symbolic name
/// (CL_OUT_OF_RESOURCES, ...) and, for program builds, the device and the
/// whole build log.
class DeviceError : public Error {
 public:
  DeviceError(const std::string& message, int status) : Error(message), status_(status) {}
  int status() const { return status_; }  ///< the OpenCL status code (CL_...)

 private:
  int status_;
};

/// "CL_OUT_OF_RESOURCES" for -5, "CL_UNKNOWN_ERROR(-1234)" for codes it does not know.
std::string cl_status_name(int status);

/// Throws DeviceError("<call> failed: <name>[: detail]") unless status is CL_SUCCESS.
void check_cl(int status, const std::string& call, const std::string& detail = "");

}  // namespace pfill

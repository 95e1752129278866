/// @file embedded_kernels.hpp
/// @brief The OpenCL C sources of kernels/*.cl, embedded at build time.
#pragma once
#include <string>
#include <vector>

namespace pfill {

/// Source text of kernels/NAME (e.g. "pairs.cl"); throws if there is none.
const char* embedded_kernel_source(const std::string& name);

/// Names of all embedded kernel files, in build order.
std::vector<std::string> embedded_kernel_names();

}  // namespace pfill

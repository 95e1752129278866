// The error message a mesh file gives, for the bad-input tests.
#pragma once
#include <doctest/doctest.h>

#include <exception>
#include <string>

#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"

namespace pfill::test {

/// The error message of load_mesh(path), or "" when it loads; any exception
/// other than pfill::Error fails the test.
inline std::string load_error(const std::string& path) {
  try {
    load_mesh(path);
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    FAIL("not a pfill::Error: " << e.what());
  }
  return "";
}

}  // namespace pfill::test

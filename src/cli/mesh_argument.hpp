// A mesh argument of any subcommand (fill, info, check, render --mesh): a
// built-in shape name (torus, sphere, cube) or a mesh file, the same way
// everywhere. A built-in name wins; a file of that name is read as ./NAME.
#pragma once
#include <string>

#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

namespace pfill::cli {

inline bool is_builtin_shape(const std::string& name) {
  for (const std::string& n : builtin_shape_names())
    if (n == name) return true;
  return false;
}

inline Mesh load_mesh_argument(const std::string& name) {
  return is_builtin_shape(name) ? make_builtin(name) : load_mesh(name);
}

}  // namespace pfill::cli

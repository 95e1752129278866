// The `mesh` argument (mesh_argument.hpp).
#include "mesh_argument.hpp"

#include <filesystem>
#include <string>

#include "arrays.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

namespace pfill::python {
namespace {

bool is_builtin_name(const std::string& name) {
  for (const std::string& n : builtin_shape_names())
    if (n == name) return true;
  return false;
}

}  // namespace

/// A path, a built-in shape name (when no such file exists, as in `pfill
/// check`), or a (vertices, triangles) pair.
Mesh mesh_from(const py::handle& object) {
  if (py::isinstance<py::str>(object) || py::hasattr(object, "__fspath__")) {
    const std::string path = py::str(py::module_::import("os").attr("fspath")(object));
    if (path.find('\0') != std::string::npos)
      throw Error("mesh: the path holds a NUL character ('" + excerpt(path) + "'); no file can have that name");
    if (is_builtin_name(path) && !std::filesystem::exists(path)) return make_builtin(path);
    py::gil_scoped_release release;
    return load_mesh(path);
  }
  if (py::isinstance<py::sequence>(object) && py::len(object) == 2) {
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(object);
    Mesh mesh;
    mesh.source = "(vertices, triangles)";
    mesh.positions = to_vec3(rows_of_three(pair[0], "mesh vertices"));
    IndexArray t;
    try {
      // Whole numbers only: forcecast would truncate 1.7 to 1 without a word.
      const py::array given = py::array::ensure(pair[1]);
      if (given && given.size() > 0 && given.dtype().kind() != 'i' && given.dtype().kind() != 'u')
        throw Error("mesh triangles: give integer vertex indices, not " + std::string(py::str(given.dtype())) +
                    " (an index like 1.7 would be cut to 1)");
      t = IndexArray::ensure(pair[1]);
    } catch (const py::error_already_set&) {
    }
    if (!t || t.ndim() != 2 || t.shape(1) != 3) throw Error("mesh triangles: give a (T, 3) array of vertex indices");
    auto v = t.unchecked<2>();
    const auto n = static_cast<int64_t>(mesh.positions.size());
    mesh.triangles.resize(static_cast<size_t>(t.shape(0)));
    for (size_t i = 0; i < mesh.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) {
        if (v(i, k) < 0 || v(i, k) >= n)
          throw Error("mesh triangles: triangle " + std::to_string(i) + " names vertex " + std::to_string(v(i, k)) +
                      ", but there are " + std::to_string(n) + " vertices (indices start at 0)");
        mesh.triangles[i][k] = static_cast<uint32_t>(v(i, k));
      }
    weld_vertices(mesh);  // as the file loaders do: bit-identical duplicates
    validate(mesh);
    mesh.turned_faces = orient_faces(mesh);
    return mesh;
  }
  throw Error("mesh: give a file path, a built-in shape name or a (vertices, triangles) pair");
}

py::tuple load_mesh_arrays(const py::handle& path) {
  const Mesh mesh = mesh_from(path);
  py::array_t<int64_t> t({static_cast<py::ssize_t>(mesh.triangles.size()), py::ssize_t(3)});
  auto v = t.mutable_unchecked<2>();
  for (size_t i = 0; i < mesh.triangles.size(); ++i)
    for (int k = 0; k < 3; ++k) v(i, k) = mesh.triangles[i][k];
  return py::make_tuple(vec3_array(mesh.positions), t);
}

}  // namespace pfill::python

// The `mesh` argument of the Python module's functions: a file path (str or
// os.PathLike), a built-in shape name, or a (vertices, triangles) pair.
#pragma once
#include <pybind11/pybind11.h>

#include "pfill/mesh.hpp"

namespace pfill::python {

namespace py = pybind11;

/// The mesh `object` names or holds; pfill::Error with a one-line message
/// otherwise. Arrays are welded (bit-identical vertices) and validated as
/// the file loaders do.
Mesh mesh_from(const py::handle& object);

/// pfill.load_mesh: (vertices (V, 3) float64, triangles (T, 3) int64).
py::tuple load_mesh_arrays(const py::handle& path);

}  // namespace pfill::python

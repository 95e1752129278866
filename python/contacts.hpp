// The contact network in the Python module: pfill.contacts(positions, radii,
// gap=, mesh=) and FillResult.contacts / .coordination (python/contacts.cpp).
#pragma once
#include <pybind11/pybind11.h>

namespace pfill::python {

namespace py = pybind11;

/// The pairs within `gap` (fraction of the smaller radius) of the spheres
/// at `positions` (N, 3) with `radii` (N,): an (M, 2) int64 array of
/// indices (a < b), and each sphere's coordination (N,) int64.
py::tuple contact_pairs(const py::object& positions, const py::object& radii, double gap);

/// Adds pfill.contacts() to the module.
void add_contacts_bindings(py::module_& m);

/// Adds pfill.surface() (python/surface.cpp).
void add_surface_bindings(py::module_& m);

/// Adds pfill.read_particles() (python/particle_files.cpp).
void add_particle_file_bindings(py::module_& m);

}  // namespace pfill::python

// pfill.read_particles(path): any particle file pfill writes, as arrays,
// with a shell's kinds apart (fill --shell) (declared in contacts.hpp).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "arrays.hpp"
#include "contacts.hpp"
#include "pfill/particle_io.hpp"

namespace pfill::python {
namespace {

template <class T, class U>
py::object column(const std::vector<U>& values) {
  if (values.empty()) return py::none();
  py::array_t<T> a(static_cast<py::ssize_t>(values.size()));
  auto v = a.template mutable_unchecked<1>();
  for (size_t i = 0; i < values.size(); ++i) v(i) = static_cast<T>(values[i]);
  return std::move(a);
}

py::dict read_particle_file(const std::string& path, std::optional<double> radius) {
  ParticleReadOptions ro;
  ro.default_radius = radius ? *radius : 0.0;
  ParticleAttributes a;
  ro.attributes = &a;
  ParticleSet p;
  {
    py::gil_scoped_release release;
    p = read_particles(path, ro);
  }
  py::dict out;
  out["positions"] = vec3_array(p.positions);
  out["radii"] = column<double>(p.radii);
  out["ids"] = column<uint64_t>(p.ids);
  if (p.has_colours()) {
    py::array_t<uint8_t> c({static_cast<py::ssize_t>(p.size()), py::ssize_t(3)});
    auto v = c.mutable_unchecked<2>();
    for (size_t i = 0; i < p.size(); ++i)
      for (int k = 0; k < 3; ++k) v(i, k) = p.colours[i][k];
    out["colours"] = c;
  } else {
    out["colours"] = py::none();
  }
  out["velocities"] = p.has_velocities() ? py::object(vec3_array(p.velocities)) : py::none();
  out["kinds"] = column<uint8_t>(a.kinds);
  out["normals"] = a.has_normals() ? py::object(vec3_array(a.normals)) : py::none();
  out["areas"] = column<double>(a.areas);
  return out;
}

}  // namespace

void add_particle_file_bindings(py::module_& m) {
  m.def("read_particles", &read_particle_file, py::arg("path"), py::kw_only(), py::arg("radius") = py::none(),
        "Reads a particle file pfill writes (.ply .glb .csv .vtp .data .xyzr). Returns a dict: positions (N, 3), "
        "radii (N,), and where the file has them (else None) ids (N,) uint64, colours (N, 3) uint8, velocities "
        "(N, 3), and a shell's (fill --shell, pfill surface) kinds (N,) uint8 (0 inner, 1 boundary), normals "
        "(N, 3) and areas (N,). radius: for files without radii.");
}

}  // namespace pfill::python

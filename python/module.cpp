// The compiled part of the Python module `pfill` (pfill._pfill): fill,
// check, load_mesh and devices, with every fill option by its command-line
// name, the GIL released while filling, and pfill's errors as pfill.Error.
// python/pfill/__init__.py re-exports it.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "arrays.hpp"
#include "contacts.hpp"
#include "fill_hooks.hpp"
#include "mesh_argument.hpp"
#include "pfill/boundary.hpp"
#include "pfill/contact_network.hpp"
#include "pfill/device/device.hpp"
#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/fill_settings.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/shapes.hpp"

namespace py = pybind11;

namespace pfill::python {
namespace {

struct PyFillResult {
  py::object positions, radii, colours, velocities, ids, metrics, report;
  py::object contacts = py::none(), coordination = py::none();  // found on first access (contacts.hpp)
  double radius = 0;
  size_t size = 0;
};

/// A keyword's value as the text FillSetting::set reads: numbers as Python
/// writes them (NaN stays "nan", which the parser refuses), sequences as
/// "a,b,c", names as they are.
std::string setting_text(const std::string& name, const py::handle& value) {
  if (py::isinstance<py::bool_>(value)) throw Error(name + ": give a number or a name, not True or False");
  if (py::isinstance<py::str>(value)) {
    const std::string text = value.cast<std::string>();
    if (text.find('\0') != std::string::npos) throw Error(name + ": the text holds a NUL character");
    return text;
  }
  if (py::isinstance<py::int_>(value) ||
      (PyNumber_Check(value.ptr()) && !py::isinstance<py::sequence>(value) && !py::isinstance<py::array>(value)))
    return py::str(py::isinstance<py::int_>(value) ? value : py::reinterpret_steal<py::object>(PyNumber_Float(value.ptr())));
  if (py::isinstance<py::sequence>(value) || py::isinstance<py::array>(value)) {
    std::string text;
    for (const py::handle& item : py::iter(value)) {
      if (py::isinstance<py::bool_>(item) || !PyNumber_Check(item.ptr()))
        throw Error(name + ": give numbers, e.g. (1, 2, 3)");
      text += (text.empty() ? "" : ",") + std::string(py::str(py::float_(py::reinterpret_borrow<py::object>(item))));
    }
    return text;
  }
  throw Error(name + ": give a number, a name or a sequence of numbers, not " +
              std::string(py::str(py::type::of(value).attr("__name__"))));
}

PyFillResult run_fill(const py::object& mesh_arg, const py::kwargs& keywords) {
  FillOptions o;
  py::object progress = py::none(), cancelled = py::none();
  for (const auto& [key, value] : keywords) {
    const std::string name = py::str(key);
    if (name == "progress") {
      progress = py::reinterpret_borrow<py::object>(value);
      continue;
    }
    if (name == "cancelled") {
      cancelled = py::reinterpret_borrow<py::object>(value);
      continue;
    }
    const FillSetting* setting = find_fill_setting(name);
    if (!setting) throw Error("fill() got an unknown keyword '" + name + "' (see help(pfill.fill) for the settings)");
    if (value.is_none()) continue;  // unset: the default
    setting->set(o, setting_text(name, value));
  }
  if (o.radius <= 0 && o.count == 0) o.count = 4000;  // the command line's default
  check_fill_options(o);  // before the mesh is read, as the command line does

  const Mesh mesh = mesh_from(mesh_arg);
  FillHooks hooks(progress, cancelled);
  hooks.attach(o);
  FillResult r;
  bool was_cancelled = false;
  {
    py::gil_scoped_release release;
    try {
      r = fill(mesh, o);
    } catch (const Cancelled&) {
      was_cancelled = true;  // raised below, with the GIL held again
    }
  }
  if (was_cancelled) hooks.raise_cancelled();
  // The command line prints these as "pfill: warning: ..." (an open or
  // inside-out mesh, a coarsened field, colours it could not take).
  for (const std::string& w : r.warnings)
    if (PyErr_WarnEx(PyExc_UserWarning, ("pfill: " + w).c_str(), 1) != 0) throw py::error_already_set();

  const ParticleSet& ps = r.particles;
  PyFillResult out;
  out.size = ps.size();
  out.radius = r.radius;
  out.positions = vec3_array(ps.positions);
  out.radii = py::array_t<double>(static_cast<py::ssize_t>(ps.size()), ps.radii.data());
  out.velocities = ps.has_velocities() ? py::object(vec3_array(ps.velocities)) : py::none();
  out.ids = ps.has_ids() ? py::object(py::array_t<uint64_t>(static_cast<py::ssize_t>(ps.size()), ps.ids.data()))
                         : py::none();
  if (ps.has_colours()) {
    py::array_t<uint8_t> c({static_cast<py::ssize_t>(ps.size()), py::ssize_t(3)});
    auto v = c.mutable_unchecked<2>();
    for (size_t i = 0; i < ps.size(); ++i)
      for (int k = 0; k < 3; ++k) v(i, k) = ps.colours[i][k];
    out.colours = c;
  } else {
    out.colours = py::none();
  }
  out.report = to_python(fill_report_json(r, mesh.source, o.seed));
  out.metrics = out.report["metrics"];
  return out;
}

py::object check(const py::object& positions, const py::object& radii, const py::object& mesh_arg,
                 double tolerance) {
  ParticleSet ps = particles_from(positions, radii);
  if (!(tolerance >= 0 && tolerance <= 1)) throw Error("tolerance must be a number in 0..1 (a fraction of r)");
  Mesh mesh = mesh_from(mesh_arg);
  // About the mesh's centre, as fill() works (the ray tracer is single precision).
  const Vec3 centre = mesh.bounds().centre();
  for (Vec3& p : mesh.positions) p -= centre;
  for (Vec3& p : ps.positions) p -= centre;
  PackingMetrics m;
  {
    py::gil_scoped_release release;
    const Boundary boundary(mesh);
    MetricsOptions mo;
    mo.containment_tolerance = tolerance;
    m = measure_packing(boundary, diagnose(mesh).volume(), ps, mo);
  }
  return to_python(metrics_json(m));
}

py::list devices() {
  const std::vector<DeviceInfo> all = list_devices();
  const int chosen = all.empty() ? -1 : choose_device("").index;
  py::list out;
  for (const DeviceInfo& d : all) {
    py::dict e;
    e["index"] = d.index;
    e["name"] = d.name;
    e["platform"] = d.platform;
    e["type"] = d.type;
    e["version"] = d.version;
    e["compute_units"] = d.compute_units;
    e["global_memory"] = d.global_memory;
    e["default"] = d.index == chosen;
    out.append(e);
  }
  return out;
}

}  // namespace
}  // namespace pfill::python

PYBIND11_MODULE(_pfill, m) {
  using namespace pfill;
  using namespace pfill::python;
  m.doc() = "pfill: fill closed triangle meshes with densely packed spheres (see help(pfill.fill))";
  m.attr("__version__") = PFILL_VERSION;

  // pfill.Error (a RuntimeError) carries pfill's one-line messages;
  // pfill.Cancelled is raised when a `cancelled` callback asked to stop.
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<Cancelled> cancelled_error(m, "Cancelled", error.ptr());
  error.attr("__module__") = "pfill";
  cancelled_error.attr("__module__") = "pfill";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Cancelled& e) {
      PyErr_SetString(cancelled_error.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });

  py::class_<PyFillResult>(m, "FillResult", "The particles of a fill and its figures")
      .def_readonly("positions", &PyFillResult::positions, "(N, 3) float64 centres")
      .def_readonly("radii", &PyFillResult::radii, "(N,) float64 radii")
      .def_readonly("colours", &PyFillResult::colours, "(N, 3) uint8 sRGB colours, or None")
      .def_readonly("velocities", &PyFillResult::velocities, "(N, 3) float64 velocities, or None")
      .def_readonly("ids", &PyFillResult::ids, "(N,) uint64 particle ids (birth order, as in the files), or None")
      .def_readonly("metrics", &PyFillResult::metrics, "dict: the metrics of `pfill fill --report`")
      .def_readonly("report", &PyFillResult::report, "dict: the whole `pfill fill --report` JSON")
      .def_readonly("radius", &PyFillResult::radius, "the particle radius")
      .def_property_readonly("contacts", [](PyFillResult& r) {
        if (r.contacts.is_none()) {
          const py::tuple t = contact_pairs(r.positions, r.radii, kDefaultContactGap);
          r.contacts = t[0], r.coordination = t[1];
        }
        return r.contacts;
      }, "(M, 2) int64: the pairs of spheres in contact (indices, a < b; gap at most 2% of the smaller "
         "radius); pfill.contacts() for another gap and the wall")
      .def_property_readonly("coordination", [](PyFillResult& r) {
        if (r.coordination.is_none()) {
          const py::tuple t = contact_pairs(r.positions, r.radii, kDefaultContactGap);
          r.contacts = t[0], r.coordination = t[1];
        }
        return r.coordination;
      }, "(N,) int64: each sphere's contacts (as in .contacts)")
      .def("__len__", [](const PyFillResult& r) { return r.size; })
      .def("__repr__", [](const PyFillResult& r) {
        return "<pfill.FillResult " + std::to_string(r.size) + " particles, radius " +
               std::string(py::str(py::float_(r.radius))) + ", packing fraction " +
               std::string(py::str(r.metrics["packing_fraction"])) + ">";
      });

  m.def("load_mesh", &load_mesh_arrays, py::arg("path"),
        "Reads a mesh file (glTF/GLB, OBJ, STL, PLY, OFF, SMF, ...) or a built-in shape name; returns "
        "(vertices (V, 3) float64, triangles (T, 3) int64), welded as `pfill fill` welds them.");
  std::string fill_doc =
      "Fills a mesh (a file path, a built-in shape name, or a (vertices, triangles) pair) with spheres.\n\n"
      "Settings are keywords with the names of `pfill fill`'s options (underscores for dashes) and of the C++ "
      "FillOptions fields; with neither count nor radius, count=4000 as on the command line; None leaves a "
      "setting at its default. The same mesh, settings, seed and device give the same particles as `pfill fill`.\n"
      "progress: called with a dict (phase, step, particles, target, kinetic_energy, colliding_pairs, "
      "steps_per_second, elapsed, remaining) at each new phase and up to ten times a second; an "
      "exception it raises stops the fill.\n"
      "cancelled: called now and then; returning True stops the fill with pfill.Cancelled. "
      "Ctrl-C stops it with KeyboardInterrupt.\n"
      "Returns a FillResult (positions, radii, colours, velocities, ids, metrics, report, radius).\n\n"
      "Settings (default in brackets):\n";
  for (const FillSetting& setting : fill_settings()) {
    const std::string shown = setting.get(FillOptions{});
    fill_doc += "  " + setting.name + " (" + setting.value_form + (shown.empty() ? "" : ") [" + shown + "]") +
                (shown.empty() ? ")" : "") + ": " + setting.help + "\n";
  }
  static const std::string fill_doc_kept = fill_doc;  // pybind11 keeps the pointer
  m.def("fill", &run_fill, py::arg("mesh"), fill_doc_kept.c_str());
  m.def("check", &check, py::arg("positions"), py::arg("radii"), py::arg("mesh"), py::kw_only(),
        py::arg("tolerance") = MetricsOptions{}.containment_tolerance,
        "Measures spheres against a mesh, exactly (as `pfill check --json`): returns the metrics dict "
        "(packing_fraction, contained_share, overlaps, coordination, ...). radii: one per particle or one "
        "for all; tolerance: allowed crossing of the surface, a fraction of r.");
  m.def("devices", &devices,
        "The OpenCL devices, as dicts (index, name, platform, type, version, compute_units, global_memory, "
        "default); choose one with fill(..., device=index or name) or PFILL_DEVICE.");
  add_contacts_bindings(m);
  add_surface_bindings(m);
  add_particle_file_bindings(m);
  m.def("builtin_shapes", &builtin_shape_names, "Names of the built-in shapes fill() and load_mesh() accept.");
}

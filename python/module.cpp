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

PyFillResult run_fill(const py::object& mesh_arg, std::optional<long long> count, std::optional<double> radius,
                      double rest_distance, double epsilon, double cutoff, const py::object& exponents,
                      double restitution, double wall_restitution, double damping, double time_step,
                      long long seed, int sites, double site_spacing, double site_min_depth, double site_depth,
                      int birth_every, double birth_clearance, double stop_share,
                      const py::object& birth_speed, double max_step, const py::object& birth,
                      const std::string& stop, int patience, int void_rounds, double void_clearance,
                      double max_overlap, const py::object& colour, double skin, int sync_every,
                      const std::string& device, const py::object& progress, const py::object& cancelled) {
  FillOptions o;
  if (count && *count < 0) throw Error("count must be >= 0 (about how many particles)");
  if (seed < 0) throw Error("seed must be >= 0");
  o.count = count ? static_cast<size_t>(*count) : 0;
  o.radius = radius.value_or(0.0);
  if (!count && !radius) o.count = 4000;  // the command line's default
  o.rest_distance = rest_distance;
  o.epsilon = epsilon;
  o.cutoff = cutoff;
  std::tie(o.exponent_a, o.exponent_b) = number_pair(exponents, "exponents");
  if (!(o.exponent_a > o.exponent_b && o.exponent_b > 0))
    throw Error("exponents: give A, B with A > B > 0 (default 12, 6)");
  o.restitution = restitution;
  o.wall_restitution = wall_restitution;
  o.damping = damping;
  o.time_step = time_step;
  o.seed = static_cast<uint64_t>(seed);
  o.sites = sites;
  o.site_spacing = site_spacing;
  o.site_min_depth = site_min_depth;
  o.site_depth_share = site_depth;
  o.birth_stop_share = stop_share;
  o.birth_every = birth_every;
  o.birth_clearance = birth_clearance;
  std::tie(o.birth_speed_min, o.birth_speed_max) = number_pair(birth_speed, "birth_speed");
  o.max_step_fraction = max_step;
  if (!birth.is_none()) {
    try {
      o.birth_point = to_vec3(rows_of_three(py::make_tuple(birth), "birth"))[0];
    } catch (const Error&) {
      throw Error("birth: give three numbers (x, y, z), a point inside the mesh");
    }
  }
  o.stop = parse_stop_criterion(stop);
  o.blocked.patience = patience;
  o.void_rounds = void_rounds;
  o.void_clearance = void_clearance;
  o.max_overlap = max_overlap;
  if (!colour.is_none()) o.colour = parse_colour_option(py::str(colour));
  o.skin = skin;
  o.sync_every = sync_every;
  o.device = device;

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
  ParticleSet ps;
  ps.positions = to_vec3(rows_of_three(positions, "positions"));
  DoubleArray r;
  try {
    r = DoubleArray::ensure(radii);
  } catch (const py::error_already_set&) {
  }
  if (!r || r.ndim() > 1) throw Error("radii: give one radius, or an array of one per particle");
  if (r.ndim() == 0) {
    ps.radii.assign(ps.positions.size(), *r.data());
  } else {
    if (static_cast<size_t>(r.shape(0)) != ps.positions.size())
      throw Error("radii: " + std::to_string(r.shape(0)) + " radii for " + std::to_string(ps.positions.size()) +
                  " positions; give one per particle");
    ps.radii.assign(r.data(), r.data() + r.shape(0));
  }
  validate(ps, "particles");
  const Mesh mesh = mesh_from(mesh_arg);
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
  const FillOptions d;
  m.def("fill", &run_fill, py::arg("mesh"), py::kw_only(), py::arg("count") = py::none(),
        py::arg("radius") = py::none(), py::arg("rest_distance") = d.rest_distance, py::arg("epsilon") = d.epsilon,
        py::arg("cutoff") = d.cutoff, py::arg("exponents") = py::make_tuple(d.exponent_a, d.exponent_b),
        py::arg("restitution") = d.restitution, py::arg("wall_restitution") = d.wall_restitution,
        py::arg("damping") = d.damping, py::arg("time_step") = d.time_step, py::arg("seed") = d.seed,
        py::arg("sites") = d.sites, py::arg("site_spacing") = d.site_spacing,
        py::arg("site_min_depth") = d.site_min_depth, py::arg("site_depth") = d.site_depth_share,
        py::arg("birth_every") = d.birth_every, py::arg("birth_clearance") = d.birth_clearance,
        py::arg("stop_share") = d.birth_stop_share,
        py::arg("birth_speed") = py::make_tuple(d.birth_speed_min, d.birth_speed_max),
        py::arg("max_step") = d.max_step_fraction, py::arg("birth") = py::none(), py::arg("stop") = "blocked",
        py::arg("patience") = d.blocked.patience, py::arg("void_rounds") = d.void_rounds,
        py::arg("void_clearance") = d.void_clearance, py::arg("max_overlap") = d.max_overlap,
        py::arg("colour") = py::none(), py::arg("skin") = d.skin, py::arg("sync_every") = d.sync_every,
        py::arg("device") = "", py::arg("progress") = py::none(), py::arg("cancelled") = py::none(),
        "Fills a mesh (a file path, a built-in shape name, or a (vertices, triangles) pair) with spheres.\n\n"
        "Options are `pfill fill`'s, by their command-line names with underscores (count, radius, "
        "rest_distance, cutoff, exponents, seed, stop, colour, ...); with neither count nor radius, "
        "count=4000 as on the command line. The same mesh, options, seed and device give the same "
        "particles as `pfill fill`.\n"
        "progress: called with a dict (phase, step, particles, target, kinetic_energy, colliding_pairs, "
        "steps_per_second, elapsed, remaining) at each new phase and up to ten times a second; an "
        "exception it raises stops the fill.\n"
        "cancelled: called now and then; returning True stops the fill with pfill.Cancelled. "
        "Ctrl-C stops it with KeyboardInterrupt.\n"
        "Returns a FillResult (positions, radii, colours, velocities, ids, metrics, report, radius).");
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
  m.def("builtin_shapes", &builtin_shape_names, "Names of the built-in shapes fill() and load_mesh() accept.");
}

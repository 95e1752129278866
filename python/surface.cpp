// pfill.surface(): boundary particles on a mesh's surface (python/contacts.hpp
// declares add_surface_bindings beside the contacts).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <string>

#include "arrays.hpp"
#include "contacts.hpp"
#include "mesh_argument.hpp"
#include "pfill/boundary.hpp"
#include "pfill/error.hpp"
#include "pfill/mesh_diagnostics.hpp"
#include "pfill/surface_sampling.hpp"

namespace pfill::python {
namespace {

py::dict shell_dict(const ShellStats& s) {
  py::dict d;
  d["particles"] = s.count;
  d["spacing"] = s.spacing;
  d["nearest_mean"] = s.nn_mean;
  d["nearest_min"] = s.nn_min;
  d["nearest_max"] = s.nn_max;
  d["share_within_15_percent"] = s.share_within_15;
  d["closer_than_0.8_spacing"] = s.closer_than_08;
  d["coverage"] = s.coverage;
  d["coverage_over_r"] = s.coverage_over_r;
  d["surface_points"] = s.surface_points;
  return d;
}

py::dict surface(const py::object& mesh_arg, std::optional<double> radius, std::optional<long long> count,
                 long long seed, int relax, bool measure) {
  if (radius.has_value() == count.has_value()) throw Error("give radius (spacing 2 radius) or count, one of them");
  if (count && *count < 1) throw Error("count must be >= 1");
  if (seed < 0) throw Error("seed must be >= 0");
  if (relax < 0) throw Error("relax must be >= 0");
  const Mesh mesh = mesh_from(mesh_arg);
  SurfaceSamples s;
  ShellStats st;
  {
    py::gil_scoped_release release;
    const Boundary boundary(mesh);
    SurfaceSamplingOptions o;
    o.radius = radius ? *radius : surface_radius_for_count(diagnose(mesh).surface_area, static_cast<size_t>(*count));
    o.seed = static_cast<uint64_t>(seed);
    o.relax_iterations = relax;
    s = sample_surface(boundary, o);
    if (measure) st = measure_shell(boundary, s.positions, s.radius);
  }
  py::dict out;
  out["positions"] = vec3_array(s.positions);
  out["normals"] = vec3_array(s.normals);
  out["areas"] = py::array_t<double>(static_cast<py::ssize_t>(s.areas.size()), s.areas.data());
  out["radius"] = s.radius;
  out["surface_area"] = s.surface_area;
  if (measure) out["shell"] = shell_dict(st);
  return out;
}

}  // namespace

void add_surface_bindings(py::module_& m) {
  m.def("surface", &surface, py::arg("mesh"), py::kw_only(), py::arg("radius") = py::none(),
        py::arg("count") = py::none(), py::arg("seed") = 1, py::arg("relax") = SurfaceSamplingOptions{}.relax_iterations,
        py::arg("measure") = true,
        "Boundary particles on a mesh's surface at spacing 2 radius (as `pfill surface`): give radius or count. "
        "Returns a dict: positions (N, 3), normals (N, 3) out of the solid, areas (N,) (summing to the "
        "surface area), radius, surface_area and, with measure, shell (nearest-neighbour spacing and coverage, "
        "as `pfill check --shell`).");
}

}  // namespace pfill::python

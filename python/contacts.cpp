// pfill.contacts() and the arrays behind FillResult.contacts (python/contacts.hpp).
#include "contacts.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <memory>
#include <string>

#include "arrays.hpp"
#include "mesh_argument.hpp"
#include "pfill/boundary.hpp"
#include "pfill/contact_network.hpp"
#include "pfill/error.hpp"

namespace pfill::python {
namespace {

py::array_t<int64_t> pairs_array(const ContactNetwork& net) {
  py::array_t<int64_t> pairs({static_cast<py::ssize_t>(net.pairs.size()), py::ssize_t(2)});
  auto v = pairs.mutable_unchecked<2>();
  for (size_t k = 0; k < net.pairs.size(); ++k) v(k, 0) = net.pairs[k].a, v(k, 1) = net.pairs[k].b;
  return pairs;
}

py::array_t<int64_t> coordination_array(const ContactNetwork& net) {
  py::array_t<int64_t> c(static_cast<py::ssize_t>(net.coordination.size()));
  auto v = c.mutable_unchecked<1>();
  for (size_t i = 0; i < net.coordination.size(); ++i) v(i) = net.coordination[i];
  return c;
}

py::dict contacts(const py::object& positions, const py::object& radii, double gap, const py::object& mesh_arg) {
  const ParticleSet ps = particles_from(positions, radii);
  ContactNetwork net;
  nlohmann::ordered_json report;
  {
    std::unique_ptr<Mesh> mesh;
    if (!mesh_arg.is_none()) mesh = std::make_unique<Mesh>(mesh_from(mesh_arg));
    py::gil_scoped_release release;
    net = find_contacts(ps, gap);
    std::unique_ptr<Boundary> boundary;
    if (mesh) {
      boundary = std::make_unique<Boundary>(*mesh);
      find_wall_contacts(net, ps, *boundary);
    }
    report = contacts_report_json(net, ps, boundary.get());
  }
  py::dict out;
  out["pairs"] = pairs_array(net);
  py::array_t<double> gaps(static_cast<py::ssize_t>(net.pairs.size()));
  for (size_t k = 0; k < net.pairs.size(); ++k) gaps.mutable_at(k) = net.pairs[k].gap;
  out["gaps"] = gaps;
  out["coordination"] = coordination_array(net);
  if (!mesh_arg.is_none()) {
    const size_t w = net.wall.size();
    py::array_t<int64_t> particle(static_cast<py::ssize_t>(w));
    py::array_t<double> wall_gaps(static_cast<py::ssize_t>(w));
    std::vector<Vec3> points(w), normals(w);
    for (size_t k = 0; k < w; ++k) {
      particle.mutable_at(k) = net.wall[k].particle;
      wall_gaps.mutable_at(k) = net.wall[k].gap;
      points[k] = net.wall[k].point;
      normals[k] = net.wall[k].normal;
    }
    out["wall_particles"] = particle;
    out["wall_points"] = vec3_array(points);
    out["wall_normals"] = vec3_array(normals);
    out["wall_gaps"] = wall_gaps;
  }
  out["report"] = to_python(report);
  return out;
}

}  // namespace

py::tuple contact_pairs(const py::object& positions, const py::object& radii, double gap) {
  const ParticleSet ps = particles_from(positions, radii);
  ContactNetwork net;
  {
    py::gil_scoped_release release;
    net = find_contacts(ps, gap);
  }
  return py::make_tuple(pairs_array(net), coordination_array(net));
}

void add_contacts_bindings(py::module_& m) {
  m.def("contacts", &contacts, py::arg("positions"), py::arg("radii"), py::kw_only(),
        py::arg("gap") = kDefaultContactGap, py::arg("mesh") = py::none(),
        "The contact network of spheres (as `pfill contacts`): the pairs whose gap is at most `gap` times "
        "the smaller radius. Returns a dict: pairs (M, 2) int64 indices (a < b), gaps (M,) (negative: "
        "overlap), coordination (N,), report (the `contacts` section of --report); with a mesh (file, "
        "built-in name or (vertices, triangles)) also the spheres touching its surface: wall_particles, "
        "wall_points, wall_normals (out of the solid), wall_gaps.");
}

}  // namespace pfill::python

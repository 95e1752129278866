// numpy <-> pfill (arrays.hpp).
#include "arrays.hpp"

#include <cstdio>

#include "pfill/error.hpp"

namespace pfill::python {

py::array_t<double> vec3_array(const std::vector<Vec3>& points) {
  py::array_t<double> a({static_cast<py::ssize_t>(points.size()), py::ssize_t(3)});
  auto v = a.mutable_unchecked<2>();
  for (size_t i = 0; i < points.size(); ++i) {
    v(i, 0) = points[i].x;
    v(i, 1) = points[i].y;
    v(i, 2) = points[i].z;
  }
  return a;
}

/// An (N, 3) array of `what`, as numbers; a one-line error otherwise.
DoubleArray rows_of_three(const py::handle& object, const std::string& what) {
  DoubleArray a;
  try {
    a = DoubleArray::ensure(object);
  } catch (const py::error_already_set&) {
  }
  if (!a || a.ndim() != 2 || a.shape(1) != 3)
    throw Error(what + ": give an (N, 3) array of numbers");
  return a;
}

std::vector<Vec3> to_vec3(const DoubleArray& a) {
  auto v = a.unchecked<2>();
  std::vector<Vec3> out(static_cast<size_t>(a.shape(0)));
  for (size_t i = 0; i < out.size(); ++i) out[i] = {v(i, 0), v(i, 1), v(i, 2)};
  return out;
}

ParticleSet particles_from(const py::handle& positions, const py::handle& radii) {
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
  return ps;
}

/// JSON from the library (fill_report.hpp) as Python dicts and lists.
py::object to_python(const nlohmann::ordered_json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

/// Two numbers from a pair or the command line's "A,B" text.
std::pair<double, double> number_pair(const py::handle& value, const std::string& what) {
  if (py::isinstance<py::str>(value)) {
    const std::string text = py::str(value);
    double a = 0, b = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%lf,%lf%c", &a, &b, &extra) == 2) return {a, b};
  } else if (py::isinstance<py::sequence>(value) && py::len(value) == 2) {
    try {
      const py::sequence s = py::reinterpret_borrow<py::sequence>(value);
      return {s[0].cast<double>(), s[1].cast<double>()};
    } catch (const py::cast_error&) {
    }
  }
  throw Error(what + ": give two numbers, (A, B) or \"A,B\"");
}

}  // namespace pfill::python

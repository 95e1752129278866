// Conversions between numpy arrays (and Python values) and pfill's types,
// for the Python module. Bad input is a pfill::Error with a one-line message.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "pfill/particles.hpp"
#include "pfill/vec3.hpp"

namespace pfill::python {

namespace py = pybind11;
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;

/// An (N, 3) float64 array of the points.
py::array_t<double> vec3_array(const std::vector<Vec3>& points);

/// `object` as an (N, 3) array of numbers; else an error naming `what`.
DoubleArray rows_of_three(const py::handle& object, const std::string& what);

std::vector<Vec3> to_vec3(const DoubleArray& rows);

/// Spheres from `positions` (N, 3) and `radii` (one number, or N of them),
/// validated; else an error naming the argument (pfill.check, pfill.contacts).
ParticleSet particles_from(const py::handle& positions, const py::handle& radii);

/// JSON from the library (fill_report.hpp) as Python dicts and lists.
py::object to_python(const nlohmann::ordered_json& json);

/// Two numbers from a pair or the command line's "A,B" text; else an error
/// naming `what`.
std::pair<double, double> number_pair(const py::handle& value, const std::string& what);

}  // namespace pfill::python

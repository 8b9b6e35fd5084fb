#pragma once
// Conversions from Python values shared by every kit's bindings.
#include <fmt/format.h>
#include <pybind11/pybind11.h>

#include <cmath>

#include "fabkit/core/frame.h"

namespace fabkit::python {

namespace py = pybind11;

/// [x, y, z] from a Python sequence of three finite numbers; TypeError/ValueError otherwise.
inline Vec3 to_vec3(const py::handle& h, const char* what) {
  if (py::isinstance<py::str>(h) || !py::isinstance<py::sequence>(h) ||
      py::len(py::reinterpret_borrow<py::sequence>(h)) != 3) {
    throw py::type_error(fmt::format("{} must be a list of three numbers, like [0, 0, 100]", what));
  }
  const auto seq = py::reinterpret_borrow<py::sequence>(h);
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    try {
      v[i] = seq[static_cast<std::size_t>(i)].cast<double>();
    } catch (const py::cast_error&) {
      throw py::type_error(fmt::format("{} must contain numbers", what));
    }
    if (!std::isfinite(v[i])) throw py::value_error(fmt::format("{} has a non-finite value", what));
  }
  return v;
}

}  // namespace fabkit::python

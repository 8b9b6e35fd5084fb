#pragma once
// Conversions from Python values shared by every kit's bindings.
#include <fmt/format.h>
#include <pybind11/pybind11.h>

#include <chrono>
#include <cmath>
#include <optional>

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

/// Seconds of a `time_limit=` argument: None (no limit) or a number in (0, 1e6];
/// TypeError/ValueError otherwise.
inline std::optional<double> time_limit_seconds(const py::handle& time_limit) {
  if (time_limit.is_none()) return std::nullopt;
  if (py::isinstance<py::bool_>(time_limit) ||
      !(py::isinstance<py::int_>(time_limit) || py::isinstance<py::float_>(time_limit))) {
    throw py::type_error("time_limit must be a number of seconds (or None)");
  }
  const double s = time_limit.cast<double>();
  if (!(s > 0) || !(s <= 1e6)) {
    throw py::value_error(fmt::format("time_limit must be between 0 and 1e6 seconds, not {}", s));
  }
  return s;
}

/// The deadline `time_limit` seconds from now, or none.
inline std::optional<std::chrono::steady_clock::time_point> deadline_from(
    const py::handle& time_limit) {
  const auto s = time_limit_seconds(time_limit);
  if (!s) return std::nullopt;
  return std::chrono::steady_clock::now() +
         std::chrono::microseconds(static_cast<long long>(*s * 1e6));
}

}  // namespace fabkit::python

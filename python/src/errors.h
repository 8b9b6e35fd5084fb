#pragma once
// fabkit's Python exceptions, one hierarchy for every kit: fabkit.Error and below it one class
// per diagnostic class (core/diagnostics.h). Every binding file raises through these.
#include <pybind11/pybind11.h>

#include <string>

#include "fabkit/core/diagnostics.h"

namespace fabkit::python {

/// The exception types (set by bind_errors).
struct Errors {
  PyObject* error = nullptr;       ///< fabkit.Error
  PyObject* input = nullptr;       ///< fabkit.InputError (also a ValueError)
  PyObject* infeasible = nullptr;  ///< fabkit.InfeasibleError
  PyObject* connect = nullptr;     ///< fabkit.ConnectError (an InfeasibleError)
  PyObject* time_limit = nullptr;  ///< fabkit.TimeLimitError (also a TimeoutError)
  PyObject* write = nullptr;       ///< fabkit.WriteError (also an OSError)
};
const Errors& errors();

/// Creates the exception types in `m` (the _fabkit module).
void bind_errors(pybind11::module_& m);

/// Raises `type` with `message`.
[[noreturn]] void raise(PyObject* type, const std::string& message);
/// Raises the exception of the class that decides `d`, with its error messages.
[[noreturn]] void raise_diagnostics(const Diagnostics& d);
/// The error messages of `d`, one per line.
std::string messages(const Diagnostics& d);

}  // namespace fabkit::python

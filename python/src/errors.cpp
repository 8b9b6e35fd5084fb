#include "errors.h"

namespace fabkit::python {
namespace {
Errors g_errors;
}  // namespace

const Errors& errors() {
  return g_errors;
}

void bind_errors(pybind11::module_& m) {
  namespace py = pybind11;
  auto make = [&](const char* name, PyObject* base) {
    PyObject* type = PyErr_NewException((std::string("fabkit.") + name).c_str(), base, nullptr);
    m.attr(name) = py::handle(type);
    return type;
  };
  auto bases = [](PyObject* a, PyObject* b) {
    return py::make_tuple(py::handle(a), py::handle(b)).release().ptr();
  };
  g_errors.error = make("Error", PyExc_Exception);
  g_errors.input = make("InputError", bases(g_errors.error, PyExc_ValueError));
  g_errors.infeasible = make("InfeasibleError", g_errors.error);
  g_errors.connect = make("ConnectError", g_errors.infeasible);
  g_errors.time_limit = make("TimeLimitError", bases(g_errors.error, PyExc_TimeoutError));
  g_errors.write = make("WriteError", bases(g_errors.error, PyExc_OSError));
}

void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw pybind11::error_already_set();
}

std::string messages(const Diagnostics& d) {
  std::string out;
  for (const Diagnostic& x : d) {
    if (x.severity != Severity::kError) continue;
    if (!out.empty()) out += "\n";
    out += x.where.known() && x.where.line > 0 ? x.format() : x.message;
  }
  return out;
}

void raise_diagnostics(const Diagnostics& d) {
  PyObject* type = g_errors.error;
  switch (d.deciding_class().value_or(DiagnosticClass::kInternal)) {
    case DiagnosticClass::kInput:
      type = g_errors.input;
      break;
    case DiagnosticClass::kInfeasible:
      type = g_errors.infeasible;
      break;
    case DiagnosticClass::kTimeout:
      type = g_errors.time_limit;
      break;
    case DiagnosticClass::kIo:
      type = g_errors.write;
      break;
    default:
      break;
  }
  raise(type, messages(d));
}

}  // namespace fabkit::python

#include "construction_guard.h"

#include <string>

namespace fabkit::python {
namespace py = pybind11;

namespace {

bool is_bound_class(const py::handle& obj) {
  if (!PyType_Check(obj.ptr())) return false;
  if (PyType_IsSubtype(reinterpret_cast<PyTypeObject*>(obj.ptr()),
                       reinterpret_cast<PyTypeObject*>(PyExc_BaseException))) {
    return false;
  }
  // pybind11's classes derive from pybind11_object; plain Python types do not.
  const py::object mro = obj.attr("__mro__");
  for (const py::handle& base : mro) {
    if (py::str(base.attr("__name__")).cast<std::string>() == "pybind11_object") return true;
  }
  return false;
}

void guard_class(const py::object& cls) {
  const std::string name = py::str(cls.attr("__qualname__")).cast<std::string>();
  const py::dict own = cls.attr("__dict__");
  if (own.contains("__new__")) return;  // already guarded
  // pybind11's constructors (py::init) are instance methods; a class without one has only the
  // slot wrapper that raises "No constructor defined!".
  const bool has_constructor =
      own.contains("__init__") && PyInstanceMethod_Check(py::object(own["__init__"]).ptr());
  if (!has_constructor) {
    // No constructor: instances come only from fabkit's functions.
    cls.attr("__new__") = py::staticmethod(py::cpp_function(
        [name](const py::handle&, const py::args&, const py::kwargs&) -> py::object {
          throw py::type_error("fabkit." + name +
                               " cannot be created directly; fabkit's functions return one");
        },
        py::name("__new__")));
    return;
  }
  // A constructor: run it inside __new__, so an instance never exists unconstructed.
  const py::object base_new = cls.attr("__new__");
  const py::object real_init = cls.attr("__init__");
  cls.attr("_construct") = real_init;
  cls.attr("__new__") = py::staticmethod(py::cpp_function(
      [base_new, real_init](const py::object& type, const py::args& args, const py::kwargs& kw) {
        py::object self = base_new(type);
        real_init(self, *args, **kw);
        return self;
      },
      py::name("__new__")));
  cls.attr("__init__") =
      py::cpp_function([](const py::handle&, const py::args&, const py::kwargs&) {},
                       py::name("__init__"),
                       py::is_method(cls));
}

void guard_module(const py::module_& m, int depth) {
  const py::dict names = m.attr("__dict__");
  for (const auto& [key, value] : names) {
    if (is_bound_class(value)) {
      guard_class(py::reinterpret_borrow<py::object>(value));
    } else if (depth < 3 && PyModule_Check(value.ptr())) {
      guard_module(py::reinterpret_borrow<py::module_>(value), depth + 1);
    }
  }
}

}  // namespace

void guard_construction(py::module_ m) {
  guard_module(m, 0);
}

}  // namespace fabkit::python

// fabkit._fabkit: the C++ library as seen from Python. Each kit binds into its own submodule
// (_fabkit.hacks, ...) from its own file; the natural, paper-style API lives in the pure-Python
// fabkit/<kit>.py on top. Every function converts arguments, calls the library and turns
// diagnostics into Python exceptions (never a crash of the interpreter).
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "convert.h"
#include "errors.h"
#include "fabkit/core/frame.h"
#include "kits.h"

namespace py = pybind11;
using namespace fabkit;

PYBIND11_MODULE(_fabkit, m) {
  m.doc() = "fabkit's C++ engine (use fabkit.hacks for the FabHaL language)";
  python::bind_errors(m);

  py::class_<Frame>(m, "Frame", "A placement: pos in mm, rot = Euler angles [a, b, c] in degrees")
      .def(py::init([](const py::object& pos, const py::object& rot) {
             Frame f;
             if (!pos.is_none()) f.pos = python::to_vec3(pos, "Frame pos");
             if (!rot.is_none()) f.rot = python::to_vec3(rot, "Frame rot");
             return f;
           }),
           py::arg("pos") = py::none(),
           py::arg("rot") = py::none())
      .def_property(
          "pos",
          [](const Frame& f) {
            return std::vector<double>{f.pos.x(), f.pos.y(), f.pos.z()};
          },
          [](Frame& f, const py::object& v) { f.pos = python::to_vec3(v, "pos"); })
      .def_property(
          "rot",
          [](const Frame& f) {
            return std::vector<double>{f.rot.x(), f.rot.y(), f.rot.z()};
          },
          [](Frame& f, const py::object& v) { f.rot = python::to_vec3(v, "rot"); })
      .def("__repr__", [](const Frame& f) {
        return fmt::format("Frame([{:g}, {:g}, {:g}], [{:g}, {:g}, {:g}])",
                           f.pos.x(),
                           f.pos.y(),
                           f.pos.z(),
                           f.rot.x(),
                           f.rot.y(),
                           f.rot.z());
      });

  python::bind_hacks(m.def_submodule("hacks", "the FabHaL kit"));
  python::bind_flatpack(m.def_submodule("flatpack", "the flat-pack furniture kit"));
  python::bind_rods(m.def_submodule("rods", "the RodSteward kit"));
  python::bind_templates(m.def_submodule("templates", "the design and fabrication by example kit"));
}

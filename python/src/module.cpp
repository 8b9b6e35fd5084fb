// fabkit._fabkit: the C++ library as seen from Python. Each kit binds into its own submodule
// (_fabkit.hacks, ...) from its own file; the natural, paper-style API lives in the pure-Python
// fabkit/<kit>.py on top. Every function converts arguments, calls the library and turns
// diagnostics into Python exceptions (never a crash of the interpreter).
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "construction_guard.h"
#include "convert.h"
#include "errors.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/frame.h"
#include "fabkit/core/text.h"
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

  // Files the pure-Python layer reads and writes go through the library's readers and writers:
  // regular files only, at most 16 MiB, checked UTF-8; written atomically, never through a
  // FIFO, a device or a link out of its directory.
  m.def(
      "read_text_file",
      [](const std::filesystem::path& path, const std::string& what) {
        Diagnostics d;
        std::optional<std::string> text;
        {
          py::gil_scoped_release release;
          text = read_input_file(path, what, d);
        }
        if (!text) python::raise_diagnostics(d);
        if (!is_valid_utf8(*text)) {
          d.error(codes::kMalformedInput,
                  fmt::format("{} '{}' is not UTF-8 text", what, excerpt(path.string(), 200)),
                  SourceLocation{path.string(), 0, 0});
          python::raise_diagnostics(d);
        }
        return *text;
      },
      py::arg("path"),
      py::arg("what") = "file");
  m.def(
      "write_text_file",
      [](const std::filesystem::path& path, const std::string& text) {
        Diagnostics d;
        bool ok = false;
        {
          py::gil_scoped_release release;
          ok = write_file_atomically(path, text, d);
        }
        if (!ok) python::raise_diagnostics(d);
      },
      py::arg("path"),
      py::arg("text"));

  python::bind_hacks(m.def_submodule("hacks", "the FabHaL kit"));
  python::bind_flatpack(m.def_submodule("flatpack", "the flat-pack furniture kit"));
  python::bind_rods(m.def_submodule("rods", "the RodSteward kit"));
  python::bind_templates(m.def_submodule("templates", "the design and fabrication by example kit"));
  python::guard_construction(m);
}

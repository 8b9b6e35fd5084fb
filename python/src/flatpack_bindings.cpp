// The flatpack kit in Python (_fabkit.flatpack); fabkit/flatpack.py builds the paper's
// Component API on it. Designs cross as design-file text (the one reader parses both).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "convert.h"
#include "errors.h"
#include "fabkit/core/json.h"
#include "fabkit/flatpack/build.h"
#include "fabkit/flatpack/design_file.h"
#include "kits.h"

namespace py = pybind11;
using namespace fabkit;
using namespace fabkit::flatpack;

namespace {

Design read(const std::string& text, const std::string& name, const std::string& base_dir) {
  Diagnostics d;
  Design design = load_design_text(text, name, d, base_dir);
  if (d.has_errors()) python::raise_diagnostics(d);
  return design;
}

py::object to_python(const Json& j) {
  return py::module_::import("json").attr("loads")(dump_json(j));
}

}  // namespace

void fabkit::python::bind_flatpack(py::module_ m) {
  m.def(
      "check",
      [](const std::string& text,
         const std::string& name,
         const std::string& base_dir,
         const py::object& time_limit) {
        const Design design = read(text, name, base_dir);
        CheckOptions o;
        o.deadline = python::deadline_from(time_limit);
        BuildSummary s;
        {
          py::gil_scoped_release release;
          s.analysis = check(design, o);
        }
        s.diagnostics = s.analysis.diagnostics;
        s.timings = s.analysis.timings;
        if (!s.analysis.placed || s.diagnostics.has_errors_of(DiagnosticClass::kTimeout)) {
          python::raise_diagnostics(s.diagnostics);
        }
        return to_python(report_json(s));
      },
      py::arg("text"),
      py::arg("name") = "design.yaml",
      py::arg("base_dir") = "",
      py::arg("time_limit") = py::none(),
      "Checks a design (design-file text): placement, joints, warnings; returns report.json's "
      "content.");
  m.def(
      "build",
      [](const std::string& text,
         const std::string& name,
         const std::string& base_dir,
         const std::string& output_dir,
         const py::object& time_limit) {
        const Design design = read(text, name, base_dir);
        BuildOptions o;
        o.output_dir = output_dir;
        o.deadline = python::deadline_from(time_limit);
        BuildSummary s;
        {
          py::gil_scoped_release release;
          s = build(design, o);
        }
        if (s.termination != Termination::kBuilt) python::raise_diagnostics(s.diagnostics);
        return to_python(report_json(s));
      },
      py::arg("text"),
      py::arg("name"),
      py::arg("base_dir"),
      py::arg("output_dir"),
      py::arg("time_limit") = py::none(),
      "Builds every output of a design into output_dir; returns report.json's content.");
  m.def(
      "to_yaml",
      [](const std::string& text, const std::string& name) {
        return to_yaml(read(text, name, ""));
      },
      py::arg("text"),
      py::arg("name") = "design.yaml",
      "The design as a tidy flatpack/1 design file.");
}

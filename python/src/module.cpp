// fabkit._fabkit: the C++ library as seen from Python. The natural, paper-style API lives in
// fabkit/hacks.py on top of this; here every function converts arguments, calls the library,
// and turns diagnostics into Python exceptions (never a crash of the interpreter).
#include <fmt/format.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <thread>

#include "fabkit/core/file_io.h"
#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/parts_library.h"
#include "fabkit/hacks/solution_export.h"
#include "fabkit/hacks/solve.h"

namespace py = pybind11;
using namespace fabkit;
using namespace fabkit::hacks;

namespace {

// Raised for rejected connects and infeasible designs; fabkit/__init__.py re-exports it with
// the base class fabkit.Error.
PyObject* g_error = nullptr;
PyObject* g_connect_error = nullptr;

[[noreturn]] void raise(PyObject* type, const std::string& message) {
  PyErr_SetString(type, message.c_str());
  throw py::error_already_set();
}

std::string messages(const Diagnostics& d) {
  std::string out;
  for (const Diagnostic& x : d) {
    if (x.severity != Severity::kError) continue;
    if (!out.empty()) out += "\n";
    out += x.message;
  }
  return out;
}

Vec3 to_vec3(const py::handle& h, const char* what) {
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

ParamValues to_params(const py::object& o, const std::string& who) {
  ParamValues values;
  if (o.is_none()) return values;
  if (!py::isinstance<py::dict>(o)) {
    throw py::type_error(fmt::format("{} takes a dict of parameters, like {{\"radius\": 5}}", who));
  }
  for (auto [k, v] : py::reinterpret_borrow<py::dict>(o)) {
    if (!py::isinstance<py::str>(k))
      throw py::type_error(fmt::format("{}: parameter names are strings", who));
    try {
      values[k.cast<std::string>()] = v.cast<double>();
    } catch (const py::cast_error&) {
      throw py::type_error(
          fmt::format("{}: parameter '{}' must be a number", who, k.cast<std::string>()));
    }
  }
  return values;
}

// A loose primitive (Surface({...}) before it belongs to a part).
struct LoosePrimitive {
  Primitive primitive;
};

LoosePrimitive make_primitive(const std::string& type_name, const py::object& params) {
  const auto type = primitive_type_from_string(type_name);
  if (!type) throw py::value_error(fmt::format("unknown primitive type '{}'", type_name));
  PrimitiveShape shape;
  // Defaults of the reference (§2.2) for sizes left out.
  switch (*type) {
    case PrimitiveType::kRod:
      shape.radius = 0.5;
      shape.length = 10;
      break;
    case PrimitiveType::kTube:
      shape.inner_radius = 0.5;
      shape.thickness = 0.1;
      shape.length = 10;
      break;
    case PrimitiveType::kEdge:
      shape.width = shape.length = shape.height = 10;
      break;
    case PrimitiveType::kSurface:
      shape.width = shape.length = 100;
      break;
    default:
      break;
  }
  Primitive p = Primitive::make(std::string(to_string(*type)), *type, shape);
  const std::string who = std::string(to_string(*type));
  for (const auto& [key, value] : to_params(params, who)) {
    if (key == "is_open") {
      p.is_open = value != 0;
      if (p.type == PrimitiveType::kRod || p.type == PrimitiveType::kHook)
        p.open_for_connect = p.is_open;
      continue;
    }
    if (key == "open_for_connect") {
      p.open_for_connect = value != 0;
      continue;
    }
    double* field = shape_field(p.shape, key);
    const auto names = shape_field_names(*type);
    if (!field || std::find(names.begin(), names.end(), key) == names.end()) {
      std::string list;
      for (auto n : names) list += (list.empty() ? "" : ", ") + std::string(n);
      throw py::value_error(
          fmt::format("{}: unknown parameter '{}' (a {} takes {})", who, key, who, list));
    }
    *field = value;
  }
  Diagnostics d;
  p.validate(who, d);
  if (d.has_errors()) throw py::value_error(messages(d));
  return {p};
}

std::shared_ptr<Part> make_part(const std::string& name, const py::object& params) {
  Diagnostics d;
  auto part = PartsLibrary::builtin().make(name, to_params(params, name), d);
  if (!part) throw py::value_error(messages(d));
  return part;
}

std::shared_ptr<Part> environment_from_primitives(
    const std::vector<std::pair<std::string, LoosePrimitive>>& items) {
  if (items.empty()) throw py::value_error("Environment({...}) needs at least one entry");
  std::vector<Primitive> prims;
  for (const auto& [name, loose] : items) {
    Primitive p = loose.primitive;
    p.name = name;
    prims.push_back(p);
  }
  return std::make_shared<Part>(make_primitive_part(std::move(prims)));
}

PrimitiveRef primitive_of(const std::shared_ptr<Part>& part, const std::string& name) {
  PrimitiveRef ref(part, name);
  if (!ref.valid()) {
    throw py::attribute_error(fmt::format(
        "{} has no primitive '{}' (it has {})", part->type_name, name, part->primitive_list()));
  }
  return ref;
}

Frame to_frame(const py::object& o) {
  if (o.is_none()) return Frame();
  try {
    return o.cast<Frame>();
  } catch (const py::cast_error&) {
    throw py::type_error("expected a Frame, like Frame([0, 0, 100], [0, 0, 90])");
  }
}

// The reference's target is a part's first primitive or a named one.
PrimitiveRef to_ref(const py::object& o, const char* what) {
  if (py::isinstance<PrimitiveRef>(o)) return o.cast<PrimitiveRef>();
  if (py::isinstance<Part>(o)) {
    auto part = o.cast<std::shared_ptr<Part>>();
    return PrimitiveRef(part, 0);
  }
  throw py::type_error(fmt::format("{} takes a primitive such as part.hook1 (or a part), not {}",
                                   what,
                                   py::str(py::type::of(o).attr("__name__")).cast<std::string>()));
}

// A solve's result, with the assembly it came from (for the exporters).
struct Solved {
  std::shared_ptr<const Assembly> assembly;
  SolveResult result;
};

Solved solve_one(const Assembly& a) {
  Solved s;
  s.assembly = std::make_shared<const Assembly>(a);
  s.result = solve(*s.assembly);
  return s;
}

void export_or_raise(const Solved& s, const std::function<bool(Diagnostics&)>& f) {
  Diagnostics d;
  if (!f(d)) raise(g_error, messages(d));
}

}  // namespace

PYBIND11_MODULE(_fabkit, m) {
  m.doc() = "fabkit's C++ engine (use fabkit.hacks for the FabHaL language)";
  g_error = PyErr_NewException("fabkit.Error", PyExc_Exception, nullptr);
  g_connect_error = PyErr_NewException("fabkit.ConnectError", g_error, nullptr);
  m.attr("Error") = py::handle(g_error);
  m.attr("ConnectError") = py::handle(g_connect_error);

  py::class_<Frame>(m, "Frame", "A placement: pos in mm, rot = Euler angles [a, b, c] in degrees")
      .def(py::init([](const py::object& pos, const py::object& rot) {
             Frame f;
             if (!pos.is_none()) f.pos = to_vec3(pos, "Frame pos");
             if (!rot.is_none()) f.rot = to_vec3(rot, "Frame rot");
             return f;
           }),
           py::arg("pos") = py::none(),
           py::arg("rot") = py::none())
      .def_property(
          "pos",
          [](const Frame& f) {
            return std::vector<double>{f.pos.x(), f.pos.y(), f.pos.z()};
          },
          [](Frame& f, const py::object& v) { f.pos = to_vec3(v, "pos"); })
      .def_property(
          "rot",
          [](const Frame& f) {
            return std::vector<double>{f.rot.x(), f.rot.y(), f.rot.z()};
          },
          [](Frame& f, const py::object& v) { f.rot = to_vec3(v, "rot"); })
      .def("__repr__", [](const Frame& f) {
        return fmt::format("Frame([{:g}, {:g}, {:g}], [{:g}, {:g}, {:g}])",
                           f.pos.x(),
                           f.pos.y(),
                           f.pos.z(),
                           f.rot.x(),
                           f.rot.y(),
                           f.rot.z());
      });

  py::class_<LoosePrimitive>(m, "Primitive", "A connector primitive not yet part of a part")
      .def_property_readonly(
          "type", [](const LoosePrimitive& p) { return std::string(to_string(p.primitive.type)); })
      .def("__repr__", [](const LoosePrimitive& p) { return p.primitive.describe(); });
  m.def("make_primitive", &make_primitive, py::arg("type"), py::arg("params") = py::none());

  py::class_<PrimitiveRef>(m, "PrimitiveRef", "A primitive of a part, e.g. part.hook1")
      .def_property_readonly("name", [](const PrimitiveRef& r) { return r.primitive().name; })
      .def_property_readonly("part", [](const PrimitiveRef& r) { return r.part; })
      .def_property_readonly(
          "type", [](const PrimitiveRef& r) { return std::string(to_string(r.primitive().type)); })
      .def("__repr__", [](const PrimitiveRef& r) {
        return fmt::format(
            "<{}.{}: {}>", r.part->type_name, r.primitive().name, r.primitive().describe());
      });

  py::class_<Part, std::shared_ptr<Part>>(m, "Part", "A part from the library")
      .def_property_readonly("type_name", [](const Part& p) { return p.type_name; })
      .def_property_readonly("mass", [](const Part& p) { return p.mass; })
      .def_property_readonly("primitives",
                             [](const Part& p) {
                               std::vector<std::string> names;
                               for (const Primitive& x : p.primitives) names.push_back(x.name);
                               return names;
                             })
      .def("primitive", &primitive_of)
      .def("__getattr__",
           [](const std::shared_ptr<Part>& p, const std::string& name) {
             if (name.rfind("__", 0) == 0) throw py::attribute_error(name);
             return primitive_of(p, name);
           })
      .def("__repr__", [](const Part& p) {
        return fmt::format("<{} with {}>", p.type_name, p.primitive_list());
      });

  m.def("make_part", &make_part, py::arg("name"), py::arg("params") = py::none());
  m.def("part_names", [] {
    std::vector<std::string> names;
    for (const PartGenerator& g : PartsLibrary::builtin().generators()) {
      names.push_back(g.name);
      for (const auto& a : g.aliases) names.push_back(a);
    }
    return names;
  });
  m.def("environment_from_primitives", &environment_from_primitives);

  py::class_<Assembly>(m, "Assembly")
      .def(py::init<>())
      .def("add",
           [](Assembly& a, const py::object& env, const py::object& frame) {
             ConnectReport r;
             if (py::isinstance<PrimitiveRef>(env)) {
               r = a.add(env.cast<PrimitiveRef>(), to_frame(frame));
             } else if (py::isinstance<Part>(env)) {
               r = a.add(env.cast<std::shared_ptr<Part>>(), to_frame(frame));
             } else {
               throw py::type_error(
                   "add() takes an environment part (or one of its primitives) and a Frame");
             }
             if (!r.accepted) raise(g_error, messages(r.diagnostics));
           })
      .def(
          "connect",
          [](Assembly& a,
             const py::object& p1,
             const py::object& p2,
             const std::string& alignment,
             bool is_fixed) {
            if (!py::isinstance<PrimitiveRef>(p1) || !py::isinstance<PrimitiveRef>(p2)) {
              const py::object& bad = py::isinstance<PrimitiveRef>(p1) ? p2 : p1;
              if (py::isinstance<Part>(bad)) {
                auto part = bad.cast<std::shared_ptr<Part>>();
                throw py::type_error(fmt::format(
                    "connect() takes two primitives; {} is a part: name one of its primitives ({})",
                    part->type_name,
                    part->primitive_list()));
              }
              throw py::type_error(
                  "connect() takes two primitives, such as eyehook.hook and basket.hook");
            }
            const auto choice = alignment_choice_from_string(alignment);
            if (!choice) {
              throw py::value_error(
                  fmt::format("alignment must be \"default\" or \"flip\", not \"{}\"", alignment));
            }
            ConnectOptions o;
            o.alignment = *choice;
            o.fixed = is_fixed;
            const ConnectReport r = a.connect(p1.cast<PrimitiveRef>(), p2.cast<PrimitiveRef>(), o);
            if (!r.accepted) raise(g_connect_error, messages(r.diagnostics));
            return r.closes_cycle;
          },
          py::arg("a"),
          py::arg("b"),
          py::arg("alignment") = "default",
          py::arg("is_fixed") = false)
      .def("end_with",
           [](Assembly& a, const py::object& target, const py::object& frame) {
             const Diagnostics d =
                 py::isinstance<Part>(target)
                     ? a.end_with(target.cast<std::shared_ptr<Part>>(), to_frame(frame))
                     : a.end_with(to_ref(target, "end_with()"), to_frame(frame));
             if (d.has_errors()) raise(g_error, messages(d));
           })
      .def_property_readonly("part_count", &Assembly::part_count)
      .def("solve", [](const Assembly& a) {
        py::gil_scoped_release release;
        return solve_one(a);
      });

  py::class_<Solved>(m, "SolveResult")
      .def_property_readonly("stable", [](const Solved& s) { return s.result.stable; })
      .def_property_readonly("feasible", [](const Solved& s) { return s.result.feasible; })
      .def_property_readonly("target_error",
                             [](const Solved& s) {
                               return py::make_tuple(s.result.target.position_mm,
                                                     s.result.target.rotation_deg);
                             })
      .def_property_readonly("step1_target_error",
                             [](const Solved& s) {
                               return py::make_tuple(s.result.target_step1.position_mm,
                                                     s.result.target_step1.rotation_deg);
                             })
      .def_property_readonly("frames",
                             [](const Solved& s) {
                               py::dict d;
                               for (const SolvedPart& p : s.result.parts)
                                 d[py::str(p.name)] = p.frame.normalized();
                               return d;
                             })
      .def_property_readonly("part_types",
                             [](const Solved& s) {
                               std::vector<std::string> t;
                               for (const SolvedPart& p : s.result.parts) t.push_back(p.type);
                               return t;
                             })
      .def_property_readonly("slipping",
                             [](const Solved& s) {
                               std::vector<std::string> out;
                               for (const Slip& x : s.result.slips) out.push_back(x.message);
                               return out;
                             })
      .def_property_readonly("timings_ms",
                             [](const Solved& s) {
                               py::dict d;
                               for (const StageTiming& t : s.result.timings)
                                 d[py::str(t.stage)] = t.milliseconds;
                               return d;
                             })
      .def_property_readonly("message", [](const Solved& s) { return s.result.message; })
      .def("summary", [](const Solved& s) { return s.result.summary(); })
      .def(
          "to_json",
          [](const Solved& s, const std::string& name) {
            return result_json(*s.assembly, s.result, name);
          },
          py::arg("design_name") = "")
      .def(
          "save_json",
          [](const Solved& s, const std::filesystem::path& path, const std::string& name) {
            export_or_raise(s, [&](Diagnostics& d) {
              return write_file_atomically(path, result_json(*s.assembly, s.result, name), d);
            });
          },
          py::arg("path"),
          py::arg("design_name") = "")
      .def("save_glb",
           [](const Solved& s, const std::filesystem::path& path) {
             export_or_raise(s, [&](Diagnostics& d) {
               return write_glb(solution_scene(*s.assembly, s.result), path, d);
             });
           })
      .def(
          "save_all",
          [](const Solved& s, const std::filesystem::path& dir, const std::string& name) {
            export_or_raise(s, [&](Diagnostics& d) {
              ExportOptions o;
              o.design_name = name;
              return export_solution(*s.assembly, s.result, dir, d, o);
            });
          },
          py::arg("directory"),
          py::arg("design_name") = "")
      .def("__repr__", [](const Solved& s) {
        return fmt::format("<SolveResult {} target error {:.2f} mm, {:.2f}°>",
                           s.result.message,
                           s.result.target.position_mm,
                           s.result.target.rotation_deg);
      });

  // Many assemblies at once, on C++ threads with the GIL released; draws a progress bar on
  // stderr when asked.
  m.def(
      "solve_many",
      [](const std::vector<Assembly*>& assemblies, int threads, bool progress) {
        for (const Assembly* a : assemblies) {
          if (!a) throw py::type_error("solve_many() takes a list of Assembly objects");
        }
        std::vector<Solved> results(assemblies.size());
        {
          py::gil_scoped_release release;
          const int n = static_cast<int>(assemblies.size());
          const int workers =
              std::max(1,
                       std::min(threads > 0 ? threads
                                            : static_cast<int>(std::thread::hardware_concurrency()),
                                n));
          std::atomic<int> next{0};
          std::atomic<int> done{0};
          std::vector<std::thread> pool;
          for (int w = 0; w < workers; ++w) {
            pool.emplace_back([&] {
              for (int i = next++; i < n; i = next++) {
                results[static_cast<std::size_t>(i)] =
                    solve_one(*assemblies[static_cast<std::size_t>(i)]);
                ++done;
              }
            });
          }
          auto draw = [&](int k) {
            const int width = 30;
            const int filled = n ? k * width / n : width;
            std::fprintf(stderr,
                         "\rsolving [%s%s] %d/%d",
                         std::string(static_cast<std::size_t>(filled), '#').c_str(),
                         std::string(static_cast<std::size_t>(width - filled), ' ').c_str(),
                         k,
                         n);
            std::fflush(stderr);
          };
          if (progress) {
            while (done.load() < n) {
              draw(done.load());
              std::this_thread::sleep_for(std::chrono::milliseconds(50));
            }
            draw(n);
            std::fprintf(stderr, "\n");
          }
          for (std::thread& t : pool) t.join();
        }
        return results;
      },
      py::arg("assemblies"),
      py::arg("threads") = 0,
      py::arg("progress") = false);
}

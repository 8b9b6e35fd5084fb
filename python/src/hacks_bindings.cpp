// The hacks kit in Python (_fabkit.hacks; fabkit/hacks.py builds the paper's API on it).
#include <fmt/format.h>
#include <pybind11/functional.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <thread>

#include "convert.h"
#include "errors.h"
#include "fabkit/core/file_io.h"
#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/deadline.h"
#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "fabkit/hacks/parts_library.h"
#include "fabkit/hacks/primitive_spec.h"
#include "fabkit/hacks/solution_export.h"
#include "fabkit/hacks/solve.h"
#include "kits.h"

namespace py = pybind11;
using namespace fabkit;
using namespace fabkit::hacks;
using fabkit::python::messages;
using fabkit::python::raise;
using fabkit::python::to_vec3;

namespace {

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

// A Python value as a YAML node, so the one primitive-spec parser reads Python specs too.
YAML::Node to_yaml(const py::handle& h, const std::string& where) {
  if (py::isinstance<py::bool_>(h)) return YAML::Node(h.cast<bool>() ? "true" : "false");
  if (py::isinstance<py::int_>(h) || py::isinstance<py::float_>(h)) {
    return YAML::Node(fmt::format("{:.17g}", h.cast<double>()));
  }
  if (py::isinstance<py::str>(h)) {
    throw py::type_error(
        fmt::format("{}: sizes and flags are numbers and booleans, not the text "
                    "'{}'",
                    where,
                    h.cast<std::string>()));
  }
  if (py::isinstance<py::dict>(h)) {
    YAML::Node map(YAML::NodeType::Map);
    for (auto [k, v] : py::reinterpret_borrow<py::dict>(h)) {
      if (!py::isinstance<py::str>(k)) throw py::type_error(where + ": keys must be strings");
      map[k.cast<std::string>()] = to_yaml(v, where);
    }
    return map;
  }
  if (py::isinstance<Frame>(h)) {
    const Frame f = h.cast<Frame>();
    YAML::Node map(YAML::NodeType::Map);
    for (int i = 0; i < 3; ++i) {
      map["pos"].push_back(fmt::format("{:.17g}", f.pos[i]));
      map["rot"].push_back(fmt::format("{:.17g}", f.rot[i]));
    }
    return map;
  }
  if (py::isinstance<py::sequence>(h)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    for (auto item : py::reinterpret_borrow<py::sequence>(h)) seq.push_back(to_yaml(item, where));
    return seq;
  }
  throw py::type_error(fmt::format("{}: values must be numbers, booleans, lists or a Frame, not {}",
                                   where,
                                   py::str(py::type::of(h).attr("__name__")).cast<std::string>()));
}

LoosePrimitive make_primitive(const std::string& type_name, const py::object& params) {
  if (!params.is_none() && !py::isinstance<py::dict>(params)) {
    throw py::type_error(
        fmt::format("{} takes a dict of sizes, like {{\"radius\": 5}}", type_name));
  }
  YAML::Node spec = params.is_none() ? YAML::Node(YAML::NodeType::Map) : to_yaml(params, type_name);
  spec["type"] = type_name;
  Diagnostics d;
  YamlReader in(type_name, d);
  PrimitiveSpecOptions options;
  options.reference_defaults = true;
  auto p = read_primitive_spec(in, spec, "", type_name, options);
  if (!p) python::raise_diagnostics(d);
  p->name = std::string(to_string(p->type));
  return {*p};
}

// The parts Python programs build from: the built-in library plus part files they loaded.
PartsLibrary& library() {
  static PartsLibrary lib = PartsLibrary::builtin();
  return lib;
}

std::shared_ptr<Part> make_part(const std::string& name, const py::object& params) {
  Diagnostics d;
  auto part = library().make(name, to_params(params, name), d);
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
    return PrimitiveRef(part, PrimitiveId{0});
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

Solved solve_one(const Assembly& a, const SolveOptions& options = {}) {
  Solved s;
  // As design files are: in the canonical order of its connects (Assembly::in_canonical_order).
  s.assembly = std::make_shared<const Assembly>(a.in_canonical_order(options.deadline));
  s.result = solve(*s.assembly, options);
  return s;
}

void export_or_raise(const Solved& s, const std::function<bool(Diagnostics&)>& f) {
  Diagnostics d;
  if (!f(d)) python::raise_diagnostics(d);
}

}  // namespace

void fabkit::python::bind_hacks(py::module_ m) {
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
      .def(
          "primitive_spec",
          [](const Part& p, const std::string& name) {
            const PrimitiveId id = p.find_primitive(name);
            if (!id.valid()) {
              throw py::attribute_error(fmt::format(
                  "{} has no primitive '{}' (it has {})", p.type_name, name, p.primitive_list()));
            }
            const Primitive& x = p.primitive(id);
            py::dict spec;
            spec["type"] = std::string(to_string(x.type));
            for (std::string_view f : shape_field_names(x.type)) {
              spec[py::str(std::string(f))] = shape_field_value(x.shape, f);
            }
            spec["pos"] = std::vector<double>{x.frame.pos.x(), x.frame.pos.y(), x.frame.pos.z()};
            spec["rot"] = std::vector<double>{x.frame.rot.x(), x.frame.rot.y(), x.frame.rot.z()};
            spec["flex"] = x.flex;
            spec["centerline"] = x.centerline;
            spec["is_open"] = x.is_open;
            spec["open_for_connect"] = x.open_for_connect;
            spec["open_ends"] = std::vector<bool>{x.open_ends[0], x.open_ends[1]};
            spec["theta_range"] =
                x.theta_range
                    ? py::cast(std::vector<double>(x.theta_range->begin(), x.theta_range->end()))
                    : py::none();
            spec["phi_range"] =
                x.phi_range
                    ? py::cast(std::vector<double>(x.phi_range->begin(), x.phi_range->end()))
                    : py::none();
            return spec;
          },
          "Everything about one primitive: type, sizes, frame, flags (for tools and tests).")
      .def("__getattr__",
           [](const std::shared_ptr<Part>& p, const std::string& name) {
             if (name.rfind("__", 0) == 0) throw py::attribute_error(name);
             return primitive_of(p, name);
           })
      .def("__repr__", [](const Part& p) {
        return fmt::format("<{} with {}>", p.type_name, p.primitive_list());
      });

  m.def("make_part", &make_part, py::arg("name"), py::arg("params") = py::none());
  m.def(
      "load_parts",
      [](const std::filesystem::path& path) {
        const std::size_t before = library().generators().size();
        PartsLibrary trial = library();
        Diagnostics d;
        if (!trial.load_yaml(path, d)) python::raise_diagnostics(d);
        library() = std::move(trial);
        std::vector<std::string> added;
        for (std::size_t i = before; i < library().generators().size(); ++i) {
          added.push_back(library().generators()[i].name);
          for (const std::string& a : library().generators()[i].aliases) added.push_back(a);
        }
        return added;
      },
      py::arg("path"),
      "Adds the parts of a YAML part file (docs/parts.md); returns their names and aliases.");
  m.def(
      "load_design",
      [](const std::filesystem::path& path, const py::object& time_limit) {
        DesignOptions o;
        o.verify.deadline = python::deadline_from(time_limit);
        Design d = load_design(path, library(), o);
        if (d.diagnostics.has_errors()) python::raise_diagnostics(d.diagnostics);
        py::dict parts;
        for (const auto& [name, part] : d.parts) parts[py::str(name)] = part;
        return py::make_tuple(py::cast(std::move(d.assembly)), parts, d.name);
      },
      py::arg("path"),
      py::arg("time_limit") = py::none(),
      "Reads a hacks design file and verifies every connect: (assembly, parts by name, name).");
  m.def("part_names", [] {
    std::vector<std::string> names;
    for (const PartGenerator& g : library().generators()) {
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
             if (!r.accepted) python::raise_diagnostics(r.diagnostics);
           })
      .def(
          "connect",
          [](Assembly& a,
             const py::object& p1,
             const py::object& p2,
             const std::string& alignment,
             bool is_fixed,
             const py::object& time_limit,
             std::uint64_t seed) {
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
            o.verify.deadline = python::deadline_from(time_limit);
            o.verify.seed = seed;
            ConnectReport r = a.connect(p1.cast<PrimitiveRef>(), p2.cast<PrimitiveRef>(), o);
            if (!r.accepted) {
              if (mark_cut_by_deadline(r, o.verify) ||
                  r.diagnostics.deciding_class() == DiagnosticClass::kInput) {
                python::raise_diagnostics(r.diagnostics);
              }
              // Which end of a cycle a program builds first must not decide whether it holds
              // together: a connect whose only fault is a missed closure is tried again with
              // every connect so far in the canonical order, as design files are.
              if (Assembly::only_closure_misses(r.diagnostics)) {
                if (std::optional<Assembly> closed = a.closed_in_canonical_order(
                        {{p1.cast<PrimitiveRef>(), p2.cast<PrimitiveRef>(), o}},
                        o.verify.deadline)) {
                  a = std::move(*closed);
                  return true;
                }
              }
              raise(python::errors().connect, messages(r.diagnostics));
            }
            return r.closes_cycle;
          },
          py::arg("a"),
          py::arg("b"),
          py::arg("alignment") = "default",
          py::arg("is_fixed") = false,
          py::arg("time_limit") = py::none(),
          py::arg("seed") = std::uint64_t{1})
      .def("end_with",
           [](Assembly& a, const py::object& target, const py::object& frame) {
             const Diagnostics d =
                 py::isinstance<Part>(target)
                     ? a.end_with(target.cast<std::shared_ptr<Part>>(), to_frame(frame))
                     : a.end_with(to_ref(target, "end_with()"), to_frame(frame));
             if (d.has_errors()) python::raise_diagnostics(d);
           })
      .def_property_readonly("part_count", &Assembly::part_count)
      .def(
          "solve",
          [](const Assembly& a, const py::object& time_limit, std::uint64_t seed) {
            SolveOptions o;
            o.deadline = python::deadline_from(time_limit);
            o.seed = seed;
            py::gil_scoped_release release;
            return solve_one(a, o);
          },
          py::arg("time_limit") = py::none(),
          py::arg("seed") = std::uint64_t{1});

  py::class_<Solved>(m, "SolveResult")
      .def_property_readonly("stable", [](const Solved& s) { return s.result.stable; })
      .def_property_readonly("feasible", [](const Solved& s) { return s.result.feasible; })
      .def_property_readonly(
          "verdict",
          [](const Solved& s) { return std::string(to_string(s.result.verdict())); },
          "The verdict in one word, as the report and result.json give it: STABLE, "
          "PARTS_PASS_THROUGH, INFEASIBLE, STOPPED, FALLS_APART or NOT_AT_REST")
      .def_property_readonly("target_error",
                             [](const Solved& s) {
                               return py::make_tuple(s.result.target.position_mm,
                                                     s.result.target.rotation_deg);
                             })
      .def_property_readonly(
          "target_pose_error",
          [](const Solved& s) {
            py::dict d;
            d["position_mm"] = s.result.target.position_mm;
            d["rotation_deg"] = s.result.target.rotation_deg;
            d["tilt_deg"] = s.result.target.tilt_deg;
            d["twist_deg"] = s.result.target.twist_deg;
            d["twist_free"] = s.result.target.twist_free;
            return d;
          },
          "The target's error split into position, tilt from up and twist about the vertical "
          "(twist_free: the assembly turns it about the vertical at no cost)")
      .def_property_readonly(
          "termination",
          [](const Solved& s) { return std::string(to_string(s.result.termination)); })
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
      .def_property_readonly(
          "remedy",
          [](const Solved& s) { return s.result.remedy; },
          "For a design that falls apart: a change to it that holds, found by solving the "
          "changed design (empty if none was found).")
      .def_property_readonly(
          "contacts",
          [](const Solved& s) {
            py::list out;
            for (const PartContact& c : s.result.contacts) {
              out.append(py::make_tuple(c.part_a, c.part_b, c.distance_mm));
            }
            return out;
          },
          "Pairs of parts that touch or overlap in the solved pose, deepest overlap first: "
          "(part, part, distance in mm; negative: they pass through each other by that much)")
      .def_property_readonly(
          "max_penetration_mm",
          [](const Solved& s) { return s.result.max_penetration_mm; },
          "Deepest overlap of two parts' bodies (mm); above 0.5 the pose is never stable")
      .def_property_readonly("timings_ms",
                             [](const Solved& s) {
                               py::dict d;
                               for (const StageTiming& t : s.result.timings)
                                 d[py::str(t.stage)] = t.milliseconds;
                               return d;
                             })
      .def_property_readonly("message", [](const Solved& s) { return s.result.message; })
      .def_property_readonly("stopped_message",
                             [](const Solved& s) { return stopped_at_deadline(s.result, {}); })
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
  // stderr when asked. `remedies`: whether a design that does not hold is solved again with
  // connects turned to find one that does (SolveResult::remedy), as solve() does; a family's
  // sweep ranks its variants and leaves it out (it was 60 % of a sweep's time).
  m.def(
      "solve_many",
      [](const std::vector<Assembly*>& assemblies, int threads, bool progress, bool remedies) {
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
                // The assemblies already share the cores: each solve runs on one thread.
                SolveOptions one_thread;
                one_thread.threads = 1;
                one_thread.seek_remedy = remedies;
                results[static_cast<std::size_t>(i)] =
                    solve_one(*assemblies[static_cast<std::size_t>(i)], one_thread);
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
      py::arg("progress") = false,
      py::arg("remedies") = true);
}

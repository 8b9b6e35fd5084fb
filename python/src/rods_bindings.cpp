// The rods kit in Python (_fabkit.rods; fabkit/rods.py builds the user-facing API on it).
// Results cross as JSON text (the report and assembly files' own encoding), so Python sees
// exactly what `fabkit build` writes.
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <chrono>

#include "convert.h"
#include "errors.h"
#include "fabkit/core/cut_plan.h"
#include "fabkit/core/json.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/rods/build.h"
#include "fabkit/rods/design_file.h"
#include "fabkit/rods/joint_geometry.h"
#include "fabkit/rods/outputs.h"
#include "fabkit/rods/reuse.h"
#include "fabkit/rods/tolerance_board.h"
#include "kits.h"

namespace py = pybind11;
using namespace fabkit;
using namespace fabkit::rods;
using fabkit::python::raise;
using fabkit::python::raise_diagnostics;
using fabkit::python::to_vec3;

namespace {

// A summary with the design it belongs to (its report names the design's joints and rods).
struct Result {
  Design design;
  Summary summary;
};

py::list mesh_to_python(const TriangleMesh& m) {
  py::list vertices, faces;
  for (const Vec3& v : m.vertices) vertices.append(py::make_tuple(v.x(), v.y(), v.z()));
  for (const auto& f : m.faces) faces.append(py::make_tuple(f[0], f[1], f[2]));
  py::list out;
  out.append(vertices);
  out.append(faces);
  return out;
}

void set_rod_material(Parameters& p, const std::string& name) {
  const auto m = find_rod_material(name);
  if (!m) {
    std::string all;
    for (const RodMaterial& r : rod_material_presets()) all += (all.empty() ? "" : ", ") + r.name;
    throw py::value_error(fmt::format("unknown rod material '{}'; presets: {}", name, all));
  }
  p.rod_material = *m;
}

void set_joint_material(Parameters& p, const std::string& name) {
  const auto m = find_joint_material(name);
  if (!m) {
    std::string all;
    for (const JointMaterial& r : joint_material_presets())
      all += (all.empty() ? "" : ", ") + r.name;
    throw py::value_error(fmt::format("unknown joint material '{}'; presets: {}", name, all));
  }
  p.joint_material = *m;
}

BuildOptions options(unsigned seed, const py::object& time_limit, int threads, bool engrave) {
  BuildOptions o;
  o.joint.engraving.seed = seed;
  o.joint.engrave = engrave;
  o.cut_plan.seed = seed;
  o.threads = threads;
  if (const auto s = python::time_limit_seconds(time_limit)) {
    o.deadline = python::deadline_from(time_limit);
    o.cut_plan.time_limit_s = std::min(o.cut_plan.time_limit_s, *s / 2);
  }
  return o;
}

}  // namespace

namespace fabkit::python {

void bind_rods(py::module_ m) {
  py::class_<Parameters>(m, "Parameters", "r, p, σ, h, ε, materials and stock (mm, kg/m³, MPa)")
      .def(py::init<>())
      .def_readwrite("radius", &Parameters::radius, "r, mm (a polygon's circumradius)")
      .def_readwrite("sides", &Parameters::sides, "p: polygon sides; 0 for a circle")
      .def_readwrite("circle_sides", &Parameters::circle_sides)
      .def_readwrite("wall", &Parameters::wall, "σ, mm")
      .def_readwrite("socket", &Parameters::socket, "h, mm")
      .def_readwrite("tolerance", &Parameters::tolerance, "ε, mm (negative: press fit)")
      .def_readwrite("leaf_offset", &Parameters::leaf_offset)
      .def_readwrite("min_rod_length", &Parameters::min_rod_length)
      .def_readwrite("merge_tolerance", &Parameters::merge_tolerance)
      .def_property(
          "stock_length",
          [](const Parameters& p) { return p.stock.length; },
          [](Parameters& p, double v) { p.stock.length = v; })
      .def_property(
          "stock_end_padding",
          [](const Parameters& p) { return p.stock.end_padding; },
          [](Parameters& p, double v) { p.stock.end_padding = v; })
      .def_property(
          "stock_kerf",
          [](const Parameters& p) { return p.stock.kerf; },
          [](Parameters& p, double v) { p.stock.kerf = v; })
      .def_property(
          "rod_material", [](const Parameters& p) { return p.rod_material.name; }, set_rod_material)
      .def_property(
          "joint_material",
          [](const Parameters& p) { return p.joint_material.name; },
          set_joint_material)
      .def_property(
          "rod_density",
          [](const Parameters& p) { return p.rod_material.density; },
          [](Parameters& p, double v) {
            p.rod_material.density = v;
            p.rod_material.name = "custom";
          })
      .def("validate", [](const Parameters& p) {
        const Diagnostics d = p.validate();
        if (d.has_errors()) raise_diagnostics(d);
      });

  py::class_<Design>(m, "Design", "A rod structure design: network, parameters, loads")
      .def_static(
          "from_file",
          [](const std::filesystem::path& path) {
            Design d = load_design(path);
            if (!d.readable) raise_diagnostics(d.diagnostics);
            return d;
          },
          py::arg("path"))
      .def_static(
          "from_text",
          [](const std::string& yaml, const std::string& name, const std::filesystem::path& base) {
            Design d = load_design_text(yaml, name, base);
            if (!d.readable) raise_diagnostics(d.diagnostics);
            return d;
          },
          py::arg("yaml"),
          py::arg("name") = "design.yaml",
          py::arg("base_dir") = std::filesystem::path())
      .def_static(
          "from_lists",
          [](const py::sequence& nodes,
             const py::sequence& edges,
             const Parameters& p,
             const std::string& name) {
            std::vector<Vec3> n;
            for (std::size_t i = 0; i < nodes.size(); ++i) {
              n.push_back(to_vec3(nodes[i], fmt::format("node {}", i).c_str()));
            }
            std::vector<std::pair<long long, long long>> e;
            for (std::size_t i = 0; i < edges.size(); ++i) {
              const py::sequence pair = py::reinterpret_borrow<py::sequence>(edges[i]);
              if (py::isinstance<py::str>(edges[i]) || pair.size() != 2) {
                throw py::type_error(
                    fmt::format("edge {} must be a pair of node indices, like (0, 1)", i));
              }
              try {
                e.emplace_back(pair[0].cast<long long>(), pair[1].cast<long long>());
              } catch (const py::cast_error&) {
                throw py::type_error(fmt::format("edge {} must hold two integers", i));
              }
            }
            Design d = design_from_lists(n, e, p);
            d.name = name;
            if (!d.readable) raise_diagnostics(d.diagnostics);
            return d;
          },
          py::arg("nodes"),
          py::arg("edges"),
          py::arg("parameters"),
          py::arg("name") = "")
      .def_readwrite("name", &Design::name)
      .def_property_readonly("parameters", [](const Design& d) { return d.parameters; })
      .def(
          "with_parameters",
          [](const Design& d, const Parameters& p) {
            const Diagnostics v = p.validate();
            if (v.has_errors()) raise_diagnostics(v);
            Design copy = d;
            copy.parameters = p;
            return copy;
          },
          "A copy with other parameters (the network is kept)")
      .def_property_readonly("nodes",
                             [](const Design& d) {
                               std::vector<std::vector<double>> out;
                               for (const Node& n : d.structure.nodes)
                                 out.push_back({n.position.x(), n.position.y(), n.position.z()});
                               return out;
                             })
      .def_property_readonly("joint_ids",
                             [](const Design& d) {
                               std::vector<int> out;
                               for (const Node& n : d.structure.nodes) out.push_back(n.id);
                               return out;
                             })
      .def_property_readonly("edges",
                             [](const Design& d) {
                               std::vector<std::pair<int, int>> out;
                               for (const Rod& r : d.structure.rods) out.emplace_back(r.a, r.b);
                               return out;
                             })
      .def_property_readonly("rod_names",
                             [](const Design& d) {
                               std::vector<std::string> out;
                               for (std::size_t e = 0; e < d.structure.rods.size(); ++e)
                                 out.push_back(d.structure.rod_name(static_cast<int>(e)));
                               return out;
                             })
      .def(
          "add_load",
          [](Design& d, int node, const py::object& force) {
            if (node < 0 || node >= static_cast<int>(d.structure.nodes.size())) {
              throw py::index_error(fmt::format(
                  "node {} is not a node index (0 to {})", node, d.structure.nodes.size() - 1));
            }
            d.loads.push_back(PointLoad{node, to_vec3(force, "force"), {}});
          },
          py::arg("node"),
          py::arg("force"),
          "A force in N at a node (0-based index)")
      .def("scaled", [](const Design& d, double f) {
        if (!(f > 0)) throw py::value_error("the scale factor must be positive");
        Design copy = d;
        copy.structure = scaled(d.structure, f);
        return copy;
      });

  py::class_<Result>(m, "Result", "What check() and build() found and made")
      .def_property_readonly(
          "termination",
          [](const Result& r) { return std::string(to_string(r.summary.termination)); })
      .def_property_readonly("message", [](const Result& r) { return r.summary.message; })
      .def("report_json",
           [](const Result& r) { return dump_json(report_json(r.design, r.summary)); })
      .def("assembly_json",
           [](const Result& r) { return dump_json(assembly_json(r.design, r.summary)); })
      .def("joint_mesh",
           [](const Result& r, int node) {
             for (const JointSolid& j : r.summary.joints) {
               if (j.node == node) return mesh_to_python(j.mesh);
             }
             throw py::index_error(fmt::format("joint index {} was not built", node));
           })
      .def("save",
           [](const Result& r, const std::filesystem::path& dir) {
             Diagnostics d;
             const auto written = write_outputs(r.design, r.summary, dir, d);
             if (d.has_errors()) raise_diagnostics(d);
             return written;
           })
      .def("save_joint_stl", [](const Result& r, int node, const std::filesystem::path& path) {
        for (const JointSolid& j : r.summary.joints) {
          if (j.node != node) continue;
          Diagnostics d;
          if (!write_stl(j.mesh.transformed(j.print_pose), path, d)) raise_diagnostics(d);
          return;
        }
        throw py::index_error(fmt::format("joint index {} was not built", node));
      });

  m.def(
      "check",
      [](const Design& d, unsigned seed, const py::object& time_limit) {
        const BuildOptions o = options(seed, time_limit, 1, false);
        Result r{d, {}};
        {
          py::gil_scoped_release release;
          r.summary = rods::check(d, o);
        }
        return r;
      },
      py::arg("design"),
      py::arg("seed") = 1,
      py::arg("time_limit") = py::none());
  m.def(
      "build",
      [](const Design& d, unsigned seed, const py::object& time_limit, int threads, bool engrave) {
        if (threads < 1 || threads > 64) throw py::value_error("threads must be 1 to 64");
        const BuildOptions o = options(seed, time_limit, threads, engrave);
        Result r{d, {}};
        {
          py::gil_scoped_release release;
          r.summary = rods::build(d, o);
        }
        return r;
      },
      py::arg("design"),
      py::arg("seed") = 1,
      py::arg("time_limit") = py::none(),
      py::arg("threads") = 2,
      py::arg("engrave") = true);
  m.def(
      "preview",
      [](const Design& d) {
        const Layout l = compute_layout(d.structure, d.parameters);
        const Preview p = make_preview(d.structure, d.parameters, l);
        py::dict out;
        py::list joints, rods;
        for (const TriangleMesh& j : p.joints) joints.append(mesh_to_python(j));
        for (const TriangleMesh& r : p.rods) rods.append(mesh_to_python(r));
        out["joints"] = joints;
        out["rods"] = rods;
        out["rod_lengths"] = l.rod_length;
        std::vector<std::pair<double, double>> offsets;
        for (const auto& e : l.ends) offsets.emplace_back(e[0].offset, e[1].offset);
        out["offsets"] = offsets;
        return out;
      },
      py::arg("design"),
      "Hulls and prisms (no booleans), rod lengths and offsets, for drawing");
  m.def(
      "plan_cuts",
      [](const std::vector<std::pair<std::string, double>>& pieces,
         double length,
         double end_padding,
         double kerf,
         double time_limit,
         unsigned seed) {
        std::vector<CutPiece> in;
        for (const auto& [label, l] : pieces) in.push_back(CutPiece{label, l});
        CutPlanOptions o;
        o.time_limit_s = time_limit;
        o.seed = seed;
        Diagnostics d;
        const auto plan = plan_cuts(in, StockSpec{length, end_padding, kerf}, d, o);
        if (!plan) raise_diagnostics(d);
        py::dict out;
        py::list stock;
        for (const StockCut& s : plan->stock) {
          py::list row;
          for (const PlacedPiece& p : s.pieces)
            row.append(
                py::make_tuple(in[static_cast<std::size_t>(p.piece)].label, p.start, p.length));
          stock.append(row);
        }
        out["stock"] = stock;
        out["stock_count"] = plan->stock_count();
        out["lower_bound"] = plan->lower_bound;
        out["proven_optimal"] = plan->proven_optimal;
        out["summary"] = plan->summary;
        out["svg"] = cut_plan_svg(*plan, in, StockSpec{length, end_padding, kerf});
        out["csv"] = cut_plan_csv(*plan, in);
        return out;
      },
      py::arg("pieces"),
      py::arg("stock_length"),
      py::arg("end_padding") = 10.0,
      py::arg("kerf") = 0.0,
      py::arg("time_limit") = 0.8,
      py::arg("seed") = 1);
  m.def(
      "tolerance_board",
      [](const Parameters& p,
         double from,
         double to,
         double step,
         const std::filesystem::path& path) {
        ToleranceBoardOptions o;
        o.from = from;
        o.to = to;
        o.step = step;
        Diagnostics d;
        std::optional<ToleranceBoard> board;
        {
          py::gil_scoped_release release;
          board = make_tolerance_board(p, o, d);
        }
        if (!board) raise_diagnostics(d);
        if (!write_stl(board->mesh, path, d)) raise_diagnostics(d);
        return board->tolerances;
      },
      py::arg("parameters"),
      py::arg("tolerance_from"),
      py::arg("tolerance_to"),
      py::arg("step"),
      py::arg("path"));
  m.def(
      "matching_joints",
      [](const Design& printed, const Design& design) {
        std::vector<std::pair<int, int>> out;
        for (const JointMatch& j : matching_joints(
                 printed.structure, printed.parameters, design.structure, design.parameters)) {
          out.emplace_back(j.node, j.printed);
        }
        return out;
      },
      py::arg("printed"),
      py::arg("design"),
      "(node in design, node in printed) for every joint they share");
  m.def("rod_materials", [] {
    std::vector<std::string> out;
    for (const RodMaterial& r : rod_material_presets()) out.push_back(r.name);
    return out;
  });
}

}  // namespace fabkit::python

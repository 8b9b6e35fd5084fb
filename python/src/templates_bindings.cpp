// The templates kit in Python (_fabkit.templates; fabkit/templates.py is the user-facing API).
#include <fmt/format.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <memory>

#include "convert.h"
#include "errors.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/templates/build.h"
#include "fabkit/templates/check.h"
#include "fabkit/templates/database.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/manipulate.h"
#include "kits.h"

namespace py = pybind11;
using namespace fabkit;
using namespace fabkit::templates;
using fabkit::python::raise_diagnostics;
using fabkit::python::to_vec3;

namespace {

py::list vec(const Vec3& v) {
  py::list l;
  for (int i = 0; i < 3; ++i) l.append(v[i]);
  return l;
}

py::dict item_dict(const Item& it) {
  py::dict d;
  d["id"] = it.id;
  d["name"] = it.name;
  d["category"] = std::string(to_string(it.category));
  d["material"] = it.material;
  d["supplier"] = it.supplier;
  d["part_number"] = it.part_number;
  d["price"] = it.price;
  d["unit"] = it.unit;
  d["pack_quantity"] = it.pack_quantity;
  py::list dims;
  for (const ItemDimension& x : it.dims) dims.append(py::make_tuple(x.mm, x.resizable));
  d["dims"] = dims;
  py::list stock;
  for (const StockSize& s : it.stock_sizes())
    stock.append(py::make_tuple(s.length_mm, s.width_mm, s.price));
  d["stock"] = stock;
  return d;
}

ControlKind control_of(const std::string& s) {
  if (auto k = control_from_string(s)) return *k;
  throw py::value_error(fmt::format(
      "unknown control '{}'; controls: center_x, center_y, center_z, size_x, size_y, size_z", s));
}

// A database the Python objects can share (the bundled one lives forever).
struct PyDatabase {
  std::shared_ptr<const TemplateDatabase> db;
  const TemplateDatabase& get() const { return *db; }
};

PyDatabase bundled_db() {
  return PyDatabase{std::shared_ptr<const TemplateDatabase>(&TemplateDatabase::bundled(),
                                                            [](const TemplateDatabase*) {})};
}

// The working model plus what the file would say: loads and friction.
struct PyModel {
  PyDatabase db;
  ComposedModel composed;
  // Kept between drags so a drag session keeps its factorisation (the browser workspace and a
  // Python loop of drags pay the null space once); rebuilt when the structure changes.
  std::shared_ptr<Manipulator> manipulator;

  Template& t() { return composed.model.model(); }
  const Manipulator& manip() {
    if (!manipulator)
      manipulator = std::make_shared<Manipulator>(t(), ManipulateOptions{}, &db.get().catalog());
    return *manipulator;
  }
  void changed() { manipulator.reset(); }

  NodeId node(const std::string& name) {
    const NodeId n = name.empty() ? t().root() : t().find_node_or_element(name);
    if (!n.valid()) {
      std::vector<std::string> names;
      for (std::size_t i = 1; i < t().nodes.size(); ++i)
        names.push_back(t().path(NodeId(static_cast<int>(i))));
      Diagnostics d;
      d.error(templates::codes::kUnknownName,
              fmt::format("the model has no node '{}'{}", name, did_you_mean(name, names)));
      raise_diagnostics(d);
    }
    return n;
  }
};

py::dict drag_dict(const DragResult& r) {
  py::dict d;
  d["requested"] = r.requested;
  d["achieved"] = r.achieved;
  d["reached"] = r.reached;
  d["message"] = r.message;
  d["used_solver"] = r.used_solver;
  d["max_violation"] = r.max_violation;
  d["milliseconds"] = r.milliseconds;
  return d;
}

}  // namespace

namespace fabkit::python {

void bind_templates(py::module_ m) {
  py::class_<ItemCatalog>(m, "Catalog", "The items catalog (SQLite)")
      .def_static("bundled", [] { return ItemCatalog::bundled(); })
      .def_static("open",
                  [](const std::filesystem::path& p) {
                    Diagnostics d;
                    auto c = ItemCatalog::open(p, d);
                    if (!c) raise_diagnostics(d);
                    return *c;
                  })
      .def_static("in_memory",
                  [] {
                    Diagnostics d;
                    auto c = ItemCatalog::create_in_memory(d);
                    if (!c) raise_diagnostics(d);
                    return *c;
                  })
      .def(
          "import_csv",
          [](ItemCatalog& c, const std::string& text, const std::string& file) {
            Diagnostics d;
            if (!c.import_csv(text, file, d)) raise_diagnostics(d);
          },
          py::arg("text"),
          py::arg("file") = "items.csv")
      .def("export_csv", &ItemCatalog::export_csv)
      .def("save_as",
           [](const ItemCatalog& c, const std::filesystem::path& p) {
             Diagnostics d;
             if (!c.save_as(p, d)) raise_diagnostics(d);
           })
      .def("schema_version", &ItemCatalog::schema_version)
      .def("ids", &ItemCatalog::ids)
      .def("__len__", &ItemCatalog::size)
      .def("find", [](const ItemCatalog& c, const std::string& id) -> py::object {
        const Item* it = c.find(id);
        return it ? py::object(item_dict(*it)) : py::none();
      });

  py::class_<PyDatabase>(m, "Database", "Source designs as templates over a catalog")
      .def_static("bundled", &bundled_db)
      .def_static(
          "with_directory",
          [](const std::filesystem::path& dir, const ItemCatalog* catalog) {
            Diagnostics d;
            auto db = TemplateDatabase::with_directory(
                dir, catalog ? *catalog : ItemCatalog::bundled(), d);
            if (!db || d.has_errors()) raise_diagnostics(d);
            return PyDatabase{std::make_shared<const TemplateDatabase>(std::move(*db))};
          },
          py::arg("directory"),
          py::arg("catalog") = nullptr)
      .def("names", [](const PyDatabase& db) { return db.get().names(); })
      .def_property_readonly("catalog", [](const PyDatabase& db) { return db.get().catalog(); })
      .def("describe", [](const PyDatabase& db, const std::string& spec) {
        Diagnostics d;
        auto t = db.get().find(spec, d);
        if (!t) raise_diagnostics(d);
        return describe_template(*t, db.get().catalog());
      });

  py::class_<PyModel>(m, "Model", "A working model composed from templates")
      .def(py::init([](const std::string& name, const PyDatabase* db) {
             ComposedModel composed{.name = name, .model = WorkingModel("model"), .readable = true};
             return PyModel{db ? *db : bundled_db(), std::move(composed), nullptr};
           }),
           py::arg("name") = "model",
           py::arg("database") = nullptr)
      .def_static(
          "load",
          [](const std::filesystem::path& path,
             const PyDatabase* db,
             const py::object& time_limit) {
            Diagnostics d;
            auto text = read_input_file(path, "model file", d);
            if (!text) raise_diagnostics(d);
            CheckOptions o;
            o.deadline = deadline_from(time_limit);
            PyModel pm{db ? *db : bundled_db(),
                       compose_model(*text, path.string(), (db ? *db : bundled_db()).get(), o),
                       nullptr};
            if (pm.composed.diagnostics.has_errors()) raise_diagnostics(pm.composed.diagnostics);
            return pm;
          },
          py::arg("path"),
          py::arg("database") = nullptr,
          py::arg("time_limit") = py::none())
      .def(
          "add",
          [](PyModel& pm,
             const std::string& spec,
             const std::string& as,
             const py::object& at,
             bool do_snap,
             bool do_connect) {
            Diagnostics d;
            auto part = pm.db.get().find(spec, d);
            if (!part) raise_diagnostics(d);
            std::optional<Vec3> where;
            if (!at.is_none()) where = to_vec3(at, "at");
            const bool first = pm.composed.model.compositions().empty();
            // A failed add leaves the model as it was.
            ComposedModel before = pm.composed;
            auto c = pm.composed.model.add(
                *part, spec, as.empty() ? spec.substr(spec.rfind('/') + 1) : as, where, d);
            if (!c) raise_diagnostics(d);
            py::dict report;
            if (!first && do_snap) {
              const SnapResult s = snap(pm.composed.model, *c, pm.db.get());
              pm.t().q = s.q;
              report["snapped_planes"] = s.chosen.size();
              report["placements_tried"] = s.combinations;
            }
            if (!first && do_connect) {
              const ConnectResult r = connect(pm.composed.model, *c, pm.db.get());
              py::list links;
              for (const Link& l : r.links) {
                py::dict x;
                x["added"] = pm.t().element(l.added).name;
                x["existing"] = pm.t().element(l.existing).name;
                x["connected"] = l.connection.has_value();
                x["message"] = l.message;
                if (l.connection) x["source"] = pm.t().connections[l.connection->value].source;
                links.append(x);
              }
              report["links"] = links;
              if (r.diagnostics.has_errors()) {
                pm.composed = std::move(before);
                raise_diagnostics(r.diagnostics);
              }
            }
            report["name"] = c->name;
            return report;
          },
          py::arg("template"),
          py::arg("as_") = "",
          py::arg("at") = py::none(),
          py::arg("snap") = true,
          py::arg("connect") = true)
      .def("remove",
           [](PyModel& pm, const std::string& name) {
             Diagnostics d;
             pm.changed();
             if (!pm.composed.model.remove(name, d)) raise_diagnostics(d);
           })
      .def(
          "controls",
          [](PyModel& pm, const std::string& node) {
            const Manipulator& manip = pm.manip();
            py::dict out;
            for (const Control& c : manip.controls(pm.node(node))) {
              py::dict x;
              x["value"] = c.value;
              x["hidden"] = c.hidden;
              out[py::str(std::string(to_string(c.kind)))] = x;
            }
            return out;
          },
          py::arg("node") = "")
      .def("drag",
           [](PyModel& pm, const std::string& node, const std::string& control, double delta) {
             const Manipulator& manip = pm.manip();
             const DragResult r =
                 manip.drag(manip.control(pm.node(node), control_of(control)), delta);
             if (r.diagnostics.has_errors()) raise_diagnostics(r.diagnostics);
             pm.t().q = r.q;
             return drag_dict(r);
           })
      .def("set",
           [](PyModel& pm, const std::string& node, const std::string& control, double value) {
             const Manipulator& manip = pm.manip();
             const DragResult r =
                 manip.set(manip.control(pm.node(node), control_of(control)), value);
             if (r.diagnostics.has_errors()) raise_diagnostics(r.diagnostics);
             pm.t().q = r.q;
             return drag_dict(r);
           })
      .def("max_violation", [](PyModel& pm) { return pm.t().max_violation(); })
      .def("parts",
           [](PyModel& pm) {
             py::list out;
             for (const PlacedPart& p : pm.t().placed_parts()) {
               py::dict x;
               x["name"] = p.name;
               x["item"] = p.item;
               x["role"] = std::string(to_string(p.role));
               x["center"] = vec(p.box.center);
               x["size"] = vec(p.box.size);
               out.append(x);
             }
             return out;
           })
      .def("box",
           [](PyModel& pm, const std::string& node) {
             const Box b = pm.t().node_box(pm.node(node));
             return py::make_tuple(vec(b.center), vec(b.size));
           })
      .def(
          "stability",
          [](PyModel& pm, const py::list& loads, double friction) {
            StabilityOptions o;
            o.friction = friction;
            for (const py::handle& h : loads) {
              const auto t = h.cast<py::tuple>();
              if (t.size() != 3)
                throw py::type_error(
                    "a load is (part name, point [x, y, z] mm, force [fx, fy, fz] N)");
              const std::string part = t[0].cast<std::string>();
              ElementId e;
              for (int i = 0; i < pm.t().element_count(); ++i) {
                if (pm.t().element(ElementId(i)).name == part) e = ElementId(i);
              }
              if (!e.valid())
                throw py::value_error(fmt::format("the model has no part '{}'", part));
              o.loads.push_back(Load{e, to_vec3(t[1], "load point"), to_vec3(t[2], "load force")});
            }
            const StabilityResult r = check_stability(pm.t(), pm.db.get().catalog(), o);
            py::dict out;
            out["stable"] = r.stable;
            py::list bodies;
            for (const Body& b : r.bodies) {
              py::dict x;
              py::list names;
              for (ElementId e : b.elements) names.append(pm.t().element(e).name);
              x["parts"] = names;
              x["mass_kg"] = b.mass_kg;
              x["verdict"] = b.verdict;
              x["stable"] = b.stable;
              bodies.append(x);
            }
            out["bodies"] = bodies;
            out["messages"] = python::messages(r.diagnostics);
            out["milliseconds"] = r.milliseconds;
            return out;
          },
          py::arg("loads") = py::list(),
          py::arg("friction") = 0.5)
      .def("bom",
           [](PyModel& pm) {
             Diagnostics d;
             auto bom = bill_of_materials(pm.t(), pm.db.get().catalog(), d);
             if (!bom) raise_diagnostics(d);
             py::dict out;
             out["total"] = bom->total;
             out["parts"] = bom->parts;
             py::list lines;
             for (const BomLine& l : bom->lines) {
               py::dict x;
               x["item"] = l.item;
               x["name"] = l.name;
               x["category"] = std::string(to_string(l.category));
               x["parts"] = l.parts;
               x["units"] = l.units;
               x["total"] = l.total;
               x["buy"] = l.buy;
               x["supplier"] = l.supplier;
               x["sizes"] = l.sizes;
               lines.append(x);
             }
             out["lines"] = lines;
             out["csv"] = bom_csv(*bom);
             return out;
           })
      .def(
          "build",
          [](PyModel& pm, const std::filesystem::path& dir, const py::object& time_limit) {
            BuildOptions o;
            o.check.deadline = deadline_from(time_limit);
            const BuildSummary s = build(pm.composed, pm.db.get(), dir, o);
            if (s.termination == BuildTermination::kNotBuilt ||
                s.termination == BuildTermination::kWriteFailed) {
              raise_diagnostics(s.diagnostics);
            }
            py::dict out;
            out["message"] = s.message;
            out["verdict"] = s.check.verdict;
            py::list files;
            for (const auto& p : s.written) files.append(p.string());
            out["written"] = files;
            return out;
          },
          py::arg("directory"),
          py::arg("time_limit") = py::none())
      .def("describe", [](PyModel& pm) { return describe_template(pm.t(), pm.db.get().catalog()); })
      .def_property_readonly("name", [](PyModel& pm) { return pm.composed.name; })
      .def_property_readonly("part_count", [](PyModel& pm) { return pm.t().part_count(); });
}

}  // namespace fabkit::python

// Writing a model's outputs: bill, report, cut diagrams, meshes.
#include "fabkit/templates/build.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "fabkit/core/file_io.h"
#include "fabkit/core/json.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/core/svg_preview.h"
#include "fabkit/core/text.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/scene.h"

namespace fabkit::templates {

namespace {

using Clock = std::chrono::steady_clock;

std::string file_safe(std::string_view s) {
  std::string out;
  for (char c : s)
    out += std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' ? c : '_';
  return out;
}

double lowest_z(const Template& t) {
  double z = std::numeric_limits<double>::infinity();
  for (const PlacedPart& p : t.placed_parts()) z = std::min(z, p.box.min().z());
  return std::isfinite(z) ? z : 0.0;
}

}  // namespace

std::string_view to_string(BuildTermination t) {
  switch (t) {
    case BuildTermination::kBuilt:
      return "built";
    case BuildTermination::kBuiltWithFindings:
      return "built-with-findings";
    case BuildTermination::kNotBuilt:
      return "not-built";
    case BuildTermination::kWriteFailed:
      return "write-failed";
  }
  return "not-built";
}

std::string model_json(const ComposedModel& cm, const CheckResult& check) {
  const Template& t = cm.model.model();
  Json j;
  j["fabkit"] = "templates/1";
  j["name"] = cm.name;
  j["verdict"] = check.verdict;
  Json comps = Json::array();
  for (const Composition& c : cm.model.compositions())
    comps.push_back({{"name", c.name}, {"source", c.source}});
  j["compositions"] = comps;
  Json elements = Json::array();
  for (int e = 0; e < t.element_count(); ++e) {
    const Element& el = t.element(ElementId(e));
    const Box b = t.box(ElementId(e));
    Json x{{"name", el.name},
           {"path", t.path(el.node)},
           {"item", el.item},
           {"role", std::string(to_string(el.role))},
           {"center", to_json(b.center)},
           {"size", to_json(b.size)}};
    if (el.pattern) x["pattern_parts"] = el.pattern->total();
    if (e < static_cast<int>(check.stability.element_stable.size()))
      x["stable"] = check.stability.element_stable[e] != 0;
    elements.push_back(std::move(x));
  }
  j["elements"] = elements;
  j["parts"] = t.part_count();
  j["relations"] = static_cast<int>(t.relations.size());
  j["connections"] = static_cast<int>(t.connections.size());
  if (check.bom) j["total_usd"] = tidy(check.bom->total);
  j["diagnostics"] = to_json(check.diagnostics);
  return dump_json(j, 2) + "\n";
}

std::string report_html(const ComposedModel& cm,
                        const CheckResult& check,
                        const std::vector<std::pair<std::string, std::string>>& drawings) {
  const Template& t = cm.model.model();
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += fmt::format("<title>{} — fabkit bill of materials</title>\n", xml_escape(cm.name));
  h += "<style>body{font-family:sans-serif;margin:2em;max-width:60em}table{border-collapse:"
       "collapse;width:100%}"
       "td,th{border:1px solid #bbb;padding:3px "
       "6px;font-size:90%;text-align:left}td.n{text-align:right}"
       ".bad{color:#b00}.ok{color:#070}figure{margin:1em 0;page-break-inside:avoid}figure "
       "svg{max-width:100%;"
       "height:auto;border:1px solid #ddd}@media print{a{color:black}}</style></head><body>\n";
  h += fmt::format("<h1>{}</h1>\n", xml_escape(cm.name));
  if (!cm.description.empty()) h += fmt::format("<p>{}</p>\n", xml_escape(cm.description));
  h += fmt::format(
      "<p>{} parts ({} principal elements, {} connections). Verdict: <b class=\"{}\">{}</b>.</p>\n",
      t.part_count(),
      std::count_if(
          t.elements.begin(), t.elements.end(), [](const Element& e) { return e.is_principal(); }),
      t.connections.size(),
      check.verdict == "feasible" ? "ok" : "bad",
      xml_escape(check.verdict));
  for (const auto& [name, svg] : drawings) {
    if (name != "preview") continue;
    h += "<figure>" + svg +
         "<figcaption>The model (connectors blue, unstable parts red).</figcaption></figure>\n";
  }
  h += "<h2>How it was composed</h2>\n<ol>\n";
  for (const StepReport& s : cm.steps) {
    h += fmt::format("<li>{}: {}</li>\n", xml_escape(s.text), xml_escape(s.outcome));
  }
  h += "</ol>\n";
  h += "<h2>Stability</h2>\n";
  h += fmt::format(
      "<p class=\"{}\">{}</p>\n<table><tr><th>parts</th><th>mass</th><th>verdict</th></tr>\n",
      check.stability.stable ? "ok" : "bad",
      check.stability.stable ? "Every part is in static equilibrium at rest (with friction)."
                             : "Some parts tip or slide.");
  for (const Body& b : check.stability.bodies) {
    std::vector<std::string> names;
    for (ElementId e : b.elements) names.push_back(t.element(e).name);
    h += fmt::format("<tr><td>{}</td><td class=\"n\">{:.1f} kg</td><td class=\"{}\">{}</td></tr>\n",
                     xml_escape(fmt::format("{}", fmt::join(names, ", "))),
                     b.mass_kg,
                     b.stable ? "ok" : "bad",
                     xml_escape(b.verdict));
  }
  h += "</table>\n";
  if (check.bom) {
    const BillOfMaterials& bom = *check.bom;
    h += "<h2>Bill of "
         "materials</h2>\n<table><tr><th>item</th><th>description</th><th>parts</th><th>buy</th>"
         "<th>total</th><th>supplier</th><th>part no.</th><th>cut sizes</th></tr>\n";
    for (const BomLine& l : bom.lines) {
      h += fmt::format(
          "<tr><td>{}</td><td>{}</td><td class=\"n\">{}</td><td>{}</td><td class=\"n\">${:.2f}</td>"
          "<td>{}</td><td>{}</td><td>{}</td></tr>\n",
          xml_escape(l.item),
          xml_escape(l.name),
          l.parts,
          xml_escape(l.buy),
          l.total,
          xml_escape(l.supplier),
          xml_escape(l.part_number),
          xml_escape(l.sizes));
    }
    h += fmt::format(
        "<tr><th colspan=\"4\">total</th><th class=\"n\">${:.2f}</th><th "
        "colspan=\"3\"></th></tr></table>\n",
        bom.total);
    h += "<h2>Cut diagrams</h2>\n<p>Red lines are saw cuts at the centre of the kerf.</p>\n";
    for (const auto& [name, svg] : drawings) {
      if (name == "preview") continue;
      h += fmt::format("<figure>{}<figcaption>{}</figcaption></figure>\n", svg, xml_escape(name));
    }
  }
  if (!check.diagnostics.empty()) {
    h += "<h2>Findings</h2>\n<ul>\n";
    for (const Diagnostic& d : check.diagnostics)
      h += fmt::format("<li>{}</li>\n", xml_escape(d.format()));
    h += "</ul>\n";
  }
  h += "<p><small>Made with fabkit (design and fabrication by example). Prices are typical retail "
       "estimates; check your supplier.</small></p>\n</body></html>\n";
  return h;
}

BuildSummary build(const ComposedModel& cm,
                   const TemplateDatabase& db,
                   const std::filesystem::path& dir,
                   const BuildOptions& options) {
  BuildSummary out;
  out.timings.push_back({"compose", cm.milliseconds});
  auto start = Clock::now();
  out.check = check(cm, db, options.check);
  out.timings.push_back(
      {"check", std::chrono::duration<double, std::milli>(Clock::now() - start).count()});
  out.diagnostics = out.check.diagnostics;
  if (!cm.readable || !out.check.bom || out.diagnostics.has_errors_of(DiagnosticClass::kTimeout)) {
    out.termination = BuildTermination::kNotBuilt;
    out.message = !cm.readable ? "not built: the model file has errors"
                  : out.diagnostics.has_errors_of(DiagnosticClass::kTimeout)
                      ? "not built: stopped at the deadline; nothing written"
                      : "not built: a part cannot be cut from any stock size";
    return out;
  }
  start = Clock::now();
  if (!make_output_directory(dir, out.diagnostics)) {
    out.termination = BuildTermination::kWriteFailed;
    out.message = "not built: the output directory cannot be created";
    return out;
  }
  const BillOfMaterials& bom = *out.check.bom;
  auto cuts_file = [](const LumberCuts& c) {
    return fmt::format("cuts_{}.svg", file_safe(c.item));
  };
  auto sheet_file = [](const SheetCuts& c, int s) {
    return fmt::format("sheet_{}_{}.svg", file_safe(c.item), s + 1);
  };
  {  // every destination checked before any is written: a refusal leaves no half-written set
    std::vector<std::filesystem::path> files{dir / "bom.csv", dir / "bom.json"};
    for (const LumberCuts& c : bom.lumber) files.push_back(dir / cuts_file(c));
    for (const SheetCuts& c : bom.sheets) {
      for (int s = 0; s < c.plan.sheet_count(); ++s) files.push_back(dir / sheet_file(c, s));
    }
    if (options.write_meshes) {
      for (const char* name : {"scene.glb", "stability.glb", "model.stl", "preview.svg"}) {
        files.push_back(dir / name);
      }
    }
    files.push_back(dir / "report.html");
    files.push_back(dir / "model.json");
    if (!outputs_writable(files, out.diagnostics)) {
      out.termination = BuildTermination::kWriteFailed;
      out.message = "not built: an output file cannot be written; nothing written";
      return out;
    }
  }
  bool ok = true;
  auto write = [&](const std::string& name, const std::string& text) {
    const auto path = dir / name;
    if (write_file_atomically(path, text, out.diagnostics)) {
      out.written.push_back(path);
    } else {
      ok = false;
    }
  };
  write("bom.csv", bom_csv(bom));
  write("bom.json", bom_json(bom));
  std::vector<std::pair<std::string, std::string>> drawings;
  for (const LumberCuts& c : bom.lumber) {
    CutPlanSvgOptions so;
    so.stock_width = std::max(10.0, c.width_mm);
    so.label_size = std::clamp(c.width_mm / 4, 3.0, 12.0);
    const std::string svg = cut_plan_svg(c.plan, c.pieces, c.stock, so);
    write(cuts_file(c), svg);
    drawings.emplace_back(fmt::format("{}: {} ({} mm stock, {:g} mm kerf)",
                                      c.item,
                                      c.plan.summary,
                                      c.stock.length,
                                      c.stock.kerf),
                          svg);
  }
  for (const SheetCuts& c : bom.sheets) {
    for (int s = 0; s < c.plan.sheet_count(); ++s) {
      const std::string svg = sheet_plan_svg(c.plan, s, c.pieces, c.sheet_specs[s]);
      write(sheet_file(c, s), svg);
      drawings.emplace_back(fmt::format("{}: sheet {} of {} ({:g} x {:g} mm, {:g} mm kerf)",
                                        c.item,
                                        s + 1,
                                        c.plan.sheet_count(),
                                        c.sheet_specs[s].length,
                                        c.sheet_specs[s].width,
                                        c.sheet_specs[s].kerf),
                            svg);
    }
  }
  out.timings.push_back({"bill of materials", 0});
  const Template& t = cm.model.model();
  if (options.write_meshes) {
    SceneOptions so;
    so.element_stable = out.check.stability.element_stable;
    so.lift = -lowest_z(t);
    const std::vector<SceneObject> scene = model_scene(t, db.catalog(), so);
    if (write_glb(scene, dir / "scene.glb", out.diagnostics)) {
      out.written.push_back(dir / "scene.glb");
    } else {
      ok = false;
    }
    so.colors = SceneColors::kStability;
    if (write_glb(model_scene(t, db.catalog(), so), dir / "stability.glb", out.diagnostics)) {
      out.written.push_back(dir / "stability.glb");
    } else {
      ok = false;
    }
    TriangleMesh all;
    for (const SceneObject& o : scene) all.append(o.mesh.transformed(o.transform));
    if (write_stl(all, dir / "model.stl", out.diagnostics)) {
      out.written.push_back(dir / "model.stl");
    } else {
      ok = false;
    }
    if (write_svg_preview(scene, dir / "preview.svg", out.diagnostics)) {
      out.written.push_back(dir / "preview.svg");
      Diagnostics quiet;
      if (auto text = read_input_file(dir / "preview.svg", "preview", quiet)) {
        // Inline without the XML declaration.
        std::string svg = *text;
        if (svg.rfind("<?xml", 0) == 0) svg = svg.substr(svg.find("?>") + 2);
        drawings.insert(drawings.begin(), {"preview", svg});
      }
    } else {
      ok = false;
    }
  }
  write("report.html", report_html(cm, out.check, drawings));
  write("model.json", model_json(cm, out.check));
  out.timings.push_back(
      {"export", std::chrono::duration<double, std::milli>(Clock::now() - start).count()});
  if (!ok) {
    out.termination = BuildTermination::kWriteFailed;
    out.message = "some outputs could not be written";
    return out;
  }
  out.termination = out.check.diagnostics.has_errors() ? BuildTermination::kBuiltWithFindings
                                                       : BuildTermination::kBuilt;
  out.message = fmt::format("built '{}': {} parts, ${:.2f}, {}",
                            cm.name,
                            t.part_count(),
                            bom.total,
                            out.check.stability.stable ? "stable" : "UNSTABLE");
  return out;
}

}  // namespace fabkit::templates

// Composing a model from its file, and checking it.
#include "fabkit/templates/check.h"

#include <fmt/format.h>

#include <chrono>

#include "fabkit/core/stop_clock.h"
#include "fabkit/core/yaml_reader.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/extract.h"
#include "fabkit/templates/manipulate.h"

namespace fabkit::templates {

namespace {

using Clock = std::chrono::steady_clock;

// Library diagnostics name no file; a model's steps give them their line.
void append_at(Diagnostics& into, const Diagnostics& from, const SourceLocation& where) {
  for (Diagnostic d : from) {
    if (!d.where.known()) d.where = where;
    into.add(std::move(d));
  }
}

bool past(const CheckOptions& o) {
  return deadline_passed(o.deadline);
}

std::string vec_text(const Vec3& v) {
  return fmt::format("[{:g}, {:g}, {:g}]", v.x(), v.y(), v.z());
}

std::optional<ElementId> element_by_name(const Template& t, std::string_view name) {
  for (int e = 0; e < t.element_count(); ++e) {
    if (t.element(ElementId(e)).name == name) return ElementId(e);
  }
  return std::nullopt;
}

std::vector<std::string> element_names(const Template& t) {
  std::vector<std::string> out;
  for (const Element& e : t.elements) out.push_back(e.name);
  return out;
}

void set_control(ComposedModel& cm,
                 NodeId node,
                 ControlKind kind,
                 double value,
                 const SourceLocation& where,
                 const ItemCatalog& catalog,
                 std::string& outcome) {
  Template& t = cm.model.model();
  const Manipulator m(t, {}, &catalog);
  const Control c = m.control(node, kind);
  if (c.hidden) {
    cm.diagnostics.error(
        codes::kFixedControl,
        fmt::format("{} of '{}' cannot change: the template's constraints fix it at {:g} mm",
                    to_string(kind),
                    t.node(node).name,
                    c.value),
        where);
    return;
  }
  const DragResult r = m.set(c, value);
  append_at(cm.diagnostics, r.diagnostics, where);
  if (r.diagnostics.has_errors()) return;
  t.q = r.q;
  outcome += fmt::format("{}{} {:g} mm{}",
                         outcome.empty() ? "" : "; ",
                         to_string(kind),
                         r.achieved,
                         r.reached ? "" : fmt::format(" (asked {:g})", value));
}

}  // namespace

ComposedModel compose_model(std::string_view yaml,
                            std::string_view file,
                            const TemplateDatabase& db,
                            const CheckOptions& options) {
  const auto start = Clock::now();
  ComposedModel cm;
  const auto kind = templates_file_kind(yaml, file, cm.diagnostics);
  if (!kind) return cm;
  if (*kind == TemplatesFileKind::kDesign) {
    // A source design on its own: the model of that one template.
    auto design = read_source_design(yaml, file, cm.diagnostics);
    if (!design) return cm;
    auto t = make_template(*design, &db.catalog(), cm.diagnostics);
    if (!t) return cm;
    cm.name = design->title;
    cm.description = design->description;
    cm.model = WorkingModel(design->name);
    cm.model.add(*t, design->name, design->name, std::nullopt, cm.diagnostics);
    cm.steps.push_back(
        {fmt::format("design {}", design->name),
         SourceLocation{std::string(file), 1, 1},
         true,
         fmt::format("{} parts, {} connections", t->part_count(), t->connections.size()),
         std::nullopt,
         std::nullopt});
    cm.readable = !cm.diagnostics.has_errors_of(DiagnosticClass::kInput);
    cm.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return cm;
  }
  auto file_model = read_model_file(yaml, file, cm.diagnostics);
  if (!file_model) return cm;
  cm.name = file_model->name.empty() ? std::string(file) : file_model->name;
  cm.description = file_model->description;
  cm.friction = file_model->friction;
  cm.model = WorkingModel("model");
  bool failed = false;
  bool stopped = false;
  SnapOptions snap_options = options.snap;
  snap_options.manipulate.deadline = options.deadline;
  ConnectOptions connect_options = options.connect;
  connect_options.manipulate.deadline = options.deadline;
  for (std::size_t i = 0; i < file_model->steps.size(); ++i) {
    const ModelStep& step = file_model->steps[i];
    if (past(options)) {
      cm.diagnostics.error(codes::kTimeLimit,
                           fmt::format("stopped at the deadline after {} iteration{} (model steps "
                                       "composed, of {}); this step and the rest were not "
                                       "composed",
                                       i,
                                       i == 1 ? "" : "s",
                                       file_model->steps.size()),
                           step.where);
      stopped = true;
      break;
    }
    StepReport report;
    report.where = step.where;
    report.text =
        fmt::format("add {} = {}{}", step.as, step.use, step.at ? " at " + vec_text(*step.at) : "");
    Diagnostics found;
    auto part = db.find(step.use, found);
    append_at(cm.diagnostics, found, step.where);
    if (!part) {
      report.ok = false;
      report.outcome = "unknown template";
      cm.steps.push_back(std::move(report));
      failed = true;
      continue;
    }
    Diagnostics added;
    auto comp = cm.model.add(*part, step.use, step.as, step.at, added);
    append_at(cm.diagnostics, added, step.where);
    if (!comp) {
      report.ok = false;
      cm.steps.push_back(std::move(report));
      failed = true;
      continue;
    }
    std::string outcome;
    for (const auto& [k, v] : step.set) {
      set_control(cm, comp->node, k, v, step.where, db.catalog(), outcome);
    }
    // A snap or connect cut short by the deadline fails for want of time, not because the
    // parts cannot meet: its errors become the time limit's.
    auto cut_short = [&](const Diagnostics& found_here, const char* what) {
      if (!found_here.has_errors() || !past(options)) return false;
      cm.diagnostics.error(codes::kTimeLimit,
                           fmt::format("stopped at the deadline while {} step {} of {}; this "
                                       "step and the rest were not composed",
                                       what,
                                       i + 1,
                                       file_model->steps.size()),
                           step.where);
      report.ok = false;
      report.outcome = "stopped at the deadline";
      cm.steps.push_back(std::move(report));
      stopped = true;
      return true;
    };
    if (i > 0 && step.snap) {
      SnapResult s = snap(cm.model, *comp, db, snap_options);
      if (cut_short(s.diagnostics, "snapping")) break;
      append_at(cm.diagnostics, s.diagnostics, step.where);
      cm.model.model().q = s.q;
      int from_source = 0;
      for (const SnapConstraint& c : s.chosen) from_source += c.from_source;
      outcome += fmt::format("{}snapped to {} plane{} ({} from {}, {} placements tried)",
                             outcome.empty() ? "" : "; ",
                             s.chosen.size(),
                             s.chosen.size() == 1 ? "" : "s",
                             from_source,
                             part->elements.empty() ? "its design" : part->elements.front().source,
                             s.combinations);
      report.snap = std::move(s);
    }
    if (i > 0 && step.connect) {
      ConnectResult c = connect(cm.model, *comp, db, connect_options);
      if (cut_short(c.diagnostics, "connecting")) break;
      append_at(cm.diagnostics, c.diagnostics, step.where);
      int joined = 0;
      std::vector<std::string> sources;
      for (const Link& l : c.links) {
        if (!l.connection) continue;
        ++joined;
        const Connection& conn = cm.model.model().connections[l.connection->value];
        std::vector<std::string> items;
        for (ElementId e : conn.connecting) items.push_back(cm.model.model().element(e).item);
        std::sort(items.begin(), items.end());
        items.erase(std::unique(items.begin(), items.end()), items.end());
        const std::string s = fmt::format("{} from {}", fmt::join(items, " + "), conn.source);
        if (std::find(sources.begin(), sources.end(), s) == sources.end()) sources.push_back(s);
      }
      outcome += fmt::format("{}connected {} of {} linked pair{}{}",
                             outcome.empty() ? "" : "; ",
                             joined,
                             c.links.size(),
                             c.links.size() == 1 ? "" : "s",
                             sources.empty() ? "" : fmt::format(" ({})", fmt::join(sources, "; ")));
      report.ok = !c.diagnostics.has_errors();
      report.connect = std::move(c);
    }
    report.outcome = outcome.empty() ? fmt::format("{} parts", part->part_count()) : outcome;
    cm.steps.push_back(std::move(report));
  }
  for (const Removal& r : file_model->remove) {
    if (stopped) break;  // what it names may be among the parts not composed
    const Template& t = cm.model.model();
    const NodeId n = t.find_node_or_element(r.node);
    if (!n.valid() || n == t.root()) {
      std::vector<std::string> names;
      for (std::size_t i = 1; i < t.nodes.size(); ++i)
        names.push_back(t.path(NodeId(static_cast<int>(i))));
      cm.diagnostics.error(codes::kUnknownName,
                           n.valid() ? std::string("the model's root cannot be removed")
                                     : fmt::format("the model has no node '{}' to remove{}",
                                                   r.node,
                                                   did_you_mean(r.node, names)),
                           r.where);
      continue;
    }
    StepReport report;
    report.where = r.where;
    report.text = fmt::format("remove {}", r.node);
    const int before = t.part_count();
    Diagnostics removed;
    report.ok = cm.model.remove(t.path(n), removed);
    append_at(cm.diagnostics, removed, r.where);
    report.outcome = report.ok ? fmt::format("{} parts removed (with their connections)",
                                             before - cm.model.model().part_count())
                               : "not removed";
    cm.steps.push_back(std::move(report));
  }
  for (const Adjustment& a : file_model->adjust) {
    if (stopped) break;
    if (past(options)) {
      cm.diagnostics.error(codes::kTimeLimit,
                           "stopped at the deadline after composing every step; this adjustment "
                           "and the rest were not made",
                           a.where);
      stopped = true;
      break;
    }
    const Template& t = cm.model.model();
    const NodeId n = t.find_node_or_element(a.node);
    if (!n.valid()) {
      std::vector<std::string> names;
      for (std::size_t i = 1; i < t.nodes.size(); ++i)
        names.push_back(t.path(NodeId(static_cast<int>(i))));
      cm.diagnostics.error(
          codes::kUnknownName,
          fmt::format("the model has no node '{}'{}", a.node, did_you_mean(a.node, names)),
          a.where);
      continue;
    }
    StepReport report;
    report.where = a.where;
    report.text = fmt::format("adjust {} {} to {:g} mm", a.node, to_string(a.control), a.value);
    set_control(cm, n, a.control, a.value, a.where, db.catalog(), report.outcome);
    cm.steps.push_back(std::move(report));
  }
  for (const LoadSpec& l : file_model->loads) {
    // A composition cut by the deadline lacks the parts it did not make: its loads cannot be
    // placed, and that is the deadline's doing, not an unknown name in the file.
    if (stopped) break;
    const auto e = element_by_name(cm.model.model(), l.part);
    if (!e) {
      cm.diagnostics.error(codes::kUnknownName,
                           fmt::format("a load names part '{}', which the model does not have{}",
                                       l.part,
                                       did_you_mean(l.part, element_names(cm.model.model()))),
                           l.where);
      continue;
    }
    cm.loads.push_back(Load{*e, l.at, l.force});
  }
  (void)failed;
  cm.readable = !cm.diagnostics.has_errors_of(DiagnosticClass::kInput);
  cm.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return cm;
}

CheckResult check(const ComposedModel& cm,
                  const TemplateDatabase& db,
                  const CheckOptions& options) {
  CheckResult out;
  out.diagnostics.append(cm.diagnostics);
  if (!cm.readable) {
    out.verdict = "unreadable";
    return out;
  }
  const Template& t = cm.model.model();
  auto stop = [&](const char* before) {
    if (!cm.diagnostics.has_errors_of(DiagnosticClass::kTimeout)) {
      out.diagnostics.error(codes::kTimeLimit,
                            fmt::format("stopped at the deadline before {}", before));
    }
    out.verdict = "stopped at the deadline";
    return out;
  };
  // A composition the deadline cut is missing parts: its overlaps and balance mean nothing.
  if (cm.diagnostics.has_errors_of(DiagnosticClass::kTimeout) || past(options))
    return stop("checking for overlaps");
  // Principal parts that interpenetrate cannot be built.
  for (int a = 0; a < t.element_count(); ++a) {
    if (!t.element(ElementId(a)).is_principal()) continue;
    for (int b = a + 1; b < t.element_count(); ++b) {
      if (!t.element(ElementId(b)).is_principal()) continue;
      const Box ba = t.box(ElementId(a)), bb = t.box(ElementId(b));
      if (!ba.intersects(bb, options.overlap_tolerance_mm)) continue;
      out.diagnostics.error(codes::kPartsOverlap,
                            fmt::format("'{}' and '{}' overlap by {:g} x {:g} x {:g} mm",
                                        t.element(ElementId(a)).name,
                                        t.element(ElementId(b)).name,
                                        std::round(ba.overlap(bb, 0) * 10) / 10,
                                        std::round(ba.overlap(bb, 1) * 10) / 10,
                                        std::round(ba.overlap(bb, 2) * 10) / 10));
    }
  }
  if (past(options)) return stop("the stability verdict was known");
  StabilityOptions so = options.stability;
  so.friction = cm.friction;
  so.loads = cm.loads;
  so.deadline = options.deadline;
  out.stability = check_stability(t, db.catalog(), so);
  if (out.stability.timed_out) return stop("the stability verdict was known");
  out.diagnostics.append(out.stability.diagnostics);
  if (past(options)) return stop("the bill of materials and cut plans");
  BomOptions bo = options.bom;
  if (options.deadline) {
    const double left = std::chrono::duration<double>(*options.deadline - Clock::now()).count();
    bo.cut_plan.time_limit_s = std::clamp(left / 2, 0.01, bo.cut_plan.time_limit_s);
  }
  Diagnostics bom_diags;
  out.bom = bill_of_materials(t, db.catalog(), bom_diags, bo);
  out.diagnostics.append(bom_diags);
  if (out.diagnostics.has_errors_of(DiagnosticClass::kInfeasible)) {
    out.verdict = "infeasible";
  } else if (!out.stability.stable) {
    out.verdict = "unstable";
  } else if (out.diagnostics.has_errors()) {
    out.verdict = "check failed";
  } else {
    out.verdict = "feasible";
  }
  return out;
}

}  // namespace fabkit::templates

// The templates kit's commands: check and build of a working model, and browsing the
// bundled database (fabkit templates list | show NAME).
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "fabkit/templates/build.h"
#include "fabkit/templates/check.h"
#include "fabkit/templates/database.h"
#include "kits.h"

namespace fabkit::cli {

namespace {

templates::CheckOptions options_of(const DesignSettings& settings) {
  templates::CheckOptions o;
  if (settings.time_limit_s) {
    o.deadline = std::chrono::steady_clock::now() +
                 std::chrono::microseconds(static_cast<long long>(*settings.time_limit_s * 1e6));
  }
  return o;
}

templates::ComposedModel compose(const DesignInput& input, const templates::CheckOptions& o) {
  return templates::compose_model(
      input.text, input.settings.design, templates::TemplateDatabase::bundled(), o);
}

void print_model(const templates::ComposedModel& cm, const templates::CheckResult& r, bool quiet) {
  if (!quiet) {
    for (const templates::StepReport& s : cm.steps) {
      const std::string where =
          s.where.known() ? fmt::format("{}:{}: ", s.where.file, s.where.line) : std::string();
      std::printf("%s%s: %s\n", where.c_str(), s.text.c_str(), s.outcome.c_str());
    }
  }
  for (const Diagnostic& d : r.diagnostics) {
    if (!quiet || d.severity != Severity::kNote) print_diagnostic(d);
  }
  if (!cm.readable) return;
  const templates::Template& t = cm.model.model();
  if (!quiet) {
    for (const templates::Body& b : r.stability.bodies) {
      std::vector<std::string> names;
      for (templates::ElementId e : b.elements) names.push_back(t.element(e).name);
      std::printf("  %-9s %6.1f kg  %s\n",
                  b.verdict.c_str(),
                  b.mass_kg,
                  fmt::format("{}", fmt::join(names, ", ")).substr(0, 90).c_str());
    }
  }
  std::printf(
      "%s: %s — %d parts, %zu connections, %s, %s\n",
      cm.name.c_str(),
      r.verdict.c_str(),
      t.part_count(),
      t.connections.size(),
      r.diagnostics.has_errors_of(DiagnosticClass::kTimeout) ? "not checked"
      : r.stability.stable                                   ? "stable"
                                                             : "UNSTABLE",
      r.bom ? fmt::format("materials ${:.2f}", r.bom->total).c_str() : "no bill of materials");
}

}  // namespace

int templates_check(const DesignInput& input) {
  const templates::CheckOptions o = options_of(input.settings);
  const templates::ComposedModel cm = compose(input, o);
  const templates::CheckResult r = templates::check(cm, templates::TemplateDatabase::bundled(), o);
  print_model(cm, r, input.settings.quiet);
  if (!cm.readable && !r.diagnostics.has_errors()) return kExitBadInput;
  return exit_code(r.diagnostics);
}

int templates_build(const DesignInput& input) {
  templates::BuildOptions bo;
  bo.check = options_of(input.settings);
  const templates::ComposedModel cm = compose(input, bo.check);
  const templates::BuildSummary s =
      templates::build(cm, templates::TemplateDatabase::bundled(), input.settings.output_dir, bo);
  print_model(cm, s.check, input.settings.quiet);
  for (const Diagnostic& d : s.diagnostics) {
    if (d.kind() == DiagnosticClass::kIo) print_diagnostic(d);
  }
  if (!input.settings.quiet) {
    for (const auto& p : s.written) std::printf("wrote %s\n", p.string().c_str());
    for (const auto& st : s.timings)
      std::printf("  %-18s %8.1f ms\n", st.stage.c_str(), st.milliseconds);
  }
  std::printf("%s\n", s.message.c_str());
  if (s.termination == templates::BuildTermination::kWriteFailed) return kExitWriteFailed;
  if (!cm.readable && !s.diagnostics.has_errors()) return kExitBadInput;
  return exit_code(s.diagnostics);
}

int run_templates(const TemplatesSettings& settings) {
  const templates::TemplateDatabase& db = templates::TemplateDatabase::bundled();
  if (settings.action == "list") {
    std::printf("%zu source designs (every node of each is a template: use design/path):\n",
                db.names().size());
    for (const std::string& name : db.names()) {
      const templates::Template* t = db.source_template(name);
      int nodes = 0;
      for (const templates::Node& n : t->nodes) nodes += !n.connection_node && !n.element;
      std::printf("  %-18s %-24s %-9s %4d parts, %2zu connections, %d sub-assemblies\n",
                  name.c_str(),
                  t->title.c_str(),
                  t->category.c_str(),
                  t->part_count(),
                  t->connections.size(),
                  nodes);
    }
    std::printf("%zu catalog items; fabkit templates show NAME for one template\n",
                db.catalog().size());
    return kExitOk;
  }
  Diagnostics d;
  const auto t = db.find(settings.name, d);
  if (!t) {
    print_diagnostics(d);
    return kExitBadInput;
  }
  std::fputs(templates::describe_template(*t, db.catalog()).c_str(), stdout);
  if (const templates::SourceDesign* sd = db.design(settings.name);
      sd && !sd->description.empty()) {
    std::printf("about: %s", sd->description.c_str());
  }
  return kExitOk;
}

}  // namespace fabkit::cli

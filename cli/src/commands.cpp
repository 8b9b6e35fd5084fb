#include "commands.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "embedded_examples.h"
#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/parts_library.h"

namespace fabkit::cli {
namespace {

using hacks::Design;
using hacks::DesignStep;

void print_diagnostic(const Diagnostic& d) {
  std::fprintf(stderr, "%s\n", d.format().c_str());
}

std::string where_prefix(const SourceLocation& where) {
  if (!where.known()) return "";
  return where.line > 0 ? fmt::format("{}:{}: ", where.file, where.line) : where.file + ": ";
}

void print_steps(const Design& design) {
  for (const DesignStep& step : design.steps) {
    std::string outcome;
    if (step.skipped) {
      outcome = "skipped";
    } else if (!step.accepted) {
      outcome = "REJECTED";
    } else if (step.report.closes_cycle) {
      outcome = fmt::format("ok, closes cycle {} ({} start{}, {:.1f} ms)",
                            step.report.cycles.empty() ? "" : step.report.cycles.front(),
                            step.report.starts_used,
                            step.report.starts_used == 1 ? "" : "s",
                            step.report.milliseconds);
    } else {
      outcome = "ok";
    }
    std::printf("%s%s: %s\n", where_prefix(step.where).c_str(), step.text.c_str(), outcome.c_str());
  }
}

int exit_code_for(const Design& design) {
  for (const Diagnostic& d : design.diagnostics) {
    if (hacks::is_input_error(d)) return kExitBadInput;
  }
  if (!design.readable) return kExitBadInput;
  return design.diagnostics.has_errors() ? kExitInfeasible : kExitOk;
}

void print_summary(const Design& design) {
  const hacks::Assembly& a = design.assembly;
  const std::size_t cycles = a.cycle_connections().size();
  int rejected = 0;
  for (const DesignStep& s : design.steps) rejected += (!s.accepted && !s.skipped) ? 1 : 0;
  const char* verdict =
      design.feasible() ? "valid" : (design.readable ? "infeasible" : "unreadable");
  std::printf(
      "%s: %s — %d parts, %zu connections (%zu close%s a cycle), %d connector parameters%s\n",
      design.name.empty() ? "design" : design.name.c_str(),
      verdict,
      a.part_count(),
      a.connections().size(),
      cycles,
      cycles == 1 ? "s" : "",
      a.parameter_count(),
      rejected ? fmt::format("; {} step{} rejected", rejected, rejected == 1 ? "" : "s").c_str()
               : "");
}

int check_design(Design design, bool quiet) {
  if (!quiet) print_steps(design);
  for (const Diagnostic& d : design.diagnostics) print_diagnostic(d);
  if (design.readable) print_summary(design);
  return exit_code_for(design);
}

}  // namespace

int run_check(const CheckSettings& settings) {
  hacks::PartsLibrary library = hacks::PartsLibrary::builtin();
  for (const std::string& file : settings.part_files) {
    Diagnostics d;
    if (!library.load_yaml(file, d)) {
      for (const Diagnostic& x : d) print_diagnostic(x);
      return kExitBadInput;
    }
  }
  hacks::DesignOptions options;
  options.verify.restarts = settings.restarts;
  options.verify.seed = settings.seed;
  return check_design(hacks::load_design(settings.design, library, options), settings.quiet);
}

int run_demo() {
  std::printf("fabkit demo: the bird feeder hack of the FabHacks paper (Fig. 1, left)\n\n");
  Design design =
      hacks::load_design_text(kDemoDesign, kDemoDesignName, hacks::PartsLibrary::builtin());
  return check_design(std::move(design), false);
}

int run_parts(const PartsSettings& settings) {
  const hacks::PartsLibrary& library = hacks::PartsLibrary::builtin();
  if (settings.name.empty()) {
    for (const hacks::PartGenerator& g : library.generators()) {
      Diagnostics d;
      auto part = library.make(g.name, {}, d);
      std::printf("%-20s %-12s %s\n",
                  g.name.c_str(),
                  std::string(to_string(g.category)).c_str(),
                  part ? part->primitive_list().c_str() : "");
    }
    return kExitOk;
  }
  Diagnostics d;
  auto part = library.make(settings.name, {}, d);
  if (!part) {
    for (const Diagnostic& x : d) print_diagnostic(x);
    return kExitBadInput;
  }
  const hacks::PartGenerator* g = library.find(settings.name);
  std::printf("%s — %s\n  mass %.1f (mm³ at density 1), centre of mass [%.1f, %.1f, %.1f] mm\n",
              part->type_name.c_str(),
              part->description.c_str(),
              part->mass,
              part->center_of_mass.x(),
              part->center_of_mass.y(),
              part->center_of_mass.z());
  for (const hacks::ParamSchema& p : g->params) {
    std::printf("  parameter %s = %g %s (%g to %g): %s\n",
                p.name.c_str(),
                p.default_value,
                p.unit.c_str(),
                p.min,
                p.max,
                p.doc.c_str());
  }
  for (const hacks::Primitive& prim : part->primitives) {
    std::printf("  %-12s %s at %s\n",
                prim.name.c_str(),
                prim.describe().c_str(),
                prim.frame.to_string().c_str());
    for (const hacks::ParamSpec& s : prim.connector_params()) {
      std::printf("  %14s %-6s init %g in [%g, %g] %s\n",
                  "",
                  s.name.c_str(),
                  s.init,
                  s.lo,
                  s.hi,
                  std::string(to_string(s.tag)).c_str());
    }
  }
  return kExitOk;
}

}  // namespace fabkit::cli

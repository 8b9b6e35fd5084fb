// The hacks kit's commands: check, solve/build (with exports), demo and parts.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>

#include "commands.h"
#include "embedded_examples.h"
#include "fabkit/core/file_io.h"
#include "fabkit/core/parallel.h"
#include "fabkit/hacks/deadline.h"
#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/parts_library.h"
#include "fabkit/hacks/solution_export.h"
#include "fabkit/hacks/solve.h"
#include "kits.h"

namespace fabkit::cli {
namespace {

using hacks::Design;
using hacks::DesignStep;

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
  if (!design.readable && !design.diagnostics.has_errors()) return kExitBadInput;
  return exit_code(design.diagnostics);
}

void print_summary(const Design& design) {
  const hacks::Assembly& a = design.assembly;
  const std::size_t cycles = a.cycle_connections().size();
  int rejected = 0;
  for (const DesignStep& s : design.steps) rejected += (!s.accepted && !s.skipped) ? 1 : 0;
  const char* verdict = design.feasible()  ? "valid"
                        : !design.readable ? "unreadable"
                        : design.diagnostics.has_errors_of(DiagnosticClass::kTimeout)
                            ? "stopped at the deadline"
                            : "infeasible";
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

// The built-in library plus the user's part files; nullopt (diagnostics printed) on error.
static std::optional<hacks::PartsLibrary> library_with(const std::vector<std::string>& part_files) {
  hacks::PartsLibrary library = hacks::PartsLibrary::builtin();
  for (const std::string& file : part_files) {
    Diagnostics d;
    if (!library.load_yaml(file, d)) {
      print_diagnostics(d);
      return std::nullopt;
    }
  }
  return library;
}

static std::optional<std::chrono::steady_clock::time_point> deadline_of(
    const DesignSettings& settings) {
  if (!settings.time_limit_s) return std::nullopt;
  return std::chrono::steady_clock::now() +
         std::chrono::microseconds(static_cast<long long>(*settings.time_limit_s * 1e6));
}

// The design of `input`, verified with the command line's options.
static Design load(const DesignInput& input, const hacks::PartsLibrary& library) {
  hacks::DesignOptions options;
  options.verify.restarts = input.settings.restarts;
  options.verify.seed = input.settings.seed;
  options.verify.deadline = deadline_of(input.settings);
  const std::filesystem::path path(input.settings.design);
  Design design =
      hacks::load_design_text(input.text, path.string(), library, options, path.parent_path());
  design.source = path;
  return design;
}

int hacks_check(const DesignInput& input) {
  const std::optional<hacks::PartsLibrary> library = library_with(input.settings.part_files);
  if (!library) return kExitBadInput;
  return check_design(load(input, *library), input.settings.quiet);
}

namespace {

std::string stage_title(std::string_view stage) {
  if (stage == "step1") return "step 1: reaching the target";
  if (stage == "step2") return "step 2: relaxing under gravity";
  return "checking stability";
}

void print_parts_table(const hacks::SolveResult& r) {
  std::printf("\n  %-22s %-18s %28s   %s\n", "part", "type", "position (mm)", "rotation (deg)");
  for (const hacks::SolvedPart& p : r.parts) {
    Frame f = p.frame.normalized();
    // Round first so tiny negatives print as 0.0, not -0.0.
    for (int i = 0; i < 3; ++i) {
      f.pos[i] = std::round(f.pos[i] * 10) / 10 + 0.0;
      f.rot[i] = std::round(f.rot[i] * 10) / 10 + 0.0;
      if (f.rot[i] >= 360.0) f.rot[i] -= 360.0;
    }
    std::printf("  %-22s %-18s [%8.1f %8.1f %8.1f]   [%6.1f %6.1f %6.1f]%s\n",
                p.name.c_str(),
                p.type.c_str(),
                f.pos.x(),
                f.pos.y(),
                f.pos.z(),
                f.rot.x(),
                f.rot.y(),
                f.rot.z(),
                p.environment ? "  (environment)" : (p.target ? "  (target)" : ""));
  }
  std::printf("\n");
}

// Where exported parts' solids are kept between runs (part_solid.h), so that only the first
// export of a part type on this machine runs the exact unions: $FABKIT_CACHE_DIR, else
// $XDG_CACHE_HOME/fabkit, else ~/.cache/fabkit, with solids/ under it; empty (memory only)
// when none is set.
std::filesystem::path solid_cache_directory() {
  const auto env = [](const char* name) -> std::filesystem::path {
    const char* value = std::getenv(name);
    return value && *value ? std::filesystem::path(value) : std::filesystem::path();
  };
  std::filesystem::path base = env("FABKIT_CACHE_DIR");
  if (base.empty() && !env("XDG_CACHE_HOME").empty()) base = env("XDG_CACHE_HOME") / "fabkit";
  if (base.empty() && !env("HOME").empty()) base = env("HOME") / ".cache" / "fabkit";
  return base.empty() ? base : base / "solids";
}

// Verifies, solves and exports one design; prints progress as it goes.
int solve_design(Design design, const DesignSettings& settings, bool write) {
  const bool talk = !settings.quiet;
  if (talk) {
    std::printf("verifying %zu steps of %s ... ",
                design.steps.size(),
                design.name.empty() ? "the design" : design.name.c_str());
    std::fflush(stdout);
  }
  double verify_ms = 0;
  for (const DesignStep& s : design.steps) verify_ms += s.report.milliseconds;
  const int check = exit_code_for(design);
  if (check != kExitOk) {
    if (talk) std::printf("failed\n");
    for (const Diagnostic& d : design.diagnostics) print_diagnostic(d);
    return check;
  }
  if (talk) std::printf("ok (%.1f ms)\n", verify_ms);
  for (const Diagnostic& d : design.diagnostics) print_diagnostic(d);

  hacks::SolveOptions options;
  options.seed = settings.seed;
  options.deadline = deadline_of(settings);
  std::string open_stage;
  auto started = std::chrono::steady_clock::now();
  auto close_stage = [&] {
    if (open_stage.empty() || !talk) return;
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started)
            .count();
    std::printf("done (%.1f ms)\n", ms);
  };
  options.on_stage = [&](std::string_view stage) {
    close_stage();
    open_stage = std::string(stage);
    started = std::chrono::steady_clock::now();
    if (talk) {
      std::printf("%s ... ", stage_title(stage).c_str());
      std::fflush(stdout);
    }
  };
  hacks::SolveResult result = hacks::solve(design.assembly, options);
  close_stage();
  result.timings.insert(result.timings.begin(), {"verify", verify_ms});
  for (const Diagnostic& d : result.diagnostics) print_diagnostic(d);
  // Infeasible without a pose (no closed configuration): nothing to show or write. A pose in
  // which parts pass through each other is infeasible too, but it is written, to be seen.
  if (!result.feasible && result.parts.empty()) {
    std::fprintf(stderr, "error: %s\n", result.message.c_str());
    return result.diagnostics.has_errors() ? exit_code(result.diagnostics) : kExitInfeasible;
  }
  if (talk) {
    print_parts_table(result);
    std::printf("%s\n", result.summary().c_str());
  } else {
    std::printf("%s: %s\n", design.name.c_str(), result.message.c_str());
  }
  if (write && !settings.output_dir.empty()) {
    Diagnostics d;
    hacks::ExportOptions eo;
    eo.design_name = design.name;
    hacks::PartSolidCache solids(solid_cache_directory());
    eo.solids = &solids;
    const bool written =
        hacks::export_solution(design.assembly, result, settings.output_dir, d, eo);
    // Also the warnings of a written export (a part kept as its display mesh).
    print_diagnostics(d);
    if (!written) return exit_code(d);
    if (talk) {
      int shells = 0;  // the cache holds every part's solid now
      bool all_solid = true;
      for (const hacks::PartNode& n : design.assembly.nodes()) {
        const hacks::PartSolid& s = solids.solid(*n.part);
        shells += s.shells;
        all_solid = all_solid && s.exact;
      }
      std::printf(
          "wrote %s/result.json, scene.glb (open it in any glTF viewer), assembly.stl, "
          "assembly.obj (%d parts as %d %s)\n",
          settings.output_dir.c_str(),
          design.assembly.part_count(),
          shells,
          all_solid ? "closed shells" : "shells, see the warnings");
    }
  }
  for (const hacks::Slip& s : result.slips) {
    std::fprintf(stderr, "error: falls apart: %s\n", s.message.c_str());
  }
  if (!result.remedy.empty()) std::fprintf(stderr, "note: %s\n", result.remedy.c_str());
  if (result.termination == hacks::Termination::kTimeout) {
    std::fprintf(stderr, "error: %s\n", hacks::stopped_at_deadline(result, options).c_str());
    return kExitTimeLimit;
  }
  // The exit code follows the verdict (SolveResult::verdict, in its order): parts passing
  // through each other are infeasible as found even where a connection also slips.
  switch (result.verdict()) {
    case hacks::Verdict::kStable:
      return kExitOk;
    case hacks::Verdict::kFallsApart:
      return kExitFallsApart;
    case hacks::Verdict::kStopped:  // handled above: a time limit is said first
    case hacks::Verdict::kPartsPassThrough:
    case hacks::Verdict::kInfeasible:
    case hacks::Verdict::kNotAtRest:
      break;
  }
  // Said once: the verdict's message is usually one of the diagnostics printed above.
  const bool said = std::any_of(result.diagnostics.begin(),
                                result.diagnostics.end(),
                                [&](const Diagnostic& d) { return d.message == result.message; });
  if (!said) std::fprintf(stderr, "error: %s\n", result.message.c_str());
  return kExitInfeasible;
}

// The solver's helper threads are started before the design is read, so that they are running
// by the time step 1 needs them (a new thread can wait milliseconds for its first turn).
void start_solver_threads() {
  fabkit::start_helper_threads(hacks::SolveOptions{}.threads);
}

}  // namespace

int run_solve(const DesignSettings& settings) {
  start_solver_threads();
  Diagnostics d;
  const auto text = read_input_file(settings.design, "design file", d);
  if (!text) {
    print_diagnostics(d);
    return exit_code(d);
  }
  const std::optional<hacks::PartsLibrary> library = library_with(settings.part_files);
  if (!library) return kExitBadInput;
  return solve_design(load(DesignInput{settings, *text}, *library), settings, true);
}

int hacks_build(const DesignInput& input) {
  start_solver_threads();
  const std::optional<hacks::PartsLibrary> library = library_with(input.settings.part_files);
  if (!library) return kExitBadInput;
  return solve_design(load(input, *library), input.settings, true);
}

int run_demo(const DemoSettings& settings) {
  start_solver_threads();
  std::printf("fabkit demo: the bird feeder hack of the FabHacks paper (Fig. 1, left)\n\n");
  Design design =
      hacks::load_design_text(kDemoDesign, kDemoDesignName, hacks::PartsLibrary::builtin());
  print_steps(design);
  std::printf("\n");
  DesignSettings solve;
  solve.output_dir = settings.output_dir;
  return solve_design(std::move(design), solve, true);
}

int run_parts(const PartsSettings& settings) {
  const std::optional<hacks::PartsLibrary> loaded = library_with(settings.part_files);
  if (!loaded) return kExitBadInput;
  const hacks::PartsLibrary& library = *loaded;
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

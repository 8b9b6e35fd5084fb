// The rods kit's commands: check and build (joints, cut plan, assembly order, report).
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "fabkit/rods/build.h"
#include "fabkit/rods/design_file.h"
#include "fabkit/rods/outputs.h"
#include "kits.h"

namespace fabkit::cli {
namespace {

rods::Design load(const DesignInput& input) {
  const std::filesystem::path path(input.settings.design);
  rods::Design design = rods::load_design_text(input.text, path.string(), path.parent_path());
  design.source = path;
  return design;
}

rods::BuildOptions options_of(const DesignSettings& settings) {
  rods::BuildOptions o;
  o.joint.engraving.seed = settings.seed;
  o.cut_plan.seed = settings.seed;
  if (settings.time_limit_s) {
    o.deadline = std::chrono::steady_clock::now() +
                 std::chrono::microseconds(static_cast<long long>(*settings.time_limit_s * 1e6));
    o.cut_plan.time_limit_s = std::min(o.cut_plan.time_limit_s, *settings.time_limit_s / 2);
  }
  return o;
}

void print_summary(const rods::Design& design, const rods::Summary& s, bool joints_table) {
  const rods::Structure& st = design.structure;
  const rods::Parameters& p = design.parameters;
  const char* name = design.name.empty() ? "design" : design.name.c_str();
  if (joints_table && !s.joints.empty() && s.joints.size() <= 40) {
    std::printf(
        "\n  %-6s %-5s %-28s %10s %9s\n", "joint", "rods", "offsets g (mm)", "volume", "ID text");
    for (const rods::JointSolid& j : s.joints) {
      std::string offsets;
      for (const rods::RodEnd* end : s.layout.ends_at(j.node)) {
        offsets += fmt::format("{}{:.1f}", offsets.empty() ? "" : " ", end->offset);
      }
      if (offsets.size() > 28) offsets = offsets.substr(0, 25) + "...";
      std::printf("  %-6s %-5zu %-28s %7.2f cm³ %6.1f mm\n",
                  j.label.c_str(),
                  s.layout.rods_at[static_cast<std::size_t>(j.node)].size(),
                  offsets.c_str(),
                  j.volume / 1000,
                  j.text_height);
    }
    std::printf("\n");
  }
  double shortest = 1e300, longest = 0, total = 0;
  for (const double l : s.layout.rod_length) {
    shortest = std::min(shortest, l);
    longest = std::max(longest, l);
    total += std::max(0.0, l);
  }
  std::printf(
      "%s: %zu joints, %zu rods of radius %g mm (%s), lengths %.1f to %.1f mm (%.2f m in all)\n",
      name,
      st.nodes.size(),
      st.rods.size(),
      p.radius,
      p.circular() ? "round" : fmt::format("{}-sided", p.sides).c_str(),
      shortest,
      longest,
      total / 1000);
  if (s.cut_plan) {
    const CutPlan& c = *s.cut_plan;
    const std::string verdict =
        c.proven_optimal ? std::string("proven optimal")
                         : fmt::format("{} above the lower bound {}", c.gap(), c.lower_bound);
    std::printf("  cut plan: %d stock rod%s of %g mm, %s (end padding %g mm, kerf %g mm)\n",
                c.stock_count(),
                c.stock_count() == 1 ? "" : "s",
                p.stock.length,
                verdict.c_str(),
                p.stock.end_padding,
                p.stock.kerf);
  }
  const rods::Balance& b = s.checks.balance;
  std::printf("  balance: %s, margin %.1f mm (%.2f kg on %zu floor contact%s)\n",
              b.stands ? "stands" : "TIPS OVER",
              b.margin,
              b.mass,
              b.ground_nodes.size(),
              b.ground_nodes.size() == 1 ? "" : "s");
  if (s.frame.solved) {
    std::printf("  structure: largest utilisation %.2f (%s), largest deflection %.2f mm (%s)\n",
                s.frame.max_utilisation,
                s.frame.critical_rod >= 0 ? st.rod_name(s.frame.critical_rod).c_str() : "-",
                s.frame.max_deflection,
                s.frame.max_deflection_node >= 0
                    ? st.joint_name(s.frame.max_deflection_node).c_str()
                    : "-");
  }
  std::printf("  assembly: %zu steps, depth-first from %s\n",
              s.assembly.size(),
              s.assembly.empty() ? "-" : st.joint_name(s.assembly.front().joint).c_str());
  std::printf("%s: %s\n", name, s.message.c_str());
}

int verdict(const rods::Summary& s) {
  return exit_code(s.diagnostics);
}

}  // namespace

int rods_check(const DesignInput& input) {
  const rods::Design design = load(input);
  if (!design.readable) {
    print_diagnostics(design.diagnostics);
    return design.diagnostics.has_errors() ? exit_code(design.diagnostics) : kExitBadInput;
  }
  const rods::Summary s = rods::check(design, options_of(input.settings));
  for (const Diagnostic& d : s.diagnostics) {
    if (!input.settings.quiet || d.severity == Severity::kError) print_diagnostic(d);
  }
  if (!input.settings.quiet) {
    print_summary(design, s, false);
  } else {
    std::printf(
        "%s: %s\n", design.name.empty() ? "design" : design.name.c_str(), s.message.c_str());
  }
  return verdict(s);
}

int rods_build(const DesignInput& input) {
  const rods::Design design = load(input);
  if (!design.readable) {
    print_diagnostics(design.diagnostics);
    return design.diagnostics.has_errors() ? exit_code(design.diagnostics) : kExitBadInput;
  }
  const bool talk = !input.settings.quiet;
  rods::BuildOptions options = options_of(input.settings);
  const bool bar = talk && isatty(fileno(stderr));
  if (bar) {
    options.on_progress = [](int done, int total) {
      const int width = 30, filled = total ? width * done / total : width;
      std::fprintf(stderr,
                   "\rbuilding joints (exact booleans) [%s%s] %d/%d",
                   std::string(static_cast<std::size_t>(filled), '#').c_str(),
                   std::string(static_cast<std::size_t>(width - filled), '.').c_str(),
                   done,
                   total);
      if (done == total) std::fprintf(stderr, "\n");
      std::fflush(stderr);
    };
  } else if (talk) {
    std::printf("building %zu joints (exact booleans, %d threads) ...\n",
                design.structure.nodes.size(),
                options.threads);
    std::fflush(stdout);
  }
  const auto started = std::chrono::steady_clock::now();
  const rods::Summary s = rods::build(design, options);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  for (const Diagnostic& d : s.diagnostics) {
    if (talk || d.severity == Severity::kError) print_diagnostic(d);
  }
  if (s.termination == rods::Termination::kFailed ||
      s.termination == rods::Termination::kInfeasible ||
      s.termination == rods::Termination::kTimeLimit) {
    std::printf("%s: %s; nothing written\n",
                design.name.empty() ? "design" : design.name.c_str(),
                s.message.c_str());
    return verdict(s);
  }
  Diagnostics io;
  const auto written = rods::write_outputs(design, s, input.settings.output_dir, io);
  print_diagnostics(io);
  if (io.has_errors()) return exit_code(io);
  if (talk) {
    print_summary(design, s, true);
    std::printf("built in %.1f s; wrote %zu files to %s: ",
                seconds,
                written.size(),
                input.settings.output_dir.c_str());
    std::size_t stl = 0;
    for (const auto& f : written)
      stl += f.extension() == ".stl" && f.filename() != "tolerance_board.stl" ? 1 : 0;
    std::string others;
    for (const auto& f : written) {
      if (f.extension() == ".stl" && f.filename() != "tolerance_board.stl") continue;
      others += (others.empty() ? "" : ", ") + f.filename().string();
    }
    std::printf("%zu joint STLs (joint_%s.stl, ...), %s\n",
                stl,
                design.structure.joint_label(0).c_str(),
                others.c_str());
  } else {
    std::printf(
        "%s: %s\n", design.name.empty() ? "design" : design.name.c_str(), s.message.c_str());
  }
  return verdict(s);
}

}  // namespace fabkit::cli

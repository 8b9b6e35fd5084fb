// The flatpack kit's commands: check (placement, joints, warnings, assembly order) and build
// (cut sheets, 3D model, report).
#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "fabkit/flatpack/build.h"
#include "fabkit/flatpack/burn_test.h"
#include "fabkit/flatpack/check.h"
#include "fabkit/flatpack/design_file.h"
#include "kits.h"

namespace fabkit::cli {
namespace {

using namespace fabkit::flatpack;

void print_analysis(const Analysis& a, bool quiet) {
  if (!quiet && a.placed) {
    std::printf(
        "%-24s %-14s %8s  %-28s %s\n", "piece", "material", "t (mm)", "position (mm)", "normal");
    for (const Piece& p : a.pieces) {
      const Vec3 o = p.frame.topRightCorner<3, 1>(), n = p.frame.block<3, 1>(0, 2);
      std::printf("%-24s %-14s %8.1f  [%7.1f %7.1f %7.1f]   [%4.1f %4.1f %4.1f]%s\n",
                  p.name.c_str(),
                  p.material.name.c_str(),
                  p.material.thickness_mm,
                  o.x() + 0.0,
                  o.y() + 0.0,
                  o.z() + 0.0,
                  n.x() + 0.0,
                  n.y() + 0.0,
                  n.z() + 0.0,
                  p.components.size() > 1
                      ? fmt::format("  (merged from {})", p.components.size()).c_str()
                      : "");
    }
    std::printf(
        "\n%-4s %-14s %-38s %9s %7s  %s\n", "id", "kind", "pieces", "length", "fingers", "from");
    for (const Joint& j : a.joints) {
      const std::string pieces = a.pieces[static_cast<std::size_t>(j.piece_a)].name + " – " +
                                 a.pieces[static_cast<std::size_t>(j.piece_b)].name;
      std::printf("%-4d %-14s %-38s %6.1f mm %7d  %s\n",
                  j.id,
                  std::string(to_string(j.kind)).c_str(),
                  pieces.c_str(),
                  j.length_mm,
                  j.fingers,
                  j.automatic() ? "automatic" : "connection");
    }
    if (!a.assembly.empty()) {
      std::printf("\nassembly order:");
      for (std::size_t k = 0; k < a.assembly.size(); ++k) {
        const AssemblyStep& st = a.assembly[k];
        std::printf("%s %zu. %s%s",
                    k ? "," : "",
                    k + 1,
                    a.pieces[static_cast<std::size_t>(st.piece)].name.c_str(),
                    st.group ? fmt::format(" (sub-assembly {})", st.group).c_str() : "");
      }
      std::printf("\n");
    }
  }
  if (!quiet && !a.meta_parameters.empty()) {
    std::printf("\nmeta-parameters:");
    for (std::size_t k = 0; k < a.meta_parameters.size(); ++k) {
      const std::string& m = a.meta_parameters[k];
      const auto drives = a.meta_drives.find(m);
      // Absent: the check stopped at its deadline before this one's effect was worked out.
      const std::string effect = drives == a.meta_drives.end()
                                     ? std::string("what it drives not worked out")
                                     : fmt::format("drives {} dimension{}",
                                                   drives->second.size(),
                                                   drives->second.size() == 1 ? "" : "s");
      std::printf("%s %s = %g (%s)",
                  k ? "," : "",
                  m.c_str(),
                  a.values.count(m) ? a.values.at(m) : 0.0,
                  effect.c_str());
    }
    std::printf("\n");
  }
  for (const Diagnostic& d : a.diagnostics) {
    if (d.severity != Severity::kNote || !quiet) print_diagnostic(d);
  }
  std::printf(
      "%s: %s — %zu components, %zu pieces, %d joints (%d from connections, %d automatic; %d "
      "finger-finger, %d finger-hole, %d slot-slot cut)\n",
      a.name.empty() ? "design" : a.name.c_str(),
      a.diagnostics.has_errors_of(DiagnosticClass::kTimeout)
          ? "stopped at the deadline"
          : (a.diagnostics.has_errors() ? (a.placed ? "built with failed checks" : "invalid")
                                        : "valid"),
      a.components.size(),
      a.pieces.size(),
      a.graph_joints(),
      a.user_connection_joints(),
      a.automatic_joints(),
      a.joints_of(JointKind::kFingerFinger),
      a.joints_of(JointKind::kFingerHole),
      a.joints_of(JointKind::kSlotSlot));
}

std::optional<Design> read(const DesignInput& input) {
  Diagnostics d;
  const std::filesystem::path path(input.settings.design);
  DesignFileOptions options;
  options.file = path;
  Design design = load_design_text(input.text, path.string(), d, path.parent_path(), options);
  design.source = path;
  if (d.has_errors()) {
    print_diagnostics(d);
    return std::nullopt;
  }
  for (const Diagnostic& x : d) print_diagnostic(x);
  return design;
}

}  // namespace

int flatpack_check(const DesignInput& input) {
  const auto design = read(input);
  if (!design) return kExitBadInput;
  CheckOptions o;
  if (input.settings.time_limit_s) {
    o.deadline =
        std::chrono::steady_clock::now() +
        std::chrono::microseconds(static_cast<long long>(*input.settings.time_limit_s * 1e6));
  }
  const Analysis a = check(*design, o);
  print_analysis(a, input.settings.quiet);
  return exit_code(a.diagnostics);
}

int flatpack_build(const DesignInput& input) {
  if (input.settings.output_dir.empty()) {
    std::fprintf(stderr, "error: fabkit build needs -o OUTPUT_DIR\n");
    return kExitUsage;
  }
  const auto design = read(input);
  if (!design) return kExitBadInput;
  BuildOptions o;
  o.output_dir = input.settings.output_dir;
  if (input.settings.time_limit_s) {
    o.deadline =
        std::chrono::steady_clock::now() +
        std::chrono::microseconds(static_cast<long long>(*input.settings.time_limit_s * 1e6));
  }
  const BuildSummary s = build(*design, o);
  Analysis shown = s.analysis;
  shown.diagnostics = s.diagnostics;
  print_analysis(shown, input.settings.quiet);
  if (s.nesting.sheet_count > 0) {
    std::printf("sheets: %d of %g × %g mm, %.1f %% used\n",
                s.nesting.sheet_count,
                o.sheet.value_or(design->sheet).sheet_width_mm,
                o.sheet.value_or(design->sheet).sheet_height_mm,
                100 * s.nesting.utilisation);
  }
  for (const auto& f : s.files) std::printf("wrote %s\n", f.string().c_str());
  if (s.termination == Termination::kTimeout)
    std::printf("stopped at the deadline; nothing written\n");
  return exit_code(s.diagnostics);
}

int flatpack_burn_test(const BurnTestSettings& settings) {
  Diagnostics d;
  BurnTestOptions o;
  o.material.name = settings.material;
  o.material.thickness_mm = settings.thickness_mm;
  o.finger_width_mm = settings.finger_width_mm;
  o.kerfs_mm = parse_value_list(settings.kerfs, "--kerf", d);
  o.interferences_mm = parse_value_list(settings.interferences, "--interference", d);
  if (d.has_errors()) {
    print_diagnostics(d);
    return exit_code(d);
  }
  const BurnTest test = burn_test(o);
  if (test.diagnostics.has_errors()) {
    print_diagnostics(test.diagnostics);
    return exit_code(test.diagnostics);
  }
  const std::filesystem::path dir(settings.output_dir);
  const std::vector<std::filesystem::path> written = write_burn_test(test, dir, d);
  if (d.has_errors()) {
    print_diagnostics(d);
    return exit_code(d);
  }
  std::printf("burn test for %s %g mm: %zu cells (rows: kerf Δ, columns: interference δ)\n",
              settings.material.c_str(),
              settings.thickness_mm,
              test.cells.size());
  std::printf("%9s %9s %11s %9s %9s\n", "kerf", "fit", "finger", "dent", "slot");
  for (const BurnTestCell& c : test.cells) {
    std::printf("%9g %9g %8.3f mm %6.3f mm %6.3f mm\n",
                c.kerf_mm,
                c.interference_mm,
                c.finger_mm,
                c.dent_mm,
                c.slot_mm);
  }
  std::printf(
      "cut it, press each comb into its dent strip and a board into its slot; put the Δ and δ "
      "of the cell that holds firmly into your design's material: {kerf: Δ, interference: δ}\n");
  std::printf("sheet %g × %g mm\n", test.sheet.width_mm, test.sheet.height_mm);
  for (const auto& f : written) std::printf("wrote %s\n", f.string().c_str());
  return kExitOk;
}

}  // namespace fabkit::cli

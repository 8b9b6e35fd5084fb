#include "fabkit/hacks/deadline.h"

#include <fmt/format.h>

#include <chrono>

#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {

bool mark_cut_by_deadline(ConnectReport& report, const VerifyOptions& verify) {
  if (report.accepted || !verify.deadline || std::chrono::steady_clock::now() <= *verify.deadline ||
      report.starts_used >= verify.restarts) {
    return false;  // not stopped by the deadline: every start ran, or there was time left
  }
  Diagnostics kept;
  bool converted = false;
  for (const Diagnostic& d : report.diagnostics) {
    if (d.severity == Severity::kError &&
        (d.code == codes::kCycleNotClosable || d.code == codes::kMultiConnection)) {
      kept.error(codes::kTimeLimit,
                 fmt::format("stopped at the deadline after {} iteration{} (starts of the "
                             "cycle-closure search, of {}), the best result so far: {}",
                             report.starts_used,
                             report.starts_used == 1 ? "" : "s",
                             verify.restarts,
                             d.message),
                 d.where);
      converted = true;
    } else {
      kept.add(d);
    }
  }
  if (converted) report.diagnostics = kept;
  return converted;
}

std::string stopped_at_deadline(const SolveResult& r, const SolveOptions& options) {
  bool relaxed = false;
  for (const StageTiming& t : r.timings) relaxed = relaxed || t.stage == "step2";
  std::string best;
  if (!r.feasible) {
    best = "no configuration yet keeps every cycle closed";
  } else {
    const PoseError& e = relaxed ? r.target : r.target_step1;
    best = fmt::format("the target is {:.1f} mm and {:.1f}° from its goal{}",
                       e.position_mm,
                       e.rotation_deg,
                       relaxed ? (r.stable ? ", and it holds" : "; whether it holds is not known")
                               : " (not yet relaxed under gravity)");
  }
  return fmt::format(
      "stopped at the deadline after {} iteration{} of step 1 (starts, of {}){}; the best "
      "result so far: {}",
      r.step1_starts,
      r.step1_starts == 1 ? "" : "s",
      options.target_starts,
      relaxed ? " and during step 2 (relaxing under gravity)" : "",
      best);
}

}  // namespace fabkit::hacks

#include "fabkit/rods/build.h"

#include <fmt/format.h>

#include <atomic>
#include <mutex>
#include <thread>

#include "fabkit/rods/diagnostic_codes.h"

namespace fabkit::rods {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// The summary's verdict from what its diagnostics hold.
void conclude(Summary& s, bool joints_built) {
  const Diagnostics& d = s.diagnostics;
  if (d.has_errors_of(DiagnosticClass::kInput) || d.has_errors_of(DiagnosticClass::kInternal) ||
      d.has_errors_of(DiagnosticClass::kIo)) {
    s.termination = Termination::kFailed;
  } else if (d.has_errors_of(DiagnosticClass::kTimeout)) {
    s.termination = Termination::kTimeLimit;
  } else if (d.has_errors_of(DiagnosticClass::kInfeasible)) {
    s.termination = Termination::kInfeasible;
  } else if (d.has_errors()) {
    s.termination = Termination::kBuiltWithFindings;
  } else {
    s.termination = Termination::kBuilt;
  }
  int errors = 0;
  for (const Diagnostic& x : d) errors += x.severity == Severity::kError ? 1 : 0;
  const std::string what = joints_built ? "built" : "checked";
  switch (s.termination) {
    case Termination::kBuilt:
      s.message = fmt::format("{}: every check passed", what);
      break;
    case Termination::kBuiltWithFindings:
      s.message = fmt::format("{}, but {} check{} failed", what, errors, errors == 1 ? "" : "s");
      break;
    case Termination::kInfeasible:
      s.message = "cannot be built as designed";
      break;
    case Termination::kTimeLimit:
      s.message = "stopped at the deadline";
      break;
    case Termination::kFailed:
      s.message = "failed";
      break;
  }
}

}  // namespace

std::string_view to_string(Termination t) {
  switch (t) {
    case Termination::kBuilt:
      return "built";
    case Termination::kBuiltWithFindings:
      return "built-with-findings";
    case Termination::kInfeasible:
      return "infeasible";
    case Termination::kTimeLimit:
      return "time-limit";
    case Termination::kFailed:
      return "failed";
  }
  return "failed";
}

namespace {

// Everything but the joints. With `masses` (the exact joints'), balance and self-weight use
// them; with `previous`, its cut plan, assembly and reuse are kept rather than recomputed.
Summary analyse(const Design& design,
                const BuildOptions& options,
                std::span<const JointMass> masses,
                Summary* previous) {
  Summary s;
  s.diagnostics = design.diagnostics;
  if (!design.readable || design.structure.nodes.empty()) {
    if (!s.diagnostics.has_errors())
      s.diagnostics.error(codes::kMalformedInput, "the design could not be read");
    conclude(s, false);
    return s;
  }
  const Structure& st = design.structure;
  const Parameters& p = design.parameters;
  // Between stages: past the deadline, say after which, and stop (the caller concludes).
  int stages = 0;
  auto stopped = [&](const char* next) {
    ++stages;
    if (!options.deadline || Clock::now() <= *options.deadline) return false;
    s.diagnostics.error(codes::kTimeLimit,
                        fmt::format("stopped at the deadline after {} iteration{} (stages of the "
                                    "check); {} and the rest were not done",
                                    stages,
                                    stages == 1 ? "" : "s",
                                    next));
    return true;
  };
  auto t = Clock::now();
  s.layout = compute_layout(st, p);
  s.timings.emplace_back("layout", ms_since(t));
  if (stopped("the fabrication checks")) return s;

  t = Clock::now();
  CheckOptions checks = options.checks;
  checks.loads = design.loads;
  // A design held by explicit supports (mounted on a wall, clamped) does not stand on a floor.
  checks.balance = checks.balance && design.supports.empty();
  s.checks = check(st, p, s.layout, checks, masses);
  s.diagnostics.append(s.checks.findings);
  s.timings.emplace_back("checks", ms_since(t));
  if (stopped("the frame analysis")) return s;

  if (options.frame_analysis) {
    t = Clock::now();
    FrameOptions fo;
    fo.loads = design.loads;
    fo.supports = design.supports;
    fo.ground_tolerance = options.checks.ground_tolerance;
    const auto estimated =
        masses.empty() ? estimate_joint_masses(st, p, s.layout) : std::vector<JointMass>();
    s.frame = analyse_frame(
        st, p, s.layout, fo, masses.empty() ? std::span<const JointMass>(estimated) : masses);
    s.diagnostics.append(s.frame.findings);
    s.timings.emplace_back("frame analysis", ms_since(t));
    if (stopped("the cut plan")) return s;
  }

  if (previous) {
    s.cut_pieces = std::move(previous->cut_pieces);
    s.cut_piece_rod = std::move(previous->cut_piece_rod);
    s.cut_plan = std::move(previous->cut_plan);
    s.assembly = std::move(previous->assembly);
    s.reused = std::move(previous->reused);
    s.reused_from = std::move(previous->reused_from);
    for (const auto& timing : previous->timings) {
      if (timing.first == "cut plan" || timing.first == "assembly order")
        s.timings.push_back(timing);
    }
    for (const Diagnostic& d : previous->diagnostics) {
      if (d.code == codes::kPieceLongerThanStock || d.code == codes::kJointsReused ||
          (d.code == codes::kTimeLimit && d.severity == Severity::kNote)) {
        s.diagnostics.add(d);
      }
    }
    return s;
  }
  t = Clock::now();
  for (std::size_t e = 0; e < st.rods.size(); ++e) {
    if (s.layout.rod_length[e] <= 0) continue;
    s.cut_pieces.push_back(CutPiece{st.rod_name(static_cast<int>(e)), s.layout.rod_length[e]});
    s.cut_piece_rod.push_back(static_cast<int>(e));
  }
  Diagnostics cut;
  s.cut_plan = plan_cuts(s.cut_pieces, p.stock, cut, options.cut_plan);
  // Name the rods' edges (file:line) in the stock messages.
  for (const Diagnostic& d : cut) {
    Diagnostic x = d;
    for (std::size_t k = 0; k < s.cut_pieces.size(); ++k) {
      if (d.message.find("'" + s.cut_pieces[k].label + "'") != std::string::npos) {
        x.where = st.rods[static_cast<std::size_t>(s.cut_piece_rod[k])].where;
        break;
      }
    }
    s.diagnostics.add(x);
  }
  if (s.cut_plan && !s.cut_plan->proven_optimal) {
    s.diagnostics.note(codes::kTimeLimit, "cut plan: " + s.cut_plan->summary);
  }
  s.timings.emplace_back("cut plan", ms_since(t));

  t = Clock::now();
  s.assembly = assembly_order(st, s.layout, design.assembly_start);
  s.timings.emplace_back("assembly order", ms_since(t));

  if (design.reuse_joints_from) {
    const Design printed = load_design(*design.reuse_joints_from);
    s.reused_from = design.reuse_joints_from->string();
    if (!printed.readable) {
      for (const Diagnostic& d : printed.diagnostics) {
        if (d.severity == Severity::kError) {
          s.diagnostics.warning(
              codes::kJointsReused,
              fmt::format("reuse_joints_from: cannot read {}: {}", s.reused_from, d.message),
              d.where);
        }
      }
    } else {
      s.reused = matching_joints(printed.structure, printed.parameters, st, p);
      std::string which;
      for (const JointMatch& m : s.reused)
        which += (which.empty() ? "" : ", ") + st.joint_label(m.node);
      const auto factor = uniform_scale_between(printed.structure, st);
      s.diagnostics.note(
          codes::kJointsReused,
          fmt::format("{} of {} joints are the same as printed for {}{}{}",
                      s.reused.size(),
                      st.nodes.size(),
                      s.reused_from,
                      factor ? fmt::format(" (this design is that one scaled by {:g})", *factor)
                             : std::string(),
                      which.empty() ? std::string() : ": " + which));
    }
  }
  return s;
}

}  // namespace

Summary check(const Design& design, const BuildOptions& options) {
  Summary s = analyse(design, options, {}, nullptr);
  conclude(s, false);
  return s;
}

Summary build(const Design& design, const BuildOptions& options) {
  Summary first = check(design, options);
  if (first.termination == Termination::kFailed || first.termination == Termination::kInfeasible ||
      first.termination == Termination::kTimeLimit) {
    return first;
  }
  Summary& s = first;
  const Structure& st = design.structure;
  const Parameters& p = design.parameters;
  const auto t = Clock::now();
  JointSolidOptions joint_options = options.joint;
  joint_options.engrave = joint_options.engrave && design.engrave;
  if (!joint_options.deadline) joint_options.deadline = options.deadline;
  const int n = static_cast<int>(st.nodes.size());
  std::vector<std::optional<JointSolid>> made(static_cast<std::size_t>(n));
  std::vector<Diagnostics> diags(static_cast<std::size_t>(n));
  std::atomic<int> next{0}, done{0};
  std::atomic<bool> timed_out{false};
  std::mutex progress;
  auto worker = [&] {
    for (int i = next++; i < n; i = next++) {
      if (options.deadline && Clock::now() >= *options.deadline) {
        timed_out = true;
        return;
      }
      made[static_cast<std::size_t>(i)] =
          make_joint_solid(st, p, s.layout, i, joint_options, diags[static_cast<std::size_t>(i)]);
      const int d = ++done;
      if (options.on_progress) {
        std::lock_guard<std::mutex> lock(progress);
        options.on_progress(d, n);
      }
    }
  };
  const int threads = std::clamp(options.threads, 1, std::max(1, n));
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& th : pool) th.join();
  // A joint the deadline cut inside its booleans says so itself; the summary below says it once.
  Diagnostics diags_of_joints;
  for (const Diagnostics& d : diags) {
    for (const Diagnostic& x : d) {
      if (x.severity == Severity::kError && x.kind() == DiagnosticClass::kTimeout) {
        timed_out = true;
      } else {
        diags_of_joints.add(x);
      }
    }
  }
  if (!std::all_of(made.begin(), made.end(), [](const auto& j) { return j.has_value(); }) ||
      timed_out) {
    s.diagnostics.append(diags_of_joints);
  }
  if (timed_out) {
    s.diagnostics.error(
        codes::kTimeLimit,
        fmt::format("stopped at the deadline after {} iteration{} (joints built, of {}); nothing "
                    "is written without every joint",
                    done.load(),
                    done.load() == 1 ? "" : "s",
                    n));
  }
  bool all = !timed_out;
  for (auto& j : made) {
    if (!j) {
      all = false;
      continue;
    }
    s.joints.push_back(std::move(*j));
  }
  if (!all) s.joints.clear();
  s.timings.emplace_back("joints", ms_since(t));

  Diagnostics build_diags;
  for (const Diagnostic& d : diags_of_joints) build_diags.add(d);
  if (all) {
    // Checks, balance and self-weight again with the exact joints' masses.
    std::vector<JointMass> masses;
    for (const JointSolid& j : s.joints) {
      masses.push_back(JointMass{j.volume * p.joint_material.density * 1e-9,
                                 st.nodes[static_cast<std::size_t>(j.node)].position + j.centroid});
    }
    Summary exact = analyse(design, options, masses, &s);
    exact.joints = std::move(s.joints);
    exact.timings.insert(exact.timings.end(), s.timings.end() - 1, s.timings.end());
    exact.diagnostics.append(build_diags);
    s = std::move(exact);
  }
  if (design.tolerance_board) {
    const auto tb = Clock::now();
    s.tolerance_board = make_tolerance_board(p, *design.tolerance_board, s.diagnostics);
    s.timings.emplace_back("tolerance board", ms_since(tb));
  }
  conclude(s, true);
  return s;
}

}  // namespace fabkit::rods

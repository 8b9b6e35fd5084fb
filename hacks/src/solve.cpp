// solve() (paper §4.3.3): step 1 brings the target as close as possible to its end_with frame
// by Levenberg-Marquardt on the constraint manifold from the verified configuration and seeded
// random starts (step1.cpp); step 2 relaxes the assembly under gravity by Newton's method on
// the potential with exact twist-based gradients (step2.cpp); then the falls-apart verdict.
// Both steps run on the core's ManifoldSolver (core/solvers/manifold_solver.h).
#include "fabkit/hacks/solve.h"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "fabkit/hacks/diagnostic_codes.h"
#include "steps.h"

namespace fabkit::hacks {
namespace {

using Clock = std::chrono::steady_clock;
using namespace detail;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

}  // namespace

std::string_view to_string(Termination t) {
  switch (t) {
    case Termination::kConverged:
      return "CONVERGED";
    case Termination::kNoTarget:
      return "NO_TARGET";
    case Termination::kInfeasible:
      return "INFEASIBLE";
    case Termination::kMaxIterations:
      return "MAX_ITERATIONS";
    case Termination::kTimeout:
      return "TIMEOUT";
  }
  return "CONVERGED";
}

PoseError target_error(const Assembly& assembly, const std::vector<double>& x) {
  const std::optional<TargetModel> t = make_target(assembly);
  if (!t) return {};
  const std::vector<Mat4> frames = assembly.part_frames(x);
  return pose_error(*t, Rigid<double>::from_matrix(frames[t->part.index()]));
}

SolveResult solve(const Assembly& assembly, const SolveOptions& options) {
  SolveResult result;
  const Problem problem = make_problem(assembly);
  if (assembly.part_count() == 0) {
    result.termination = Termination::kInfeasible;
    result.message = "the assembly is empty";
    result.diagnostics.error(codes::kNoEnvironment, "solve: the assembly is empty");
    return result;
  }
  if (!problem.target) {
    result.termination = Termination::kNoTarget;
    result.diagnostics.warning(codes::kTargetMissing,
                               assembly.target() ? "the target is not connected to the hack; "
                                                   "step 1 is skipped"
                                                 : "the design has no target (end_with); step 1 "
                                                   "is skipped");
  }
  // The starting point must be a closed configuration (connect verified it).
  if (max_gap(assembly, assembly.values()) > kStartGapMm) {
    result.termination = Termination::kInfeasible;
    result.message = "the cycles of the assembly are not closed";
    result.diagnostics.error(codes::kCycleNotClosable,
                             "solve: the assembly's cycles are not closed; verify its connects");
    return result;
  }

  auto announce = [&](std::string_view stage) {
    if (options.on_stage) options.on_stage(stage);
  };
  // Step 1.
  announce("step1");
  auto t1 = Clock::now();
  const Step1Result step1 = run_step1(problem, options);
  result.timings.push_back({"step1", ms_since(t1)});
  result.step1_parameters = step1.x;
  result.step1_starts = step1.starts;
  result.target_step1 = step1.error;
  if (!step1.closed) {
    result.termination = Termination::kInfeasible;
    result.message = "step 1 found no configuration that keeps every cycle closed";
    result.diagnostics.error(codes::kCycleNotClosable, result.message);
    return result;
  }
  result.feasible = true;

  // Step 2.
  const Variables vars = select_variables(assembly, /*physics=*/true);
  std::vector<double> x = step1.x;
  bool converged = !step1.hit_iteration_limit;
  if (options.relax) {
    announce("step2");
    auto t2 = Clock::now();
    StepResult step2 = run_step2(problem, vars, step1.x, options);
    x = step2.x;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (assembly.parameters()[i].spec.tag == ParamTag::kUnbounded) x[i] = wrap_360(x[i]);
    }
    if (!step2.closed || max_gap(assembly, x) > options.closure_tolerance_mm) {
      result.diagnostics.warning(codes::kCycleNotClosable,
                                 "relaxation left a cycle open by more than the tolerance");
    }
    converged = converged && step2.converged;
    if (!step2.note.empty()) result.stability_notes.push_back(step2.note);
    result.timings.push_back({"step2", ms_since(t2)});
  }
  result.parameters = x;

  // Verdict.
  announce("stability");
  auto t3 = Clock::now();
  const StabilityReport stability = check_stability(problem, vars, x, options);
  result.slips = stability.slips;
  result.equilibrium_residual = stability.equilibrium_residual;
  result.stable = result.slips.empty();
  result.timings.push_back({"stability", ms_since(t3)});

  const std::vector<Mat4> frames = assembly.part_frames(x);
  for (int i = 0; i < assembly.part_count(); ++i) {
    const PartNode& n = assembly.node(PartId{i});
    result.parts.push_back({assembly.label(PartId{i}),
                            n.part->type_name,
                            n.environment,
                            problem.target && problem.target->part.value == i,
                            Frame::from_matrix(frames[static_cast<std::size_t>(i)])});
  }
  if (problem.target) {
    result.target = pose_error(
        *problem.target,
        Rigid<double>::from_matrix(frames[static_cast<std::size_t>(problem.target->part.value)]));
  }
  result.max_gap_mm = max_gap(assembly, x, &result.max_gap_deg);
  double energy = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    energy += problem.masses[i] * (frames[i].topLeftCorner<3, 3>() * problem.coms[i] +
                                   frames[i].topRightCorner<3, 1>())[2];
  }
  result.energy = energy;
  if (!converged && result.termination == Termination::kConverged) {
    result.termination = Termination::kMaxIterations;
  }
  if (options.deadline && Clock::now() > *options.deadline) {
    result.termination = Termination::kTimeout;
    result.diagnostics.error(codes::kTimeLimit,
                             "the solve stopped at its time limit; the result is incomplete");
  }
  if (result.stable) {
    std::string how = "nothing slides off under gravity";
    if (problem.target) {
      // How far gravity moved the target from where step 1 put it: a sag, not a failure.
      const std::size_t t = static_cast<std::size_t>(problem.target->part.value);
      const Mat4 before = assembly.part_frames(step1.x)[t] * problem.target->base.matrix();
      const Mat4 after = frames[t] * problem.target->base.matrix();
      const double moved = (after.topRightCorner<3, 1>() - before.topRightCorner<3, 1>()).norm();
      const double turned = Eigen::AngleAxisd(Mat3(before.topLeftCorner<3, 3>().transpose() *
                                                   after.topLeftCorner<3, 3>()))
                                .angle() *
                            kRadToDeg;
      if (moved > kSagNoteMm || turned > kSagNoteDeg) {
        how = fmt::format(
            "nothing slides off; under gravity the target sags {:.1f} mm and tilts "
            "{:.1f}° from step 1",
            moved,
            turned);
      }
    }
    result.stability_notes.push_back(fmt::format("stable: {}", how));
    result.message = "stable";
  } else {
    result.message = fmt::format("falls apart: {}", result.slips.front().message);
  }
  return result;
}

std::string SolveResult::summary() const {
  std::string s;
  s += "FabHaL solve report\n";
  s += fmt::format("  {:<28}{}\n", "termination", to_string(termination));
  s += fmt::format(
      "  {:<28}{}\n", "verdict", stable ? "STABLE" : (feasible ? "FALLS APART" : "INFEASIBLE"));
  s += fmt::format("  {:<28}{:.3f} mm, {:.3f}°  ({} start{})\n",
                   "target error after step 1",
                   target_step1.position_mm,
                   target_step1.rotation_deg,
                   step1_starts,
                   step1_starts == 1 ? "" : "s");
  s += fmt::format("  {:<28}{:.3f} mm, {:.3f}°\n",
                   "target error after step 2",
                   target.position_mm,
                   target.rotation_deg);
  s += fmt::format(
      "  {:<28}{:.2e} mm, {:.2e}°\n", "largest connection gap", max_gap_mm, max_gap_deg);
  s += fmt::format("  {:<28}{:.2e} (slope of the potential, mm per mm or degree)\n",
                   "equilibrium residual",
                   equilibrium_residual);
  for (const Slip& slip : slips) s += fmt::format("  {:<28}{}\n", "slips", slip.message);
  for (const std::string& n : stability_notes) s += fmt::format("  {:<28}{}\n", "note", n);
  std::string times;
  for (const StageTiming& t : timings)
    times += fmt::format("{} {:.1f} ms  ", t.stage, t.milliseconds);
  s += fmt::format("  {:<28}{}\n", "time", times);
  return s;
}

}  // namespace fabkit::hacks

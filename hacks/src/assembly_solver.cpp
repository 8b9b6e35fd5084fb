#include "steps.h"

namespace fabkit::hacks::detail {
namespace {

solvers::ManifoldSolverOptions solver_options(
    const Problem& p,
    Objective objective,
    std::optional<std::chrono::steady_clock::time_point> deadline) {
  solvers::ManifoldSolverOptions o;
  // Holding the target is only ever the settling of a start (step 1's candidates).
  o.gradient_tolerance =
      objective == Objective::kEnergyHoldingTarget ? kSettleTolerance : kGradientTolerance;
  if (objective == Objective::kEnergyHoldingTarget) {
    o.progress_window = kSettleWindow;
    o.least_progress = kSettleProgressMm;
  }
  // A fit within about a tenth of a millimetre of its goal is not finished (tolerances.h).
  if (objective == Objective::kTarget) o.finish_above = kFitCloseEnough;
  // Step 2's relaxations are judged where they end (check_stability), from their last model.
  o.curvature_at_rest = objective == Objective::kEnergy;
  o.feasibility_tolerance = kClosureTolerance;
  o.projection_tolerance = kProjectionTolerance;
  o.inequality_margin = kInequalityMargin;
  o.neutral_curvature = kNeutralCurvature;
  o.neutral_slope = kEquilibriumTolerance;
  // The solve's shared deadline; a problem made on its own stops at its own.
  o.stop = p.stop ? p.stop : deadline ? std::make_shared<const StopClock>(deadline) : nullptr;
  return o;
}

Eigen::VectorXd lower(const Assembly& a, const Variables& v) {
  Eigen::VectorXd lo, hi;
  scaled_bounds(a, v, lo, hi);
  return lo;
}
Eigen::VectorXd upper(const Assembly& a, const Variables& v) {
  Eigen::VectorXd lo, hi;
  scaled_bounds(a, v, lo, hi);
  return hi;
}

}  // namespace

AssemblySolver::AssemblySolver(const Problem& p,
                               const Variables& v,
                               const std::vector<double>& x,
                               Objective o,
                               std::optional<std::chrono::steady_clock::time_point> deadline)
    : problem_(p),
      vars_(v),
      eval_(p, v, x, o),
      solver_(eval_, lower(*p.assembly, v), upper(*p.assembly, v), solver_options(p, o, deadline)) {
}

bool AssemblySolver::close(std::vector<double>& x, int max_iterations) {
  Eigen::VectorXd z = scaled(vars_, x);
  if (!solver_.close(z, max_iterations)) return false;
  std::vector<double> closed = x;
  from_z(vars_, std::vector<double>(z.data(), z.data() + z.size()), closed);
  // The minimal orientation residuals also vanish at a half turn: check the real gaps.
  for (const ClosureGap& g : closure_gaps(*problem_.assembly, closed)) {
    if (g.rotation_deg > kHalfTurnCheckDeg) return false;
  }
  x = std::move(closed);
  return true;
}

StepResult AssemblySolver::to_step(const solvers::ManifoldSolver::Result& r,
                                   const std::vector<double>& x0) const {
  StepResult out;
  out.x = x0;
  out.closed = r.closed;
  out.converged = r.converged;
  out.iterations = r.iterations;
  out.escapes = r.escapes;
  if (!r.closed) {
    out.note = "the cycles could not be kept closed";
    return out;
  }
  from_z(vars_, std::vector<double>(r.z.data(), r.z.data() + r.z.size()), out.x);
  out.curvature = r.curvature;
  return out;
}

StepResult AssemblySolver::fit(const std::vector<double>& x0, int max_iterations, double give_up) {
  return to_step(solver_.fit(scaled(vars_, x0), max_iterations, give_up), x0);
}

StepResult AssemblySolver::relax(const std::vector<double>& x0, int max_iterations) {
  return to_step(solver_.relax(scaled(vars_, x0), max_iterations), x0);
}

}  // namespace fabkit::hacks::detail

#pragma once
// Internals of solve.cpp exposed to the tests.

#include <Eigen/Dense>
#include <cstdint>
#include <vector>

#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks::detail {

/// Largest difference between the analytic (twist) Jacobian and the automatically
/// differentiated one of step 1's (target) or step 2's (energy) rows at parameters `x`,
/// relative to the largest entry.
double jacobian_mismatch(const Assembly& assembly, const std::vector<double>& x, bool energy);

/// Largest difference between the analytic Jacobian and central finite differences of the
/// rows' values (step `h` in scaled units), relative to the largest entry.
double finite_difference_mismatch(const Assembly& assembly,
                                  const std::vector<double>& x,
                                  bool energy,
                                  double h = 1e-6);

/// Largest difference between the analytic Hessian of step 2's Lagrangian
/// (AnalyticEvaluator::lagrangian_hessian: the potential's; with `hold_target` also the
/// closures' and the held target's rows under random multipliers from `seed`) and central
/// finite differences of its analytic gradient (step `h` in scaled units), relative to the
/// largest entry; 0 if nothing moves (or no target is held).
double hessian_mismatch(const Assembly& assembly,
                        const std::vector<double>& x,
                        bool hold_target,
                        std::uint64_t seed = 1,
                        double h = 1e-5);

/// Largest difference between the closure search's analytic rows and Jacobian (verification,
/// cycle_closure.cpp) and Ceres' automatic differentiation of the same rows at `x`, relative to
/// the largest Jacobian entry; 0 for a design without cycles.
double closure_search_jacobian_mismatch(const Assembly& assembly,
                                        const std::vector<double>& x,
                                        double rotation_weight = 1.0);

/// The same for step 1's Lagrangian, ½‖r‖² of the target's residuals with the closures' rows
/// under random multipliers: its exact Hessian JᵀJ + Σ rᵢ∇²rᵢ − Σ λ∇²h against central
/// differences of its gradient; 0 without a target.
double target_hessian_mismatch(const Assembly& assembly,
                               const std::vector<double>& x,
                               std::uint64_t seed = 1,
                               double h = 1e-5);

/// Largest difference between step 2's rows and Jacobian at x evaluated at once and evaluated
/// the way the solver does a trial step (AnalyticEvaluator::evaluate_values, at `x` after
/// another point `other`, then the Jacobian at `x` from what that kept), with the pairs of
/// pieces near each other at x watched as contact rows (as step 2 does); with `target` the rows of
/// step 1 (the target's residuals) instead. 0 is the only right answer: the solver takes the
/// values of a trial step and the Jacobian of the same point from the two calls.
double values_first_mismatch(const Assembly& assembly,
                             const std::vector<double>& x,
                             const std::vector<double>& other,
                             bool target);

/// Whether the vertical lies in the span of `turns` (the target's rotation vectors per unit of
/// motion along each neutral direction, one a column), counting only turns above round-off
/// (10⁻⁵ rad per unit): then some costless motion twists the target about the vertical,
/// whichever basis of the neutral directions the eigensolver returned.
bool vertical_in_span(const Eigen::Matrix3Xd& turns);

}  // namespace fabkit::hacks::detail

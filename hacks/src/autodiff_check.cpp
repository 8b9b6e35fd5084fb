// The one translation unit where step 1's and step 2's rows are differentiated automatically
// (Ceres), to check the analytic twist Jacobians of kinematics.h in the tests.
#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <random>

#include "kinematics.h"
#include "solve_internal.h"
#include "steps.h"

namespace fabkit::hacks::detail {
namespace {

// Values and Jacobian of ManifoldCost, caching the last point.
class ManifoldEvaluator {
 public:
  ManifoldEvaluator(const Problem& p, const Variables& v, std::vector<double> base, Objective o)
      : functor_(new ManifoldCost{&p, &v, std::move(base), o}),
        cost_(functor_),
        rows_(functor_->residual_count()),
        n_(static_cast<int>(v.index.size())) {
    cost_.AddParameterBlock(n_);
    cost_.SetNumResiduals(rows_);
  }

  void evaluate(const double* z) {
    if (!values_.empty() && std::equal(z, z + n_, last_.begin())) return;
    last_.assign(z, z + n_);
    values_.assign(static_cast<std::size_t>(rows_), 0.0);
    jacobian_.assign(static_cast<std::size_t>(rows_ * n_), 0.0);
    const double* blocks[] = {z};
    double* jac[] = {jacobian_.data()};
    cost_.Evaluate(blocks, values_.data(), jac);
  }
  int objectives() const { return functor_->objective_count(); }
  int equalities() const { return functor_->equality_count(); }
  int inequalities() const { return rows_ - objectives() - equalities(); }
  double value(int row) const { return values_[static_cast<std::size_t>(row)]; }
  double gradient(int row, int col) const {
    return jacobian_[static_cast<std::size_t>(row * n_ + col)];
  }

 private:
  ManifoldCost* functor_;  // owned by cost_
  ceres::DynamicAutoDiffCostFunction<ManifoldCost, 4> cost_;
  int rows_;
  int n_;
  std::vector<double> last_, values_, jacobian_;
};

// Central differences of `f` (z → a vector) along each coordinate of z: column c is
// (f(z + h·e_c) − f(z − h·e_c)) / 2h.
template <class F>
Eigen::MatrixXd central_differences(const std::vector<double>& z, double h, F f) {
  Eigen::MatrixXd out;
  for (std::size_t c = 0; c < z.size(); ++c) {
    std::vector<double> zp = z, zm = z;
    zp[c] += h;
    zm[c] -= h;
    const Eigen::VectorXd column = (f(zp) - f(zm)) / (2 * h);
    if (out.size() == 0) out.resize(column.size(), static_cast<Eigen::Index>(z.size()));
    out.col(static_cast<Eigen::Index>(c)) = column;
  }
  return out;
}

}  // namespace

double jacobian_mismatch(const Assembly& assembly, const std::vector<double>& x, bool energy) {
  const Problem p = make_problem(assembly);
  if (!energy && !p.target) return 0;
  const Variables vars = select_variables(assembly, energy);
  const Objective o = energy ? Objective::kEnergy : Objective::kTarget;
  ManifoldEvaluator automatic(p, vars, x, o);
  AnalyticEvaluator analytic(p, vars, x, o);
  const std::vector<double> z = to_z(vars, x);
  automatic.evaluate(z.data());
  analytic.evaluate(z.data());
  const int rows = automatic.objectives() + automatic.equalities() + automatic.inequalities();
  double largest = 1e-12;
  double worst = 0;
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < static_cast<int>(vars.index.size()); ++c) {
      largest = std::max(largest, std::abs(automatic.gradient(r, c)));
      worst = std::max(worst, std::abs(automatic.gradient(r, c) - analytic.gradient(r, c)));
    }
  }
  return worst / largest;
}

double finite_difference_mismatch(const Assembly& assembly,
                                  const std::vector<double>& x,
                                  bool energy,
                                  double h) {
  const Problem p = make_problem(assembly);
  if (!energy && !p.target) return 0;
  const Variables vars = select_variables(assembly, energy);
  const Objective o = energy ? Objective::kEnergy : Objective::kTarget;
  AnalyticEvaluator analytic(p, vars, x, o);
  const std::vector<double> z = to_z(vars, x);
  const int n = static_cast<int>(z.size());
  const int rows = analytic.objectives() + analytic.equalities() + analytic.inequalities();
  std::vector<double> values(static_cast<std::size_t>(rows));
  std::vector<double> jac(static_cast<std::size_t>(rows * n));
  analytic.evaluate(z.data(), values.data(), jac.data());
  const std::vector<double> J = jac;
  const Eigen::MatrixXd fd = central_differences(z, h, [&](const std::vector<double>& at) {
    analytic.evaluate(at.data(), values.data(), jac.data());
    return Eigen::Map<const Eigen::VectorXd>(values.data(), rows).eval();
  });
  double largest = 1e-12;
  double worst = 0;
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < rows; ++r) {
      const double an = J[static_cast<std::size_t>(r * n + c)];
      largest = std::max(largest, std::abs(an));
      // Spacing rows have |Δt| kinks; skip them where the kink is within the step.
      if (r >= analytic.objectives() + analytic.equalities()) continue;
      worst = std::max(worst, std::abs(fd(r, c) - an));
    }
  }
  return worst / largest;
}

double hessian_mismatch(const Assembly& assembly,
                        const std::vector<double>& x,
                        bool hold_target,
                        std::uint64_t seed,
                        double h) {
  const Problem p = make_problem(assembly);
  if (hold_target && !p.target) return 0;
  const Variables vars = select_variables(assembly, /*physics=*/true);
  if (vars.index.empty() || p.total_mass <= 0) return 0;
  const Objective o = hold_target ? Objective::kEnergyHoldingTarget : Objective::kEnergy;
  AnalyticEvaluator analytic(p, vars, x, o);
  const std::vector<double> z = to_z(vars, x);
  const int n = static_cast<int>(z.size());
  // Holding the target: the closures' rows and the held target's rows, with random
  // multipliers (the target's constraint numbers follow the closures'). The plain potential's
  // Hessian is exact without closure rows (step 2 differences their share).
  std::vector<int> rows;
  std::vector<double> multipliers;
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  int first = 0;
  for (const auto& axis : p.free_axes) first += axis ? 5 : 6;
  if (hold_target) {
    for (int i = 0; i < first; ++i) {
      rows.push_back(i);
      multipliers.push_back(uniform(rng) * 1e-3);
    }
  }
  if (hold_target) {
    for (int i = 0; i < kTargetResiduals; ++i) {
      rows.push_back(first + i);
      multipliers.push_back(uniform(rng) * 1e-3);
    }
  }
  const Eigen::VectorXd lambda = Eigen::Map<const Eigen::VectorXd>(
      multipliers.data(), static_cast<Eigen::Index>(multipliers.size()));
  Eigen::MatrixXd exact;
  if (!analytic.lagrangian_hessian(z.data(), rows, lambda, exact)) return 1;
  // ∇f − Σ λᵢ ∇rowᵢ at z (constraint row r is Jacobian row objectives() + r).
  auto gradient = [&](const std::vector<double>& at) {
    analytic.evaluate(at.data());
    Eigen::VectorXd g(n);
    for (int k = 0; k < n; ++k) {
      g[k] = analytic.gradient(0, k);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        g[k] -= lambda[static_cast<Eigen::Index>(i)] *
                analytic.gradient(analytic.objectives() + rows[i], k);
      }
    }
    return g;
  };
  const Eigen::MatrixXd fd = central_differences(z, h, gradient);
  const double largest = std::max(1e-12, exact.cwiseAbs().maxCoeff());
  const double worst = (fd - exact).cwiseAbs().maxCoeff();
  return worst / largest;
}

double target_hessian_mismatch(const Assembly& assembly,
                               const std::vector<double>& x,
                               std::uint64_t seed,
                               double h) {
  const Problem p = make_problem(assembly);
  if (!p.target) return 0;
  const Variables vars = select_variables(assembly, /*physics=*/false);
  if (vars.index.empty()) return 0;
  AnalyticEvaluator analytic(p, vars, x, Objective::kTarget);
  const std::vector<double> z = to_z(vars, x);
  const int n = static_cast<int>(z.size());
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1, 1);
  std::vector<int> rows;
  Eigen::VectorXd lambda(analytic.equalities());
  for (int i = 0; i < analytic.equalities(); ++i) {
    rows.push_back(i);
    lambda[i] = uniform(rng) * 1e-3;
  }
  Eigen::MatrixXd exact;
  if (!analytic.lagrangian_hessian(z.data(), rows, lambda, exact)) return 1;
  // The gradient Jᵀr − Σ λ∇h at z.
  auto gradient = [&](const std::vector<double>& at) {
    analytic.evaluate(at.data());
    Eigen::VectorXd g = Eigen::VectorXd::Zero(n);
    for (int k = 0; k < n; ++k) {
      for (int i = 0; i < analytic.objectives(); ++i) {
        g[k] += analytic.value(i) * analytic.gradient(i, k);
      }
      for (std::size_t i = 0; i < rows.size(); ++i) {
        g[k] -= lambda[static_cast<Eigen::Index>(i)] *
                analytic.gradient(analytic.objectives() + rows[i], k);
      }
    }
    return g;
  };
  const Eigen::MatrixXd fd = central_differences(z, h, gradient);
  const double largest = std::max(1e-12, exact.cwiseAbs().maxCoeff());
  return (fd - exact).cwiseAbs().maxCoeff() / largest;
}

double values_first_mismatch(const Assembly& assembly,
                             const std::vector<double>& x,
                             const std::vector<double>& other,
                             bool target) {
  Problem p = make_problem(assembly);
  if (target && !p.target) return 0;
  p.contacts = std::make_shared<const ContactModel>(assembly);
  watch_contacts(p, x);
  const Variables vars = select_variables(assembly, /*physics=*/!target);
  if (vars.index.empty()) return 0;
  const Objective o = target ? Objective::kTarget : Objective::kEnergy;
  AnalyticEvaluator at_once(p, vars, x, o);
  AnalyticEvaluator values_first(p, vars, x, o);
  const std::vector<double> z = to_z(vars, x);
  const std::vector<double> z_other = to_z(vars, other);
  const auto rows = static_cast<std::size_t>(at_once.objectives() + at_once.equalities() +
                                             at_once.inequalities());
  const std::size_t n = z.size();
  std::vector<double> values(rows), jacobian(rows * n), trial(rows), after(rows),
      after_jacobian(rows * n);
  at_once.evaluate(z.data(), values.data(), jacobian.data());
  values_first.evaluate_values(z_other.data(), trial.data());
  values_first.evaluate_values(z.data(), trial.data());
  values_first.evaluate(z.data(), after.data(), after_jacobian.data());
  double worst = 0;
  for (std::size_t i = 0; i < rows; ++i) {
    worst = std::max({worst, std::abs(values[i] - trial[i]), std::abs(values[i] - after[i])});
  }
  for (std::size_t i = 0; i < rows * n; ++i) {
    worst = std::max(worst, std::abs(jacobian[i] - after_jacobian[i]));
  }
  return worst;
}

}  // namespace fabkit::hacks::detail

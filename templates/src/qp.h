#pragma once
// Dense convex QPs for the kit (manipulation, snapping, connecting, stability), behind plain
// Eigen types so that NLopt and Ipopt each stay inside one translation unit:
//
//   minimise ½ zᵀ H z + gᵀ z   subject to   C z ≤ d,   lower ≤ z ≤ upper
//
// H must be symmetric positive definite (every caller adds a proximity term).

#include <Eigen/Core>
#include <string>
#include <string_view>

namespace fabkit::templates::qp {

struct Problem {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  Eigen::MatrixXd C;  ///< m × n (m may be 0)
  Eigen::VectorXd d;
  Eigen::VectorXd lower;  ///< empty: unbounded
  Eigen::VectorXd upper;  ///< empty: unbounded
  Eigen::VectorXd start;  ///< a starting point (need not be feasible); empty: zero
};

/// The solvers measured for the kit (bench/templates_bench.cpp, docs/benchmarks.md).
enum class Backend {
  kSlsqp,  ///< NLopt's SLSQP (dense sequential least squares; exact for a QP)
  kIpopt,  ///< Ipopt's interior point method with MUMPS
};
std::string_view to_string(Backend b);

struct Settings {
  Backend backend = Backend::kSlsqp;
  double tolerance = 1e-10;  ///< constraint and step tolerance (relative to the problem scale)
  int max_iterations = 500;
  /// Stop after this many seconds (a caller's deadline); 0: no limit. A stopped solve is not
  /// converged and says so in `message`.
  double max_seconds = 0;
};

struct Result {
  Eigen::VectorXd z;
  /// Multipliers of the rows of C (≥ 0; estimated from the KKT conditions on the active set).
  Eigen::VectorXd multipliers;
  bool converged = false;
  int iterations = 0;
  std::string message;  ///< the solver's own word when it did not converge
};

Result solve(const Problem& p, const Settings& s = {});

/// The solvers, callable one by one (benchmarks).
Result solve_slsqp(const Problem& p, const Settings& s);
Result solve_ipopt(const Problem& p, const Settings& s);

/// Multipliers μ ≥ 0 of the rows of C active at z (|C z − d| small), from least squares on
/// H z + g + Cᵀ μ = 0; zero for inactive rows.
Eigen::VectorXd estimate_multipliers(const Problem& p, const Eigen::VectorXd& z, double active_tol);

}  // namespace fabkit::templates::qp

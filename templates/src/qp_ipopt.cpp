// Ipopt on a dense QP. The only file that includes Ipopt.
#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>
#include <limits>

#include "qp.h"

namespace fabkit::templates::qp {

namespace {

using Ipopt::Index;
using Ipopt::Number;

class QpTnlp : public Ipopt::TNLP {
 public:
  QpTnlp(const Problem& p, Eigen::VectorXd& out) : p_(p), out_(out) {}

  bool get_nlp_info(
      Index& n, Index& m, Index& nnz_jac, Index& nnz_h, IndexStyleEnum& style) override {
    n = static_cast<Index>(p_.H.rows());
    m = static_cast<Index>(p_.C.rows());
    nnz_jac = n * m;
    nnz_h = n * (n + 1) / 2;
    style = C_STYLE;
    return true;
  }
  bool get_bounds_info(Index n, Number* xl, Number* xu, Index m, Number* gl, Number* gu) override {
    const double inf = 2e19;
    for (Index i = 0; i < n; ++i) {
      xl[i] = p_.lower.size() == n ? p_.lower[i] : -inf;
      xu[i] = p_.upper.size() == n ? p_.upper[i] : inf;
    }
    for (Index j = 0; j < m; ++j) {
      gl[j] = -inf;
      gu[j] = p_.d[j];
    }
    return true;
  }
  bool get_starting_point(
      Index n, bool, Number* x, bool, Number*, Number*, Index, bool, Number*) override {
    for (Index i = 0; i < n; ++i) x[i] = p_.start.size() == n ? p_.start[i] : 0.0;
    return true;
  }
  bool eval_f(Index n, const Number* x, bool, Number& f) override {
    const Eigen::Map<const Eigen::VectorXd> z(x, n);
    f = 0.5 * z.dot(p_.H * z) + p_.g.dot(z);
    return true;
  }
  bool eval_grad_f(Index n, const Number* x, bool, Number* g) override {
    const Eigen::Map<const Eigen::VectorXd> z(x, n);
    Eigen::Map<Eigen::VectorXd>(g, n) = p_.H * z + p_.g;
    return true;
  }
  bool eval_g(Index n, const Number* x, bool, Index m, Number* g) override {
    const Eigen::Map<const Eigen::VectorXd> z(x, n);
    Eigen::Map<Eigen::VectorXd>(g, m) = p_.C * z;
    return true;
  }
  bool eval_jac_g(Index n,
                  const Number*,
                  bool,
                  Index m,
                  Index,
                  Index* rows,
                  Index* cols,
                  Number* values) override {
    Index k = 0;
    for (Index j = 0; j < m; ++j) {
      for (Index i = 0; i < n; ++i, ++k) {
        if (values) {
          values[k] = p_.C(j, i);
        } else {
          rows[k] = j;
          cols[k] = i;
        }
      }
    }
    return true;
  }
  bool eval_h(Index n,
              const Number*,
              bool,
              Number obj_factor,
              Index,
              const Number*,
              bool,
              Index,
              Index* rows,
              Index* cols,
              Number* values) override {
    Index k = 0;
    for (Index i = 0; i < n; ++i) {
      for (Index j = 0; j <= i; ++j, ++k) {
        if (values) {
          values[k] = obj_factor * p_.H(i, j);
        } else {
          rows[k] = i;
          cols[k] = j;
        }
      }
    }
    return true;
  }
  void finalize_solution(Ipopt::SolverReturn,
                         Index n,
                         const Number* x,
                         const Number*,
                         const Number*,
                         Index,
                         const Number*,
                         const Number*,
                         Number,
                         const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    out_ = Eigen::Map<const Eigen::VectorXd>(x, n);
  }

 private:
  const Problem& p_;
  Eigen::VectorXd& out_;
};

}  // namespace

Result solve_ipopt(const Problem& p, const Settings& s) {
  Result r;
  const Eigen::Index n = p.H.rows();
  r.z = p.start.size() == n ? p.start : Eigen::VectorXd::Zero(n);
  if (n == 0) {
    r.converged = true;
    return r;
  }
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  app->Options()->SetIntegerValue("print_level", 0);
  app->Options()->SetStringValue("sb", "yes");
  app->Options()->SetNumericValue("tol", s.tolerance);
  // Hard constraints mean hard: no relaxed bounds, no loose feasibility tolerance.
  app->Options()->SetNumericValue("constr_viol_tol", s.tolerance);
  app->Options()->SetNumericValue("bound_relax_factor", 0.0);
  app->Options()->SetIntegerValue("max_iter", s.max_iterations);
  // Ipopt 3.11 (Debian bookworm) has a CPU-time limit, not a wall-clock one; the solve is
  // single-threaded, so the two agree.
  if (s.max_seconds > 0) app->Options()->SetNumericValue("max_cpu_time", s.max_seconds);
  app->Options()->SetStringValue("hessian_constant", "yes");
  app->Options()->SetStringValue("jac_c_constant", "yes");
  app->Options()->SetStringValue("jac_d_constant", "yes");
  app->Options()->SetStringValue("mu_strategy", "adaptive");
  if (app->Initialize() != Ipopt::Solve_Succeeded) {
    r.message = "Ipopt: initialisation failed";
    return r;
  }
  Eigen::VectorXd z = r.z;
  Ipopt::SmartPtr<Ipopt::TNLP> nlp = new QpTnlp(p, z);
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(nlp);
  r.z = z;
  r.converged = status == Ipopt::Solve_Succeeded || status == Ipopt::Solved_To_Acceptable_Level;
  if (!r.converged) r.message = "Ipopt: status " + std::to_string(static_cast<int>(status));
  Ipopt::SmartPtr<Ipopt::SolveStatistics> stats = app->Statistics();
  if (IsValid(stats)) r.iterations = stats->IterationCount();
  return r;
}

}  // namespace fabkit::templates::qp

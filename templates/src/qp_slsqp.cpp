// NLopt's SLSQP on a dense QP. The only file that includes NLopt.
#include "qp.h"

#include <nlopt.h>

#include <algorithm>
#include <vector>

namespace fabkit::templates::qp {

namespace {

struct Data {
  const Problem* p;
  double scale = 1;  // SLSQP stops early on badly scaled objectives: f is divided by max |H|
  int evaluations = 0;
};

double objective(unsigned n, const double* x, double* grad, void* data) {
  auto* d = static_cast<Data*>(data);
  ++d->evaluations;
  const Eigen::Map<const Eigen::VectorXd> z(x, n);
  const Eigen::VectorXd hz = d->p->H * z;
  if (grad) Eigen::Map<Eigen::VectorXd>(grad, n) = (hz + d->p->g) * d->scale;
  return (0.5 * z.dot(hz) + d->p->g.dot(z)) * d->scale;
}

void constraints(
    unsigned m, double* result, unsigned n, const double* x, double* grad, void* data) {
  auto* d = static_cast<Data*>(data);
  const Eigen::Map<const Eigen::VectorXd> z(x, n);
  Eigen::Map<Eigen::VectorXd>(result, m) = d->p->C * z - d->p->d;
  if (grad) {
    // Row-major m × n.
    Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(grad, m, n) =
        d->p->C;
  }
}

}  // namespace

Result solve_slsqp(const Problem& p, const Settings& s) {
  Result r;
  const unsigned n = static_cast<unsigned>(p.H.rows());
  r.z = p.start.size() == p.H.rows() ? p.start : Eigen::VectorXd::Zero(n);
  if (n == 0) {
    r.converged = true;
    return r;
  }
  nlopt_opt opt = nlopt_create(NLOPT_LD_SLSQP, n);
  Data data{&p};
  // Both the curvature and the slope set the objective's scale (a heavily weighted target
  // gives slopes of 1e7 at the start).
  data.scale =
      1.0 /
      std::max({1e-12, p.H.cwiseAbs().maxCoeff(), p.g.size() ? p.g.cwiseAbs().maxCoeff() : 0.0});
  nlopt_set_min_objective(opt, objective, &data);
  const double scale = 1.0 + (p.d.size() ? p.d.cwiseAbs().maxCoeff() : 0.0);
  if (p.C.rows() > 0) {
    std::vector<double> tol(static_cast<std::size_t>(p.C.rows()), s.tolerance * scale);
    nlopt_add_inequality_mconstraint(
        opt, static_cast<unsigned>(p.C.rows()), constraints, &data, tol.data());
  }
  if (p.lower.size() == p.H.rows()) nlopt_set_lower_bounds(opt, p.lower.data());
  if (p.upper.size() == p.H.rows()) nlopt_set_upper_bounds(opt, p.upper.data());
  nlopt_set_xtol_abs1(opt, s.tolerance * scale);
  nlopt_set_maxeval(opt, s.max_iterations);
  if (s.max_seconds > 0) nlopt_set_maxtime(opt, s.max_seconds);
  double f = 0;
  const nlopt_result res = nlopt_optimize(opt, r.z.data(), &f);
  r.iterations = data.evaluations;
  // NLopt counts running out of evaluations or time as success (positive codes): neither is
  // convergence, and a deadline's cut must not pass for an answer.
  r.converged = (res > 0 && res != NLOPT_MAXEVAL_REACHED && res != NLOPT_MAXTIME_REACHED) ||
                res == NLOPT_ROUNDOFF_LIMITED;
  if (!r.converged) r.message = std::string("SLSQP: ") + nlopt_result_to_string(res);
  nlopt_destroy(opt);
  return r;
}

}  // namespace fabkit::templates::qp

#include "qp.h"

#include <Eigen/QR>
#include <cmath>
#include <vector>

namespace fabkit::templates::qp {

std::string_view to_string(Backend b) {
  return b == Backend::kIpopt ? "ipopt" : "slsqp";
}

Result solve(const Problem& p, const Settings& s) {
  Result r = s.backend == Backend::kIpopt ? solve_ipopt(p, s) : solve_slsqp(p, s);
  if (r.z.size() == p.H.rows()) {
    const double scale = 1.0 + (p.d.size() ? p.d.cwiseAbs().maxCoeff() : 0.0);
    r.multipliers = estimate_multipliers(p, r.z, 1e-6 * scale);
  }
  return r;
}

Eigen::VectorXd estimate_multipliers(const Problem& p,
                                     const Eigen::VectorXd& z,
                                     double active_tol) {
  const Eigen::Index m = p.C.rows();
  Eigen::VectorXd mu = Eigen::VectorXd::Zero(m);
  if (m == 0) return mu;
  std::vector<Eigen::Index> active;
  const Eigen::VectorXd slack = p.d - p.C * z;
  for (Eigen::Index i = 0; i < m; ++i) {
    if (slack[i] <= active_tol) active.push_back(i);
  }
  if (active.empty()) return mu;
  Eigen::MatrixXd At(p.C.cols(), static_cast<Eigen::Index>(active.size()));
  for (std::size_t j = 0; j < active.size(); ++j)
    At.col(static_cast<Eigen::Index>(j)) = p.C.row(active[j]).transpose();
  const Eigen::VectorXd grad = p.H * z + p.g;
  const Eigen::VectorXd sol = At.colPivHouseholderQr().solve(-grad);
  for (std::size_t j = 0; j < active.size(); ++j)
    mu[active[j]] = std::max(0.0, sol[static_cast<Eigen::Index>(j)]);
  return mu;
}

}  // namespace fabkit::templates::qp

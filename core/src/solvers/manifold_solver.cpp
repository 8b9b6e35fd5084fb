#include "fabkit/core/solvers/manifold_solver.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

#include "fabkit/core/solvers/eigenbasis.h"

namespace fabkit::solvers {

using Clock = std::chrono::steady_clock;

ManifoldSolver::ManifoldSolver(ManifoldProblem& problem,
                               Eigen::VectorXd lo,
                               Eigen::VectorXd hi,
                               ManifoldSolverOptions options)
    : problem_(problem),
      n_(problem.variables()),
      lo_(std::move(lo)),
      hi_(std::move(hi)),
      options_(options) {}

bool ManifoldSolver::out_of_time() const {
  return options_.stop && options_.stop->passed();
}

bool ManifoldSolver::no_time_for(Clock::duration cost) const {
  return options_.stop && options_.stop->would_pass(cost);
}

namespace {

// What a trust-region iteration (reduced Hessian, its eigendecomposition, the step) cost per
// cube of the motions, lately, in any solver of the process: a solver's first iteration has
// no time of its own to go by. The prior is this machine's (≈15 ms at 240 motions); measured
// iterations replace it at once.
std::atomic<double> g_newton_ns_per_cube{1.0};

Clock::duration newton_cost(int motions, Clock::duration last) {
  const double cube = static_cast<double>(motions) * motions * motions;
  const auto typical = std::chrono::nanoseconds(
      static_cast<long long>(g_newton_ns_per_cube.load(std::memory_order_relaxed) * cube));
  return std::max<Clock::duration>(typical, last);
}

void record_newton(int motions, Clock::duration took) {
  if (motions < 16) return;  // too small for its cube to say anything
  const double cube = static_cast<double>(motions) * motions * motions;
  const double per_cube =
      static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(took).count()) /
      cube;
  g_newton_ns_per_cube.store(per_cube, std::memory_order_relaxed);
}

}  // namespace

Eigen::MatrixXd ManifoldSolver::columns(const Eigen::MatrixXd& m, const std::vector<int>& cols) {
  Eigen::MatrixXd out(m.rows(), static_cast<int>(cols.size()));
  for (std::size_t i = 0; i < cols.size(); ++i) out.col(static_cast<int>(i)) = m.col(cols[i]);
  return out;
}

Eigen::VectorXd ManifoldSolver::rows(const Eigen::VectorXd& v, const std::vector<int>& idx) {
  Eigen::VectorXd out(static_cast<int>(idx.size()));
  for (std::size_t i = 0; i < idx.size(); ++i) out[static_cast<int>(i)] = v[idx[i]];
  return out;
}

namespace {

// The value `window` steps before the last of `history` (none while it is shorter): the runs
// that stop when they stall or crawl compare it with where they are now.
std::optional<double> window_ago(const std::vector<double>& history, std::size_t window) {
  if (history.size() <= window) return std::nullopt;
  return history[history.size() - 1 - window];
}

// The rank a column-pivoted QR reveals: pivots above 10⁻⁹ of the largest (and 10⁻¹²), as an
// SVD would at that tolerance (redundant closure rows leave pivots at round-off).
int revealed_rank(const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr) {
  const Eigen::VectorXd pivots = qr.matrixQR().diagonal().cwiseAbs();
  const double tol = std::max(1e-12, 1e-9 * (pivots.size() ? pivots[0] : 0.0));
  int rank = 0;
  while (rank < pivots.size() && pivots[rank] > tol) ++rank;
  return rank;
}

// The motions m's rows allow: the factorisation their basis Z comes from (none when m has no
// rows: Z is the identity). Column-pivoted Householder QR of mᵀ: the first `rank` columns of Q
// span m's row space and the others its null space. It reveals rank at this tolerance as an
// SVD does (redundant closure rows leave pivots at round-off), without the SVD's Jacobi
// sweeps, which were a quarter of a cycle design's step 1. Z itself is not formed: on a
// 64-hook chain forming it (Q applied to 254 columns) was most of an iteration of step 1's
// fits, which only multiply by it.
void set_motions(const Eigen::MatrixXd& m, ManifoldSolver::Active& act) {
  const int n = static_cast<int>(m.cols());
  if (m.rows() == 0 || n == 0) return;
  auto qr = std::make_shared<Eigen::ColPivHouseholderQR<Eigen::MatrixXd>>(m.transpose());
  act.rank = std::min(revealed_rank(*qr), n);
  act.rows_qr = std::move(qr);
}

// B·y: the fold's coordinates (rows of y) on `free`.
template <typename Dense>
Dense unfold(const ManifoldSolver::Active& act, const Dense& y) {
  if (act.fold.empty()) return y;
  Dense out = Dense::Zero(static_cast<Eigen::Index>(act.free.size()), y.cols());
  for (std::size_t r = 0; r < act.fold.size(); ++r) {
    const ManifoldSolver::Active::Fold& f = act.fold[r];
    const auto row = static_cast<Eigen::Index>(r);
    out.row(f.slot) += f.keep_self * y.row(row);
    if (f.partner >= 0) out.row(f.partner) += f.keep_partner * y.row(row);
  }
  return out;
}

// m·B: m's columns (on `free`) in the fold's coordinates.
Eigen::MatrixXd fold_columns(const ManifoldSolver::Active& act, const Eigen::MatrixXd& m) {
  if (act.fold.empty()) return m;
  Eigen::MatrixXd out(m.rows(), static_cast<Eigen::Index>(act.fold.size()));
  for (std::size_t r = 0; r < act.fold.size(); ++r) {
    const ManifoldSolver::Active::Fold& f = act.fold[r];
    const auto col = static_cast<Eigen::Index>(r);
    out.col(col) = f.keep_self * m.col(f.slot);
    if (f.partner >= 0) out.col(col) += f.keep_partner * m.col(f.partner);
  }
  return out;
}

// B·Z·q for a vector or a matrix of motions' coordinates: q below the rank, turned by the
// reflectors, unfolded.
template <typename Dense>
Dense along_basis(const ManifoldSolver::Active& act, const Dense& q) {
  if (!act.rows_qr) return unfold(act, q);
  const int n = act.folded();
  Dense out = Dense::Zero(n, q.cols());
  // An empty product would offset a null pointer in Eigen's reflectors (UBSan: undefined).
  if (act.rank >= n || q.cols() == 0) return unfold(act, out);
  out.bottomRows(n - act.rank) = q;
  out.applyOnTheLeft(act.rows_qr->householderQ());
  return unfold(act, out);
}

}  // namespace

Eigen::VectorXd ManifoldSolver::Active::along(const Eigen::VectorXd& q) const {
  return along_basis(*this, q);
}

Eigen::MatrixXd ManifoldSolver::Active::along(const Eigen::MatrixXd& q) const {
  return along_basis(*this, q);
}

Eigen::VectorXd ManifoldSolver::Active::onto(const Eigen::VectorXd& v) const {
  // Bᵀ·v: the transpose of a fold is a fold of the row.
  const Eigen::VectorXd folded_v =
      fold.empty() ? v : Eigen::VectorXd(fold_columns(*this, v.transpose()).transpose());
  if (!rows_qr) return folded_v;
  const int n = folded();
  if (rank >= n) return Eigen::VectorXd(0);
  Eigen::VectorXd turned = folded_v;
  turned.applyOnTheLeft(rows_qr->householderQ().adjoint());
  return turned.tail(n - rank);
}

Eigen::MatrixXd ManifoldSolver::Active::basis() const {
  const int k = motions();
  return along(Eigen::MatrixXd(Eigen::MatrixXd::Identity(k, k)));
}

Eigen::MatrixXd ManifoldSolver::null_space(const Eigen::MatrixXd& m) {
  Active act;
  act.free.resize(static_cast<std::size_t>(m.cols()));
  set_motions(m, act);
  return act.basis();
}

Eigen::MatrixXd ManifoldSolver::reduced(const Active& act, const Eigen::MatrixXd& unfolded) {
  // Bᵀ·m·B, m symmetric: (m·B)ᵀ·B.
  const Eigen::MatrixXd m =
      act.fold.empty() ? unfolded
                       : Eigen::MatrixXd(fold_columns(
                             act, Eigen::MatrixXd(fold_columns(act, unfolded).transpose())));
  if (!act.rows_qr) return m;
  // Zᵀ·m·Z is the trailing block of Qᵀ·m·Q, and Q is one reflector per kept row: applied to
  // both sides it costs O(n²·rows) where the products with the explicit Z cost 2n³ (on a
  // 64-hook chain holding its target, 70 Mflop an iteration).
  const int k = static_cast<int>(m.rows()) - act.rank;
  if (k <= 0) return Eigen::MatrixXd(0, 0);
  Eigen::MatrixXd full = m;
  full.applyOnTheLeft(act.rows_qr->householderQ().adjoint());
  full.applyOnTheRight(act.rows_qr->householderQ());
  return full.bottomRightCorner(k, k);
}

Eigen::MatrixXd ManifoldSolver::along_motions(const Active& act, const Eigen::MatrixXd& unfolded) {
  const Eigen::MatrixXd m = fold_columns(act, unfolded);
  if (!act.rows_qr) return m;  // Z is the identity: no product (n² per row for nothing)
  const int k = static_cast<int>(m.cols()) - act.rank;
  if (k <= 0) return Eigen::MatrixXd(m.rows(), 0);
  Eigen::MatrixXd turned = m;
  turned.applyOnTheRight(act.rows_qr->householderQ());
  return turned.rightCols(k);
}

// aᵀ·P = Q·R, so a = P·Rᵀ·Qᵀ and x = Q·[y; 0] with R₁₁ᵀ·y = (Pᵀ·b) over the first `rank` rows.
Eigen::VectorXd ManifoldSolver::min_norm_solution(const Eigen::MatrixXd& a,
                                                  const Eigen::VectorXd& b) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(a.cols());
  if (a.rows() == 0 || a.cols() == 0) return x;  // Eigen's QR of an empty matrix is undefined
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a.transpose());
  const int rank = revealed_rank(qr);
  if (rank == 0) return x;
  const Eigen::VectorXd permuted = qr.colsPermutation().transpose() * b;
  x.head(rank) = qr.matrixQR()
                     .topLeftCorner(rank, rank)
                     .triangularView<Eigen::Upper>()
                     .transpose()
                     .solve(permuted.head(rank));
  x.applyOnTheLeft(qr.householderQ());
  return x;
}

int ManifoldSolver::at_bound(const Eigen::VectorXd& z, int k) const {
  const double tol = 1e-9 * std::max(1.0, hi_[k] - lo_[k]);
  if (std::isfinite(lo_[k]) && z[k] <= lo_[k] + tol) return -1;
  if (std::isfinite(hi_[k]) && z[k] >= hi_[k] - tol) return +1;
  return 0;
}

std::vector<int> ManifoldSolver::off_bounds(const Point& p) const {
  std::vector<int> f;
  for (int k = 0; k < n_; ++k) {
    if (at_bound(p.z, k) == 0) f.push_back(k);
  }
  return f;
}

std::vector<int> ManifoldSolver::all_rows(const Point& p) {
  std::vector<int> r(static_cast<std::size_t>(p.J.rows()));
  for (std::size_t i = 0; i < r.size(); ++i) r[i] = static_cast<int>(i);
  return r;
}

namespace {

Eigen::MatrixXd row_subset(const Eigen::MatrixXd& m, const std::vector<int>& rows) {
  Eigen::MatrixXd out(static_cast<int>(rows.size()), m.cols());
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<int>(i)) = m.row(rows[i]);
  return out;
}

}  // namespace

// Least-squares multipliers of the kept rows: g_F ≈ J_{rows,F}ᵀ λ.
Eigen::VectorXd ManifoldSolver::multipliers(const Point& p,
                                            const std::vector<int>& free,
                                            const std::vector<int>& kept) const {
  if (kept.empty()) return Eigen::VectorXd();
  if (free.empty()) return Eigen::VectorXd::Zero(static_cast<int>(kept.size()));
  // Redundant closure equations (fixed joints) make J rank-deficient: drop its near-zero
  // singular values, as null_space() does, or the multipliers blow up with round-off.
  return least_squares_multipliers(columns(row_subset(p.J, kept), free), rows(p.g, free));
}

Eigen::VectorXd ManifoldSolver::least_squares_multipliers(const Eigen::MatrixXd& rows,
                                                          const Eigen::VectorXd& gradient) {
  // The threshold is set before the decomposition: its Z part is built for the rank it finds
  // (set afterwards, a lower rank read reflectors that were never computed — uninitialised
  // memory, and multipliers of 1e244 on a soap bottle's settling).
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod;
  cod.setThreshold(1e-9);
  cod.compute(rows.transpose());
  return cod.solve(gradient);
}

void ManifoldSolver::set_basis(const Eigen::MatrixXd& kept_rows, Active& act) const {
  act.fold.clear();
  act.rows_qr.reset();
  act.rank = 0;
  const int nf = static_cast<int>(act.free.size());
  if (nf >= options_.fold_gauge_from && !gauge_) gauge_ = problem_.gauge_pairs();
  if (nf >= options_.fold_gauge_from && !gauge_->empty()) {
    std::vector<int> slot_of(static_cast<std::size_t>(n_), -1);
    for (int i = 0; i < nf; ++i)
      slot_of[static_cast<std::size_t>(act.free[static_cast<std::size_t>(i)])] = i;
    std::vector<Active::Fold> by_slot(static_cast<std::size_t>(nf));
    std::vector<char> dropped(static_cast<std::size_t>(nf), 0);
    bool any = false;
    for (int i = 0; i < nf; ++i) by_slot[static_cast<std::size_t>(i)].slot = i;
    for (const ManifoldProblem::GaugePair& g : *gauge_) {
      const int sa = slot_of[static_cast<std::size_t>(g.a)];
      const int sb = slot_of[static_cast<std::size_t>(g.b)];
      if (sa < 0 || sb < 0) continue;  // one of them held at a bound: no gauge left
      Active::Fold& f = by_slot[static_cast<std::size_t>(sa)];
      if (f.partner >= 0 || dropped[static_cast<std::size_t>(sa)] ||
          dropped[static_cast<std::size_t>(sb)] ||
          by_slot[static_cast<std::size_t>(sb)].partner >= 0) {
        continue;
      }
      // The kept direction is the null direction turned a quarter turn in the pair's plane.
      const double norm = std::hypot(g.null_a, g.null_b);
      if (!(norm > 0)) continue;
      f.partner = sb;
      f.keep_self = g.null_b / norm;
      f.keep_partner = -g.null_a / norm;
      dropped[static_cast<std::size_t>(sb)] = 1;
      any = true;
    }
    if (any) {
      for (int i = 0; i < nf; ++i) {
        if (!dropped[static_cast<std::size_t>(i)])
          act.fold.push_back(by_slot[static_cast<std::size_t>(i)]);
      }
    }
  }
  set_motions(fold_columns(act, kept_rows), act);
}

ManifoldSolver::Active ManifoldSolver::active_set(const Point& p) const {
  Active act;
  const std::vector<int> off = off_bounds(p);
  act.rows = all_rows(p);
  // A binding inequality g ≤ 0 holds the point only if the objective presses against it
  // (∇f = Jᵀλ with λ ≤ 0 on its row); one the objective pulls away from is let go.
  const int equalities = static_cast<int>(p.J.rows()) - static_cast<int>(p.binding.size());
  if (!p.binding.empty()) {
    const Eigen::VectorXd lambda = multipliers(p, off, act.rows);
    std::vector<int> kept;
    for (int r : act.rows) {
      if (r < equalities || lambda[r] <= options_.gradient_tolerance) kept.push_back(r);
    }
    act.rows = std::move(kept);
  }
  const Eigen::VectorXd lambda = multipliers(p, off, act.rows);
  const Eigen::MatrixXd J = row_subset(p.J, act.rows);
  const Eigen::VectorXd reduced =
      lambda.size() ? Eigen::VectorXd(p.g - J.transpose() * lambda) : p.g;
  for (int k = 0; k < n_; ++k) {
    const int side = at_bound(p.z, k);
    if (side == 0 || side * reduced[k] > options_.gradient_tolerance) act.free.push_back(k);
  }
  set_basis(columns(J, act.free), act);
  return act;
}

ManifoldSolver::Point ManifoldSolver::evaluate(const Eigen::VectorXd& z,
                                               const std::vector<int>* binding) {
  return evaluate_rows(z, binding, /*slopes_only=*/false);
}

ManifoldSolver::Point ManifoldSolver::evaluate_slopes(const Eigen::VectorXd& z,
                                                      const std::vector<int>& binding) {
  return evaluate_rows(z, &binding, /*slopes_only=*/true);
}

ManifoldSolver::Point ManifoldSolver::evaluate_rows(const Eigen::VectorXd& z,
                                                    const std::vector<int>* binding,
                                                    bool slopes_only) {
  Point p;
  p.z = z;
  const int no = problem_.objectives();
  const int m = problem_.equalities();
  const int ni = problem_.inequalities();
  const int total = no + m + ni;
  // Reused, not cleared: the problem writes every entry (ManifoldProblem::evaluate). Clearing
  // them was 7 % of a 128-hook chain's time, its contact rows spanning 516 coordinates.
  values_.resize(static_cast<std::size_t>(total));
  jacobian_.resize(static_cast<std::size_t>(total) * static_cast<std::size_t>(n_));
  if (slopes_only) {
    problem_.evaluate_slopes(z.data(), values_.data(), jacobian_.data());
  } else {
    problem_.evaluate(z.data(), values_.data(), jacobian_.data());
  }
  auto grad = [&](int row, int col) {
    return jacobian_[static_cast<std::size_t>(row) * static_cast<std::size_t>(n_) +
                     static_cast<std::size_t>(col)];
  };
  const std::vector<int> rows = take_values(p, binding);
  p.J.resize(static_cast<Eigen::Index>(rows.size()), n_);
  for (std::size_t r = 0; r < rows.size(); ++r) {
    for (int k = 0; k < n_; ++k) p.J(static_cast<Eigen::Index>(r), k) = grad(rows[r], k);
  }
  p.g.resize(n_);
  if (no == 1) {
    for (int k = 0; k < n_; ++k) p.g[k] = grad(0, k);
  } else {
    p.Jr.resize(no, n_);
    for (int i = 0; i < no; ++i) {
      for (int k = 0; k < n_; ++k) p.Jr(i, k) = grad(i, k);
    }
    p.g = p.Jr.transpose() * p.r;
  }
  return p;
}

ManifoldSolver::Point ManifoldSolver::evaluate_values(const Eigen::VectorXd& z) {
  Point p;
  p.z = z;
  p.complete = false;
  values_.resize(static_cast<std::size_t>(problem_.objectives() + problem_.equalities() +
                                          problem_.inequalities()));
  problem_.evaluate_values(z.data(), values_.data());
  take_values(p, nullptr);
  return p;
}

std::vector<int> ManifoldSolver::take_values(Point& p, const std::vector<int>* binding) const {
  const int no = problem_.objectives();
  const int m = problem_.equalities();
  const int ni = problem_.inequalities();
  auto value = [&](int row) { return values_[static_cast<std::size_t>(row)]; };
  std::vector<int> rows;  // of values_: the equalities, then the binding inequalities
  for (int r = 0; r < m; ++r) rows.push_back(no + r);
  if (binding) {
    for (int i : *binding) rows.push_back(no + m + i);
    p.binding = *binding;
  } else {
    for (int i = 0; i < ni; ++i) {
      if (value(no + m + i) > -options_.inequality_margin) {
        rows.push_back(no + m + i);
        p.binding.push_back(i);
      }
    }
  }
  p.h.resize(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    // An inequality binds only while active; a satisfied one contributes 0.
    const double v = value(rows[r]);
    p.h[static_cast<Eigen::Index>(r)] = static_cast<int>(r) < m ? v : std::max(0.0, v);
  }
  if (no == 1) {
    p.f = value(0);
  } else {
    p.r.resize(no);
    for (int i = 0; i < no; ++i) p.r[i] = value(i);
    p.f = 0.5 * p.r.squaredNorm();
  }
  return rows;
}

void ManifoldSolver::complete(Point& p) {
  if (p.complete) return;
  const bool valid = p.valid;
  p = evaluate(p.z);
  p.valid = valid;
}

bool ManifoldSolver::project(Point& p) {
  for (int iter = 0; iter < 30; ++iter) {
    if (p.h.size() == 0 || p.h.cwiseAbs().maxCoeff() < options_.feasibility_tolerance) return true;
    complete(p);
    const std::vector<int> free = off_bounds(p);
    if (free.empty()) return false;
    // Binding contact rows may outnumber the free coordinates and disagree with each other:
    // those get the least-squares solution of a complete orthogonal decomposition.
    const Eigen::MatrixXd jf = columns(p.J, free);
    const Eigen::VectorXd delta =
        p.binding.empty() ? min_norm_solution(jf, -p.h)
                          : Eigen::VectorXd(jf.completeOrthogonalDecomposition().solve(-p.h));
    Eigen::VectorXd z = p.z;
    for (std::size_t i = 0; i < free.size(); ++i) z[free[i]] += delta[static_cast<int>(i)];
    const double before = p.h.norm();
    // Values first: the next iteration, or the caller if it keeps the point, completes it (a
    // rejected trial step never needs the derivatives at its projection).
    p = evaluate_values(z.cwiseMax(lo_).cwiseMin(hi_));
    if (p.h.norm() > before && iter > 3) return false;
  }
  return p.h.size() == 0 || p.h.cwiseAbs().maxCoeff() < options_.projection_tolerance;
}

ManifoldSolver::Point ManifoldSolver::step(const Point& from,
                                           const Active& act,
                                           const Eigen::VectorXd& dF) {
  Eigen::VectorXd z = from.z;
  for (std::size_t i = 0; i < act.free.size(); ++i) z[act.free[i]] += dF[static_cast<int>(i)];
  // Values first: a step the solver rejects never needs its derivatives (the caller completes
  // the point it keeps).
  Point trial = evaluate_values(z.cwiseMax(lo_).cwiseMin(hi_));
  trial.valid = project(trial) && problem_.acceptable(trial.z.data());
  return trial;
}

Eigen::MatrixXd ManifoldSolver::lagrangian_hessian(const Point& p, const Active& act) {
  const Eigen::VectorXd lambda = multipliers(p, act.free, act.rows);
  const int nf = static_cast<int>(act.free.size());
  Eigen::MatrixXd H(nf, nf);
  // Rows whose curvature counts: flat inequalities keep their slope at p.
  const int equalities = static_cast<int>(p.J.rows()) - static_cast<int>(p.binding.size());
  std::vector<char> flat(static_cast<std::size_t>(p.J.rows()), 0);
  for (std::size_t i = 0; i < p.binding.size(); ++i) {
    flat[static_cast<std::size_t>(equalities) + i] = problem_.flat_inequality(p.binding[i]) ? 1 : 0;
  }
  // The problem's exact Hessian where it has one: no evaluation per column. The rows that
  // curve are passed with their multipliers (flat ones keep their slope: no curvature).
  {
    std::vector<int> curving;
    Eigen::VectorXd curving_lambda(static_cast<Eigen::Index>(act.rows.size()));
    for (std::size_t i = 0; i < act.rows.size(); ++i) {
      const int r = act.rows[i];
      if (flat[static_cast<std::size_t>(r)]) continue;
      curving_lambda[static_cast<Eigen::Index>(curving.size())] =
          lambda[static_cast<Eigen::Index>(i)];
      curving.push_back(r < equalities ? r
                                       : problem_.equalities() +
                                             p.binding[static_cast<std::size_t>(r - equalities)]);
    }
    curving_lambda.conservativeResize(static_cast<Eigen::Index>(curving.size()));
    Eigen::MatrixXd full;
    if (problem_.lagrangian_hessian(p.z.data(), curving, curving_lambda, full)) {
      for (int i = 0; i < nf; ++i) {
        for (int j = 0; j < nf; ++j) {
          H(i, j) =
              full(act.free[static_cast<std::size_t>(i)], act.free[static_cast<std::size_t>(j)]);
        }
      }
      return H;
    }
  }
  auto grad_l = [&](const Point& q) {
    Eigen::VectorXd gl = q.g;
    // q is evaluated with p's binding rows, so its rows line up with p's.
    if (lambda.size() && q.J.rows() == p.J.rows()) {
      Eigen::MatrixXd J = row_subset(q.J, act.rows);
      for (std::size_t i = 0; i < act.rows.size(); ++i) {
        const int r = act.rows[i];
        if (flat[static_cast<std::size_t>(r)]) J.row(static_cast<int>(i)) = p.J.row(r);
      }
      gl -= J.transpose() * lambda;
    }
    return rows(gl, act.free);
  };
  const Eigen::VectorXd g0 = grad_l(p);
  H.setZero();
  for (int i = 0; i < nf; ++i) {
    // A column costs an evaluation; on a long chain the whole matrix costs more than a
    // deadline's slack, so the deadline is checked per column (the caller stops).
    if (out_of_time()) break;
    const int k = act.free[static_cast<std::size_t>(i)];
    const double eps = 1e-6 * std::max(1.0, std::abs(p.z[k]));
    Eigen::VectorXd zp = p.z;
    zp[k] += eps;
    H.col(i) = (grad_l(evaluate_slopes(zp, p.binding)) - g0) / eps;
  }
  return H;
}

ManifoldSolver::Result ManifoldSolver::finish(const Point& cur,
                                              int iterations,
                                              int max_iterations,
                                              Result out) const {
  out.iterations = iterations;
  out.converged = iterations < max_iterations;
  out.z = cur.z;
  out.timed_out = out_of_time();
  return out;
}

bool ManifoldSolver::close(Eigen::VectorXd& z0, int max_iterations) {
  Point cur = evaluate(z0.cwiseMax(lo_).cwiseMin(hi_));
  double mu = 1e-3;
  Clock::duration last{};
  // Levenberg-Marquardt closes a gap it can reach superlinearly; one that has not halved ‖h‖²
  // in ten iterations is creeping towards a gap it will not close (parts starting deep inside
  // each other, their contact rows unmet; a random start of a long cycle), as the closure
  // search's starts are judged.
  constexpr std::size_t kStallWindow = 10;
  constexpr double kStallFactor = 0.5;
  std::vector<double> gaps;  // ‖h‖² after each iteration
  for (int it = 0; it < max_iterations; ++it) {
    if (cur.h.size() == 0 || cur.h.cwiseAbs().maxCoeff() < options_.projection_tolerance) break;
    if (no_time_for(last)) return false;
    const auto began = Clock::now();
    const std::vector<int> free = off_bounds(cur);
    if (free.empty()) return false;
    const Eigen::MatrixXd JF = columns(cur.J, free);
    const Eigen::MatrixXd N = JF.transpose() * JF;
    const Eigen::VectorXd b = JF.transpose() * cur.h;
    const double scale = std::max(1e-12, N.diagonal().maxCoeff());
    bool moved = false;
    for (int tries = 0; tries < 10 && !moved; ++tries) {
      Eigen::MatrixXd M = N;
      M.diagonal().array() += mu * scale;
      const Eigen::VectorXd d = -M.ldlt().solve(b);
      Eigen::VectorXd z = cur.z;
      for (std::size_t i = 0; i < free.size(); ++i) z[free[i]] += d[static_cast<int>(i)];
      Point trial = evaluate(z.cwiseMax(lo_).cwiseMin(hi_));
      if (trial.h.squaredNorm() < cur.h.squaredNorm()) {
        cur = std::move(trial);
        mu = std::max(1e-12, mu / 3);
        moved = true;
      } else {
        mu *= 8;
      }
    }
    if (!moved) return false;
    last = Clock::now() - began;
    gaps.push_back(cur.h.squaredNorm());
    const std::optional<double> before = window_ago(gaps, kStallWindow);
    if (before && gaps.back() > kStallFactor * *before) return false;
  }
  if (!project(cur)) return false;
  z0 = cur.z;
  return true;
}

ManifoldSolver::Result ManifoldSolver::fit(const Eigen::VectorXd& z0,
                                           int max_iterations,
                                           double give_up) {
  Result out;
  Point cur = evaluate(z0.cwiseMax(lo_).cwiseMin(hi_));
  out.closed = project(cur);
  if (!out.closed) {
    out.z = cur.z;
    return out;
  }
  complete(cur);
  double mu = 1e-4;
  int it = 0;
  Clock::duration last{};
  // Gauss-Newton, which Levenberg-Marquardt becomes as its damping falls, converges only
  // linearly where the residuals stay large at the minimum (a target the hack cannot quite
  // reach): such fits crawled for hundreds of iterations and ended at the iteration limit short
  // of the minimum (clip light S: 460 iterations for the last 2 % of f). Once kCrawlWindow
  // iterations have lowered f by less than kCrawlDecrease of it together, the fit is finished
  // by Newton's method on ½‖r‖² (relax()), whose Hessian has the residuals' own curvature.
  // Stopping there instead would be faster but leaves the fit short (clip light M: 4.27 mm
  // from its target instead of 3.55).
  constexpr std::size_t kCrawlWindow = 10;
  constexpr double kCrawlDecrease = 0.01;
  std::vector<double> history;  // f after each iteration
  bool crawling = false;
  for (; it < max_iterations; ++it) {
    if (it == 15 && cur.f > give_up) break;
    if (no_time_for(last)) break;
    const auto began = Clock::now();
    const Active act = active_set(cur);
    if (act.motions() == 0) break;
    const Eigen::MatrixXd A = along_motions(act, columns(cur.Jr, act.free));
    const Eigen::VectorXd b = A.transpose() * cur.r;
    if (b.cwiseAbs().maxCoeff() < options_.gradient_tolerance) break;
    // The damped step solves (AᵀA + c·I) p = −Aᵀr. With far fewer residuals than free motions
    // (a target's twelve rows against a long chain's hundred angles) the same p is
    // −V·diag(σ/(σ² + c))·Uᵀr from the thin SVD A = UΣVᵀ: a decomposition the size of the
    // residuals, once per iteration, and stable where the rows are dependent (the nine
    // rotation entries have three degrees of freedom), which AAᵀ's inverse would not be.
    // Worth it only well past the residuals' size: below, the motions' own system is as cheap,
    // and the two differ in round-off, which moves the fits' paths (measured on the gallery).
    //
    // The SVD is taken through Aᵀ = Q·R (Householder): A = Rᵀ·Qᵀ, and with Rᵀ = U·Σ·Wᵀ (an SVD
    // the size of the residuals) V = Q·W, so p = −Q·(W·diag(σ/(σ² + c))·Uᵀr), and V itself is
    // never formed. Eigen's SVD of A formed it, applying every Jacobi rotation of its sweeps to
    // all of V's rows: on a 64-hook chain that was most of an iteration of step 1.
    const bool wide = A.cols() > 4 * A.rows();
    Eigen::MatrixXd N;
    Eigen::HouseholderQR<Eigen::MatrixXd> rows_qr;
    Eigen::JacobiSVD<Eigen::MatrixXd> svd;
    Eigen::VectorXd projected;  // Uᵀr
    if (wide) {
      rows_qr.compute(A.transpose());
      const Eigen::Index m = A.rows();
      const Eigen::MatrixXd r_transposed =
          rows_qr.matrixQR().topRows(m).triangularView<Eigen::Upper>().transpose();
      svd.compute(r_transposed, Eigen::ComputeFullU | Eigen::ComputeFullV);
      projected = svd.matrixU().transpose() * cur.r;
    } else {
      N = A.transpose() * A;
    }
    // The damping's scale: AᵀA's largest diagonal entry, a column's squared norm.
    const double scale =
        std::max(1e-12, wide ? A.colwise().squaredNorm().maxCoeff() : N.diagonal().maxCoeff());
    bool moved = false;
    for (int tries = 0; tries < 12 && !moved; ++tries) {
      Eigen::VectorXd p;
      if (wide) {
        const Eigen::VectorXd& sigma = svd.singularValues();
        const Eigen::VectorXd weights =
            (sigma.array() / (sigma.array().square() + mu * scale)).matrix();
        Eigen::VectorXd turned = Eigen::VectorXd::Zero(A.cols());
        turned.head(A.rows()) = svd.matrixV() * weights.cwiseProduct(projected);
        turned.applyOnTheLeft(rows_qr.householderQ());
        p = -turned;
      } else {
        Eigen::MatrixXd M = N;
        M.diagonal().array() += mu * scale;
        p = -M.ldlt().solve(b);
      }
      Point trial = step(cur, act, act.along(p));
      if (trial.valid && trial.f < cur.f) {
        moved = cur.f - trial.f > 1e-14 * std::max(1.0, cur.f);
        complete(trial);
        cur = std::move(trial);
        mu = std::max(1e-12, mu / 3);
        if (!moved) break;
        moved = true;
      } else {
        mu *= 8;
      }
    }
    if (!moved) break;
    last = Clock::now() - began;
    history.push_back(cur.f);
    const std::optional<double> before = window_ago(history, kCrawlWindow);
    if (before && *before - cur.f < kCrawlDecrease * cur.f) {
      crawling = true;
      ++it;
      break;
    }
    // Close enough for the caller and converging slowly (not halving ½‖r‖² in ten iterations):
    // done. A long chain's fit crept from 0.03 mm to its goal for the rest of its 500.
    if (before && cur.f <= options_.finish_above && *before < 2 * cur.f) {
      ++it;
      break;
    }
  }
  // A start that would be abandoned (far from the best so far) is not finished.
  // Newton's method is held to the same rule: where it crawls too (steps clamped at bounds
  // failing, the trust region shrinking: clip light M's random starts ran 74-77 iterations into
  // their limit lowering f by 0.15 % per ten) the fit is as near as these methods get.
  if (crawling && cur.f <= give_up && cur.f > options_.finish_above && it < max_iterations) {
    Result polished = newton(cur.z,
                             max_iterations - it,
                             /*small_curvatures=*/true,
                             {static_cast<int>(kCrawlWindow), kCrawlDecrease * cur.f});
    polished.iterations += it;
    return polished;
  }
  return finish(cur, it, max_iterations, out);
}

ManifoldSolver::Curvature ManifoldSolver::curvature(const Point& p) {
  Curvature c;
  const Active act = active_set(p);
  c.free = act.free;
  if (act.motions() == 0 || no_time_for(newton_cost(act.motions(), {}))) return c;
  const Eigen::MatrixXd full = lagrangian_hessian(p, act);
  if (out_of_time()) return c;  // incomplete: no curvature is reported
  Eigen::MatrixXd H = reduced(act, full);
  H = 0.5 * (H + H.transpose());
  // As the relaxations' models are decomposed (LAPACK's divide and conquer from
  // Eigenbasis::kFactoredFrom): Eigen's QR iteration formed every eigenvector by rotations, a
  // third of a 128-hook chain's solve.
  return curvature_from(p, act, Eigenbasis(H));
}

ManifoldSolver::Curvature ManifoldSolver::curvature_from(const Point& p,
                                                         const Active& act,
                                                         const Eigenbasis& eig) const {
  Curvature c;
  c.free = act.free;
  c.rows = act.rows;
  c.binding = static_cast<int>(p.binding.size());
  c.eigenvalues = eig.values();
  const double largest = c.eigenvalues.size() ? c.eigenvalues.cwiseAbs().maxCoeff() : 0.0;
  c.neutral_threshold = std::max(options_.neutral_floor, options_.neutral_curvature * largest);
  // Only the neutral directions are formed: the rest would cost a product the size of the
  // model's cube and nobody reads them.
  std::vector<int> neutral;
  for (int i = 0; i < c.eigenvalues.size(); ++i) {
    if (std::abs(c.eigenvalues[i]) <= c.neutral_threshold) neutral.push_back(i);
  }
  c.directions.resize(n_, 0);
  if (neutral.empty()) return c;  // (rows of an empty matrix have no data to point at)
  Eigen::MatrixXd basis(eig.size(), static_cast<Eigen::Index>(neutral.size()));
  for (std::size_t k = 0; k < neutral.size(); ++k) {
    basis.col(static_cast<Eigen::Index>(k)) = eig.vector(neutral[k]);
  }
  const Eigen::MatrixXd local = act.along(basis);
  c.directions = Eigen::MatrixXd::Zero(n_, local.cols());
  for (std::size_t i = 0; i < act.free.size(); ++i) {
    c.directions.row(act.free[i]) = local.row(static_cast<int>(i));
  }
  return c;
}

namespace {
// The trust region's radius at the start of a relaxation, as a share of the longest step.
constexpr double kInitialRadiusShare = 0.2;
// What the radius is multiplied by after a step whose projection back onto the constraints
// failed (0.25 after a step that was merely worse than its model).
constexpr double kFailedProjectionShrink = 0.05;
// Steps in a row that promise less than the potential resolves and do not lower its slope,
// after which the relaxation stops where it is.
constexpr int kUnresolvedSteps = 2;
// Iterations of a relaxation after which coordinates that keep meeting their bounds are held
// at them (newton()).
constexpr int kHoldAfter = 50;
}  // namespace

ManifoldSolver::Result ManifoldSolver::relax(const Eigen::VectorXd& z0, int max_iterations) {
  return newton(z0,
                max_iterations,
                /*small_curvatures=*/false,
                {options_.progress_window, options_.least_progress});
}

ManifoldSolver::Result ManifoldSolver::newton(const Eigen::VectorXd& z0,
                                              int max_iterations,
                                              bool small_curvatures,
                                              ProgressFloor floor) {
  // A trust-region Newton method on the manifold (Nocedal & Wright, ch. 4): each step solves
  // min gᵀp + ½pᵀHp within |p| ≤ Δ in the eigenbasis of the reduced Hessian H, so negative
  // curvature is followed down (a balance point is left, not kept) and neutral directions get
  // no step unless the potential slopes along them. Δ grows on steps the model predicts well
  // and shrinks on the others.
  Result out;
  Point cur = evaluate(z0.cwiseMax(lo_).cwiseMin(hi_));
  out.closed = project(cur);
  if (!out.closed) {
    out.z = cur.z;
    return out;
  }
  complete(cur);
  double radius = kInitialRadiusShare * options_.max_step;
  int it = 0;
  int motions = n_;  // free motions at the last iteration
  Clock::duration last{};
  std::optional<Clock::time_point> previous;
  bool model_current = false;
  int unresolved = 0;  // steps in a row judged by the slope (below) that did not lower it
  // Coordinates caught at a bound again after being let go of it, once a relaxation has run
  // kHoldAfter iterations: held there until the point is at rest with them held, then let go
  // together (the classic active-set rule). Without it a long slack chain's joints left and
  // met their stops step after step, the steps stayed short and 500 iterations ended short of
  // rest (slopes of 1e-6 to 6e-5: "did not converge"). From the first iteration it cost more
  // than it saved where a few joints settle against their stops and leave them once or twice
  // on the way (the reading nook 265 -> 620 ms); after 50 the gallery's relaxations, which
  // end sooner, are as they were.
  std::vector<int> caught(static_cast<std::size_t>(n_), 0);  // times caught, per coordinate
  std::vector<char> held(static_cast<std::size_t>(n_), 0);
  auto release = [&] {
    bool any = false;
    for (int k = 0; k < n_; ++k) {
      any = any || held[static_cast<std::size_t>(k)] != 0;
      held[static_cast<std::size_t>(k)] = 0;
      caught[static_cast<std::size_t>(k)] = 0;
    }
    if (any) model_current = false;
    return any;
  };
  std::vector<char> was_free(static_cast<std::size_t>(n_), 0);
  auto note_catches = [&](const Point& now) {
    for (int k = 0; k < n_; ++k) {
      const auto i = static_cast<std::size_t>(k);
      if (was_free[i] && at_bound(now.z, k) != 0 && ++caught[i] >= 2 && it >= kHoldAfter) {
        held[i] = 1;
      }
    }
  };
  Active act;
  Eigen::VectorXd rg, lambda, c;
  std::optional<Eigenbasis> V;
  std::vector<double> progress;  // f at the start of each iteration (floor.window)
  for (; it < max_iterations; ++it) {
    const auto began = Clock::now();
    if (previous) {
      last = began - *previous;
      record_newton(motions, last);
    }
    previous = began;
    if (no_time_for(newton_cost(motions, last))) break;
    // The model at cur: a rejected step changes only the radius, so it is kept until cur moves
    // (the Hessian and its eigendecomposition are most of an iteration's cost).
    if (!model_current) {
      act = active_set(cur);
      {
        // Coordinates let go of a bound (free now) that were caught back at it twice stay.
        std::vector<int> kept;
        kept.reserve(act.free.size());
        for (int k : act.free) {
          if (!(held[static_cast<std::size_t>(k)] && at_bound(cur.z, k) != 0)) kept.push_back(k);
        }
        if (kept.size() != act.free.size()) {
          act.free = std::move(kept);
          set_basis(columns(row_subset(cur.J, act.rows), act.free), act);
        }
        std::fill(was_free.begin(), was_free.end(), 0);
        for (int k : act.free) was_free[static_cast<std::size_t>(k)] = 1;
      }
      if (act.motions() == 0) {
        if (release()) continue;
        break;
      }
      motions = act.motions();
      rg = act.onto(rows(cur.g, act.free));
      const Eigen::MatrixXd full = lagrangian_hessian(cur, act);
      if (out_of_time()) break;
      Eigen::MatrixXd H = reduced(act, full);
      H = 0.5 * (H + H.transpose());
      if (out_of_time()) break;
      V.emplace(H);
      if (out_of_time()) break;
      const Eigen::VectorXd& raw = V->values();
      const double neutral =
          std::max(options_.neutral_floor, options_.neutral_curvature * raw.cwiseAbs().maxCoeff());
      // Curvatures within ± neutral are 0; gradient components below tolerance are 0.
      lambda = raw;
      for (int i = 0; i < lambda.size(); ++i) {
        if (std::abs(lambda[i]) <= neutral) lambda[i] = 0;
      }
      c = V->coordinates(rg);
      for (int i = 0; i < c.size(); ++i) {
        if (std::abs(c[i]) <= 0.1 * options_.gradient_tolerance) c[i] = 0;
        if (lambda[i] == 0 && std::abs(c[i]) <= options_.neutral_slope) c[i] = 0;
      }
      // A least-squares fit's finish keeps the small positive curvatures where its objective
      // slopes: they are the residuals' real curvature along the long, shallow valleys of a
      // chain reaching for a target (a 32-hook chain's finish took 123 iterations without
      // them, 32 with), and a fit has no flat family to keep still.
      if (small_curvatures) {
        for (int i = 0; i < c.size(); ++i) {
          if (lambda[i] == 0 && c[i] != 0 && raw[i] > 0) lambda[i] = raw[i];
        }
      }
      model_current = true;
    }
    const bool stationary = rg.cwiseAbs().maxCoeff() < options_.gradient_tolerance;
    if (stationary && lambda[0] >= 0) {
      if (release()) continue;
      // A minimum (up to neutral directions). Its model is the curvature there, which the
      // caller's stability check would make again (4 % of a 64-hook chain's instructions). No
      // coordinate was held (release() found none), so act is active_set's.
      if (options_.curvature_at_rest && !small_curvatures) {
        out.curvature = curvature_from(cur, act, *V);
      }
      break;
    }
    if (floor.window > 0) {
      progress.push_back(cur.f);
      const std::optional<double> before =
          window_ago(progress, static_cast<std::size_t>(floor.window));
      if (before && *before - cur.f < floor.least) break;  // creeping: the caller goes on
    }

    auto step_for = [&](double mu) {
      Eigen::VectorXd y = Eigen::VectorXd::Zero(rg.size());
      for (int i = 0; i < lambda.size(); ++i) {
        if (c[i] != 0) y[i] = -(c[i] / (lambda[i] + mu));
      }
      return V->combination(y);
    };
    // The step's length, from its coordinates in the (orthonormal) eigenbasis: the search
    // for μ below asks it often, and building the step costs a matrix-vector product.
    auto length_for = [&](double mu) {
      double sum = 0;
      for (int i = 0; i < lambda.size(); ++i) {
        if (c[i] == 0) continue;
        const double qi = c[i] / (lambda[i] + mu);
        sum += qi * qi;
      }
      return std::sqrt(sum);
    };
    // The trust-region subproblem: μ = 0 if H is positive there and the step fits; otherwise
    // the μ > max(0, -λ_min) that puts the step on the boundary.
    Eigen::VectorXd p;
    const double lambda_min = lambda[0];
    bool interior = lambda_min > 0 || (lambda_min == 0 && c[0] == 0);
    if (interior) {
      for (int i = 0; i < lambda.size() && interior; ++i) interior = lambda[i] > 0 || c[i] == 0;
    }
    if (interior) p = step_for(0.0);
    if (!interior || p.norm() > radius) {
      const double floor_mu = std::max(0.0, -lambda_min);
      double lo_mu = floor_mu;
      // The gap above the floor grows by doubling; it starts at least a relative 1e-12 of
      // the floor, so that floor + gap is never the floor itself (a doubling of nothing was an
      // endless loop under a huge curvature).
      double gap = std::max({1e-12, 1e-12 * floor_mu, c.norm() / radius});
      double hi_mu = floor_mu + gap;
      for (int k = 0; k < 2100 && length_for(hi_mu) > radius; ++k) {
        gap *= 2;
        hi_mu = floor_mu + gap;
      }
      for (int k = 0; k < 80; ++k) {
        const double mid = 0.5 * (lo_mu + hi_mu);
        (length_for(mid) > radius ? lo_mu : hi_mu) = mid;
      }
      p = step_for(hi_mu);
      // The hard case: no gradient along the most negative direction (a balance point), so
      // the step falls short of the boundary: go the rest of the way along that direction.
      if (lambda_min < 0 && p.norm() < 0.99 * radius) {
        const double extra = std::sqrt(std::max(0.0, radius * radius - p.squaredNorm()));
        p += (c[0] > 0 ? -extra : extra) * V->vector(0);
      }
    }
    // The decrease the model promises: the model the step minimised (neutral curvatures 0),
    // not the raw Hessian, whose round-off along neutral directions can outweigh a small
    // slope over a long step and stop the walk before it gets there.
    const Eigen::VectorXd q = V->coordinates(p);
    const double predicted = -(c.dot(q) + 0.5 * q.dot(lambda.cwiseProduct(q)));
    if (!(predicted > 0) || p.norm() < 1e-14) {
      if (release()) continue;
      break;  // nothing left to gain
    }
    Point trial = step(cur, act, act.along(p));
    const double actual = trial.valid ? cur.f - trial.f : -HUGE_VAL;
    double rho = actual / predicted;
    // Near a minimum the decrease a step promises can be below what the potential's value
    // resolves (round-off of f ≈ 1e-13·|f|, while the slope is still above the tolerance):
    // the ratio is noise there, so such a step is judged by whether it lowers the slope.
    const double resolvable =
        1e3 * std::numeric_limits<double>::epsilon() * std::max(1.0, std::abs(cur.f));
    if (trial.valid && predicted < resolvable) {
      complete(trial);  // judged by its slope
      const Active next = active_set(trial);
      const double before = rg.cwiseAbs().maxCoeff();
      const double after =
          next.motions() > 0 ? next.onto(rows(trial.g, next.free)).cwiseAbs().maxCoeff() : 0.0;
      rho = after < 0.5 * before && actual > -resolvable ? 1.0 : 0.0;
      if (rho > 0) {
        note_catches(trial);
        cur = std::move(trial);
        model_current = false;
        unresolved = 0;
        continue;
      }
      // A step a quarter as long failed too: the slope left is round-off that no shorter
      // step resolves (the radius used to shrink on to 1e-10, a projected step each time:
      // eight or nine more on most least-squares finishes, measured on the gallery).
      if (++unresolved >= kUnresolvedSteps) {
        unresolved = 0;
        if (release()) continue;
        break;
      }
    } else {
      unresolved = 0;
    }
    // A step that reaches an inequality the model did not have (a part coming to touch
    // another) is projected onto it and gains far less than promised, however short: the
    // model, not its reach, is wrong there. Such a step is taken if it lowers the potential,
    // and the radius starts afresh with the new row in the model (a paper towel roll
    // reaching the wall's edge shrank it to 10⁻⁵ and took 20 steps to grow it back).
    const bool binding_changes = trial.valid && trial.binding != cur.binding;
    bool accepted = false;
    if (trial.valid && actual > 0 && (rho > 0.1 || binding_changes)) {
      if (lambda_min < 0 && stationary) ++out.escapes;
      note_catches(trial);
      complete(trial);
      cur = std::move(trial);
      model_current = false;
      accepted = true;
      if (rho > 0.75 && p.norm() > 0.99 * radius) radius = std::min(2 * radius, options_.max_step);
    } else {
      // A step the constraints cannot be brought back onto (the projection failed) is far
      // too long for their curvature, not a little too long for the model: it shrinks by more
      // (a settled start escaping a saddle along a held target's rows failed six times from
      // 10 to 0.0024 at a quarter each, each failure a projection of several iterations).
      radius *= trial.valid ? 0.25 : kFailedProjectionShrink;
    }
    if (rho < 0.25) radius = std::min(radius, 0.25 * p.norm());
    if (accepted && binding_changes)
      radius = std::max(radius, kInitialRadiusShare * options_.max_step);
    if (radius < 1e-10) {
      // The model cannot find a lower point: as good as it gets, unless coordinates were held.
      if (!release()) break;
      radius = kInitialRadiusShare * options_.max_step;
    }
    if (out.escapes > options_.max_escapes) break;
  }
  return finish(cur, it, max_iterations, out);
}

}  // namespace fabkit::solvers

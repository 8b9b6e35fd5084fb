// The manipulation QP (paper eq. 2), its drag sessions, and the projection used by snapping
// and connecting. The QP solvers themselves are behind qp.h.
#include "fabkit/templates/manipulate.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <Eigen/QR>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <map>
#include <mutex>
#include <numeric>

#include "fabkit/templates/diagnostic_codes.h"
#include "qp.h"

namespace fabkit::templates {

namespace {

using Clock = std::chrono::steady_clock;
using SparseRows = Eigen::SparseMatrix<double, Eigen::RowMajor>;

constexpr std::array<std::string_view, 6> kControlNames = {
    "center_x", "center_y", "center_z", "size_x", "size_y", "size_z"};

double dot(const std::vector<LinearTerm>& c, const Eigen::VectorXd& q) {
  double v = 0;
  for (const LinearTerm& t : c) v += t.coefficient * q[t.index];
  return v;
}

SparseRows to_sparse(const std::vector<const Relation*>& rows,
                     Eigen::Index n,
                     Eigen::VectorXd& rhs) {
  std::vector<Eigen::Triplet<double>> trip;
  rhs.resize(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    for (const LinearTerm& t : rows[i]->terms) {
      trip.emplace_back(static_cast<int>(i), t.index, t.coefficient);
    }
    rhs[static_cast<Eigen::Index>(i)] = rows[i]->rhs;
  }
  SparseRows m(static_cast<Eigen::Index>(rows.size()), n);
  m.setFromTriplets(trip.begin(), trip.end());
  return m;
}

// An orthonormal basis of the null space of M (rows), and of its row space.
struct NullSpace {
  Eigen::MatrixXd N;  // n × (n − rank)
  Eigen::MatrixXd Y;  // n × rank
};

NullSpace null_space(const Eigen::MatrixXd& M, Eigen::Index n) {
  NullSpace out;
  if (M.rows() == 0) {
    out.N = Eigen::MatrixXd::Identity(n, n);
    out.Y.resize(n, 0);
    return out;
  }
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(M.transpose());
  qr.setThreshold(1e-10);
  const Eigen::Index rank = qr.rank();
  const Eigen::MatrixXd Q = qr.householderQ();
  out.Y = Q.leftCols(rank);
  out.N = Q.rightCols(n - rank);
  return out;
}

// The same from sparse rows, block by block: rows only couple the parameters they mention
// (one axis of a few related elements), so the equality system splits into small independent
// blocks whose null spaces are computed separately — a 200-part model's 768 × 1500 system
// becomes dozens of blocks of tens of parameters.
NullSpace null_space(const SparseRows& A, Eigen::Index n) {
  std::vector<int> parent(static_cast<std::size_t>(n));
  std::iota(parent.begin(), parent.end(), 0);
  std::function<int(int)> root = [&](int x) {
    return parent[x] == x ? x : parent[x] = root(parent[x]);
  };
  std::vector<int> first_var(static_cast<std::size_t>(A.rows()), -1);
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    for (SparseRows::InnerIterator it(A, r); it; ++it) {
      if (it.value() == 0) continue;
      const int v = static_cast<int>(it.col());
      if (first_var[r] < 0) {
        first_var[r] = v;
      } else {
        parent[root(v)] = root(first_var[r]);
      }
    }
  }
  std::map<int, std::vector<int>> vars, rows;
  for (int v = 0; v < n; ++v) vars[root(v)].push_back(v);
  for (Eigen::Index r = 0; r < A.rows(); ++r) {
    if (first_var[r] >= 0) rows[root(first_var[r])].push_back(static_cast<int>(r));
  }
  std::vector<Eigen::VectorXd> n_cols, y_cols;
  for (const auto& [key, vs] : vars) {
    const auto rit = rows.find(key);
    if (rit == rows.end()) {
      for (int v : vs) {
        Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
        e[v] = 1;
        n_cols.push_back(std::move(e));
      }
      continue;
    }
    std::map<int, int> local;
    for (std::size_t i = 0; i < vs.size(); ++i) local[vs[i]] = static_cast<int>(i);
    Eigen::MatrixXd block = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(rit->second.size()),
                                                  static_cast<Eigen::Index>(vs.size()));
    for (std::size_t i = 0; i < rit->second.size(); ++i) {
      for (SparseRows::InnerIterator it(A, rit->second[i]); it; ++it) {
        block(static_cast<Eigen::Index>(i), local[static_cast<int>(it.col())]) += it.value();
      }
    }
    const NullSpace b = null_space(block, static_cast<Eigen::Index>(vs.size()));
    for (Eigen::Index c = 0; c < b.N.cols(); ++c) {
      Eigen::VectorXd col = Eigen::VectorXd::Zero(n);
      for (std::size_t i = 0; i < vs.size(); ++i) col[vs[i]] = b.N(static_cast<Eigen::Index>(i), c);
      n_cols.push_back(std::move(col));
    }
    for (Eigen::Index c = 0; c < b.Y.cols(); ++c) {
      Eigen::VectorXd col = Eigen::VectorXd::Zero(n);
      for (std::size_t i = 0; i < vs.size(); ++i) col[vs[i]] = b.Y(static_cast<Eigen::Index>(i), c);
      y_cols.push_back(std::move(col));
    }
  }
  NullSpace out;
  out.N.resize(n, static_cast<Eigen::Index>(n_cols.size()));
  for (std::size_t c = 0; c < n_cols.size(); ++c)
    out.N.col(static_cast<Eigen::Index>(c)) = n_cols[c];
  out.Y.resize(n, static_cast<Eigen::Index>(y_cols.size()));
  for (std::size_t c = 0; c < y_cols.size(); ++c)
    out.Y.col(static_cast<Eigen::Index>(c)) = y_cols[c];
  return out;
}

// A reduced QP in z (q = q0 + N z) with inequality rows Gz z ≤ slack, solved by adding
// violated rows to the solver's working set until none is violated (exact for a convex QP).
struct ReducedSolution {
  Eigen::VectorXd z;
  bool used_solver = false;
  bool converged = true;
  int iterations = 0;
  std::string message;
  std::vector<std::pair<Eigen::Index, double>> active;  // (row, multiplier)
};

ReducedSolution solve_reduced(const Eigen::MatrixXd& H,
                              const Eigen::LLT<Eigen::MatrixXd>& llt,
                              const Eigen::VectorXd& g,
                              const Eigen::MatrixXd& Gz,
                              const Eigen::VectorXd& slack,
                              double tol,
                              QpSolver solver,
                              std::optional<Clock::time_point> deadline) {
  ReducedSolution out;
  out.z = llt.solve(-g);
  if (Gz.rows() == 0) return out;
  const Eigen::Index r = Gz.cols();
  if (r == 0) {  // nothing can move: the rows hold or they do not
    if ((slack.array() < -tol).any()) {
      out.converged = false;
      out.message = "an inequality cannot hold with the equalities";
    }
    return out;
  }
  std::vector<Eigen::Index> working;
  std::vector<char> in_working(static_cast<std::size_t>(Gz.rows()), 0);
  // Rows that vanish in the reduced space only hold or fail; they never enter the solver
  // (a zero row with a slightly negative slack stalls SLSQP and Ipopt alike).
  const Eigen::VectorXd norms = Gz.rowwise().norm();
  for (Eigen::Index i = 0; i < Gz.rows(); ++i) {
    if (norms[i] > 1e-12) continue;
    in_working[i] = 1;
    if (slack[i] < -tol) {
      out.converged = false;
      out.message = "an inequality cannot hold with the equalities";
    }
  }
  // The reduced variables fall into groups H does not couple (parts of the model unrelated by
  // equalities and placement). Only the groups a working row touches go to the solver; the
  // others keep their unconstrained optimum. Exact: nothing else couples them.
  std::vector<int> group(static_cast<std::size_t>(r));
  std::iota(group.begin(), group.end(), 0);
  std::function<int(int)> find = [&](int x) {
    return group[x] == x ? x : group[x] = find(group[x]);
  };
  const double hscale = 1e-14 * (1.0 + H.cwiseAbs().maxCoeff());
  for (Eigen::Index i = 0; i < r; ++i) {
    for (Eigen::Index j = i + 1; j < r; ++j) {
      if (std::abs(H(i, j)) > hscale) group[find(static_cast<int>(i))] = find(static_cast<int>(j));
    }
  }
  std::vector<char> group_in(static_cast<std::size_t>(r), 0);
  Eigen::VectorXd z = out.z;
  std::vector<Eigen::Index> vars;  // the solver's variables, ascending
  for (int round = 0; round < 50; ++round) {
    const Eigen::VectorXd viol = Gz * z - slack;
    bool added = false;
    for (Eigen::Index i = 0; i < viol.size(); ++i) {
      // Violated rows only: tight rows that the step does not push stay out of the solver.
      if (viol[i] > tol && !in_working[i]) {
        in_working[i] = 1;
        working.push_back(i);
        added = true;
        for (Eigen::Index j = 0; j < r; ++j) {
          if (std::abs(Gz(i, j)) > 1e-14 * norms[i]) group_in[find(static_cast<int>(j))] = 1;
        }
      }
    }
    if (!added) break;
    vars.clear();
    for (Eigen::Index j = 0; j < r; ++j) {
      if (group_in[find(static_cast<int>(j))]) vars.push_back(j);
    }
    const Eigen::Index k = static_cast<Eigen::Index>(vars.size());
    Eigen::MatrixXd Hs(k, k);
    Eigen::VectorXd gs(k);
    for (Eigen::Index a = 0; a < k; ++a) {
      gs[a] = g[vars[a]];
      for (Eigen::Index b = 0; b < k; ++b) Hs(a, b) = H(vars[a], vars[b]);
    }
    const Eigen::LLT<Eigen::MatrixXd> lls(Hs);
    const auto L = lls.matrixL();
    // Rows on the chosen variables; the others stay at the unconstrained optimum.
    Eigen::VectorXd fixed_part = Gz * out.z;
    Eigen::MatrixXd Ct(k, static_cast<Eigen::Index>(working.size()));
    qp::Problem p;
    p.d.resize(static_cast<Eigen::Index>(working.size()));
    for (std::size_t j = 0; j < working.size(); ++j) {
      const Eigen::Index row = working[j];
      double inside = 0;
      for (Eigen::Index a = 0; a < k; ++a) {
        Ct(a, static_cast<Eigen::Index>(j)) = Gz(row, vars[a]) / norms[row];
        inside += Gz(row, vars[a]) * out.z[vars[a]];
      }
      // Unit rows: slack in mm along each constraint's normal, whatever its scale.
      p.d[static_cast<Eigen::Index>(j)] = (slack[row] - (fixed_part[row] - inside)) / norms[row];
    }
    // Equal rows (four legs tied to one length, each with its stock limit) go to the solver
    // once: repeated constraints break SLSQP's least-squares subproblem. Each working row maps
    // to its representative.
    std::vector<Eigen::Index> unique, representative(working.size());
    for (std::size_t j = 0; j < working.size(); ++j) {
      const Eigen::Index jj = static_cast<Eigen::Index>(j);
      Eigen::Index found = -1;
      for (std::size_t u = 0; u < unique.size() && found < 0; ++u) {
        const Eigen::Index q = unique[u];
        if (Ct.col(jj).dot(Ct.col(q)) > (1 - 1e-12) * Ct.col(jj).norm() * Ct.col(q).norm() &&
            std::abs(p.d[jj] - p.d[q]) <= 1e-9 * (1 + std::abs(p.d[q]))) {
          found = static_cast<Eigen::Index>(u);
        }
      }
      if (found < 0) {
        found = static_cast<Eigen::Index>(unique.size());
        unique.push_back(jj);
      }
      representative[j] = found;
    }
    Eigen::MatrixXd Cu(k, static_cast<Eigen::Index>(unique.size()));
    Eigen::VectorXd du(static_cast<Eigen::Index>(unique.size()));
    for (std::size_t u = 0; u < unique.size(); ++u) {
      Cu.col(static_cast<Eigen::Index>(u)) = Ct.col(unique[u]);
      du[static_cast<Eigen::Index>(u)] = p.d[unique[u]];
    }
    // The solver sees the problem in y = Lᵀz (H = L·Lᵀ): an identity Hessian, so SLSQP's
    // quasi-Newton model is exact from its first step and Ipopt's is trivially conditioned;
    // the rows and their multipliers are the same.
    p.H = Eigen::MatrixXd::Identity(k, k);
    p.g = L.solve(gs);
    const Eigen::VectorXd d_all = p.d;
    p.C = L.solve(Cu).transpose();
    p.d = du;
    p.start = Eigen::VectorXd::Zero(k);
    qp::Settings s;
    s.backend = solver == QpSolver::kIpopt ? qp::Backend::kIpopt : qp::Backend::kSlsqp;
    s.tolerance = 1e-10;
    if (deadline) {  // 0 would mean no limit: a deadline already past still stops it at once
      s.max_seconds =
          std::max(1e-6, std::chrono::duration<double>(*deadline - Clock::now()).count());
    }
    const qp::Result res = qp::solve(p, s);
    out.used_solver = true;
    out.iterations += res.iterations;
    if (!res.converged) {
      out.converged = false;
      out.message = res.message;
    }
    Eigen::VectorXd zs = lls.matrixU().solve(res.z);
    // Polish: the rows the solver left (nearly) tight, as equalities, solved exactly by the
    // range-space KKT equations; a row with a negative multiplier is released and the rest
    // solved again. Solvers stop within their tolerances; the polished point holds every row
    // to rounding. It is kept only if it is feasible.
    {
      p.d = d_all;
      std::vector<Eigen::Index> act;
      const Eigen::VectorXd vs = Ct.transpose() * zs - p.d;
      for (std::size_t j = 0; j < working.size(); ++j) {
        if (vs[static_cast<Eigen::Index>(j)] <= -1e-2) continue;
        bool duplicate = false;
        for (Eigen::Index q : act) {
          const double cosine = Ct.col(static_cast<Eigen::Index>(j)).dot(Ct.col(q));
          duplicate = duplicate || (cosine > 1 - 1e-12 &&
                                    std::abs(p.d[static_cast<Eigen::Index>(j)] - p.d[q]) < 1e-9);
        }
        if (!duplicate) act.push_back(static_cast<Eigen::Index>(j));
      }
      const Eigen::VectorXd Lg = L.solve(gs);
      for (int attempt = 0; attempt < 10 && !act.empty(); ++attempt) {
        const Eigen::Index m = static_cast<Eigen::Index>(act.size());
        Eigen::MatrixXd Ca(k, m);
        Eigen::VectorXd d(m);
        for (Eigen::Index j = 0; j < m; ++j) {
          Ca.col(j) = Ct.col(act[j]);
          d[j] = p.d[act[j]];
        }
        const Eigen::MatrixXd W = L.solve(Ca);  // L⁻¹Cᵀ
        const Eigen::VectorXd mu = (W.transpose() * W).ldlt().solve(-(d + W.transpose() * Lg));
        Eigen::Index worst = 0;
        if (mu.minCoeff(&worst) < -1e-9) {
          act.erase(act.begin() + worst);
          continue;
        }
        const Eigen::VectorXd zp = lls.matrixU().solve(-(Lg + W * mu));
        if (zp.allFinite() && ((Ct.transpose() * zp - p.d).array() <= tol).all()) zs = zp;
        break;
      }
    }
    z = out.z;
    for (Eigen::Index a = 0; a < k; ++a) z[vars[a]] = zs[a];
    out.active.clear();
    for (std::size_t j = 0; j < working.size(); ++j) {
      const Eigen::Index u = representative[j];
      if (res.multipliers.size() > u && res.multipliers[u] > 1e-9) {
        out.active.emplace_back(working[j], res.multipliers[u]);
      }
    }
  }
  out.z = z;
  return out;
}

std::string plane_word(int axis, Side side) {
  static constexpr std::string_view kMin[] = {"left side", "front", "bottom"};
  static constexpr std::string_view kMax[] = {"right side", "back", "top"};
  if (side == Side::kCenter) return fmt::format("centre ({})", axis_name(axis));
  return std::string(side == Side::kMin ? kMin[axis] : kMax[axis]);
}

std::string_view size_word(int axis) {
  static constexpr std::string_view kWords[] = {"width (x)", "depth (y)", "height (z)"};
  return kWords[axis];
}

}  // namespace

std::string_view to_string(ControlKind k) {
  return kControlNames[static_cast<int>(k)];
}

std::optional<ControlKind> control_from_string(std::string_view s) {
  for (int i = 0; i < 6; ++i) {
    if (kControlNames[i] == s) return static_cast<ControlKind>(i);
  }
  return std::nullopt;
}

std::string_view to_string(QpSolver s) {
  return s == QpSolver::kIpopt ? "ipopt" : "slsqp";
}

std::string describe_relation(const Template& t,
                              const Relation& r,
                              const Eigen::VectorXd& q,
                              const ItemCatalog* catalog,
                              NodeId moving) {
  auto name = [&](ElementId e) { return fmt::format("'{}'", t.element(e).name); };
  auto item_text = [&](const Element& el) {
    const Item* it = catalog ? catalog->find(el.item) : nullptr;
    return it ? fmt::format("{}, {}", el.item, it->name) : el.item;
  };
  auto plane_value = [&](const PlaneRef& p) {
    const Box b = t.box(p.element, q);
    return p.side == Side::kMin   ? b.min()[p.axis]
           : p.side == Side::kMax ? b.max()[p.axis]
                                  : b.center[p.axis];
  };
  auto pose = [&](const PlaneRef& p) { return p.pose.empty() ? std::string() : " with " + p.pose; };
  if (r.planes.empty()) return fmt::format("a {} relation", to_string(r.kind));
  const PlaneRef& p0 = r.planes[0];
  const Element& e0 = t.element(p0.element);
  switch (r.kind) {
    case RelationKind::kFixedSize: {
      const Item* it = catalog ? catalog->find(e0.item) : nullptr;
      static constexpr std::string_view kDim[] = {"length", "width", "thickness"};
      return fmt::format("{} has a fixed {} of {:g} mm along {} (item {}: its {} cannot be cut)",
                         name(p0.element),
                         size_word(p0.axis),
                         r.rhs,
                         axis_name(p0.axis),
                         it ? item_text(e0) : e0.item,
                         kDim[e0.item_dim[p0.axis]]);
    }
    case RelationKind::kMaxSize:
      return fmt::format("{} cannot be longer than {:g} mm along {}, the longest stock of item {}",
                         name(p0.element),
                         r.rhs,
                         axis_name(p0.axis),
                         item_text(e0));
    case RelationKind::kMinSize:
      return e0.pattern
                 ? fmt::format("{} cannot be shorter than one of its parts ({:g} mm along {})",
                               name(p0.element),
                               -r.rhs,
                               axis_name(p0.axis))
                 : fmt::format("{} cannot be thinner than {:g} mm along {}",
                               name(p0.element),
                               -r.rhs,
                               axis_name(p0.axis));
    case RelationKind::kOrder: {
      if (r.planes.size() < 2) break;
      const PlaneRef& lo = r.planes[0];  // lo's plane stays at or below hi's plane
      const PlaneRef& hi = r.planes[1];
      static constexpr std::string_view kBelow[] = {"further left", "further forward", "lower"};
      static constexpr std::string_view kAbove[] = {"further right", "further back", "higher"};
      const int k = lo.axis;
      // Speak of the element being moved when we know it.
      const bool moving_hi = moving.valid() && t.is_ancestor(moving, t.element(hi.element).node);
      const bool moving_lo = moving.valid() && t.is_ancestor(moving, t.element(lo.element).node);
      std::string fixed_note;
      for (const PlaneRef& p : {lo, hi}) {
        const Element& el = t.element(p.element);
        if (!el.resizable[k] && !el.item.empty()) {
          fixed_note = fmt::format("; {} is {:g} mm along {}, fixed by item {}",
                                   name(p.element),
                                   t.box(p.element, q).size[k],
                                   axis_name(k),
                                   item_text(el));
          break;
        }
      }
      if (moving_lo && !moving_hi) {
        return fmt::format("the {} of {}{} cannot be {} than the {} of {}{} ({:g} mm){}",
                           plane_word(k, lo.side),
                           name(lo.element),
                           pose(lo),
                           kAbove[k],
                           plane_word(k, hi.side),
                           name(hi.element),
                           pose(hi),
                           plane_value(hi),
                           fixed_note);
      }
      return fmt::format("the {} of {}{} cannot be {} than the {} of {}{} ({:g} mm){}",
                         plane_word(k, hi.side),
                         name(hi.element),
                         pose(hi),
                         kBelow[k],
                         plane_word(k, lo.side),
                         name(lo.element),
                         pose(lo),
                         plane_value(lo),
                         fixed_note);
    }
    case RelationKind::kCoplanar:
      if (r.planes.size() < 2) break;
      return fmt::format("the {} of {}{} stays level with the {} of {}{} (coplanar in the design)",
                         plane_word(p0.axis, p0.side),
                         name(p0.element),
                         pose(p0),
                         plane_word(r.planes[1].axis, r.planes[1].side),
                         name(r.planes[1].element),
                         pose(r.planes[1]));
    case RelationKind::kConcentric:
      if (r.planes.size() < 2) break;
      return fmt::format("{} and {} stay centred on each other along {}",
                         name(p0.element),
                         name(r.planes[1].element),
                         axis_name(p0.axis));
    case RelationKind::kSymmetric:
      if (r.planes.size() < 3) break;
      return fmt::format("{} and {} stay mirror images about the centre of {} along {}",
                         name(p0.element),
                         name(r.planes[1].element),
                         name(r.planes[2].element),
                         axis_name(p0.axis));
    case RelationKind::kPlacement:
      return fmt::format("{} keeps its place on its joint", name(p0.element));
  }
  return fmt::format("a {} relation of {}", to_string(r.kind), name(p0.element));
}

// ---- the manipulator ------------------------------------------------------------------------

struct Manipulator::Impl {
  Eigen::Index n = 0;
  std::vector<const Relation*> eq_rows, in_rows, soft_rows;
  std::vector<RelationId> in_ids;
  SparseRows A, G, S;
  Eigen::VectorXd b, h, s;
  Eigen::VectorXd principal;  // 1 for principal parameters, 0 for connecting ones

  struct Basis {
    Eigen::MatrixXd N;
    Eigen::MatrixXd GN;  // G·N
    Eigen::MatrixXd SN;  // S·N
    Eigen::MatrixXd PN;  // principal rows of N (zeroed elsewhere)
  };
  struct Session {
    std::shared_ptr<Basis> basis;
    Eigen::VectorXd u;  // Nᵀc
    Eigen::MatrixXd H;
    Eigen::LLT<Eigen::MatrixXd> llt;
  };
  mutable std::mutex mutex;
  mutable std::map<std::string, std::shared_ptr<Basis>> bases;
  mutable std::map<std::string, std::shared_ptr<Session>> sessions;

  // Anchor rows keeping the model in place (root centre x, y; root bottom z), except `free`.
  std::vector<std::vector<LinearTerm>> anchors(const Template& t, int free_axis) const {
    std::vector<std::vector<LinearTerm>> out;
    std::vector<ElementId> es;
    for (int i = 0; i < t.element_count(); ++i) {
      if (t.element(ElementId(i)).is_principal()) es.push_back(ElementId(i));
    }
    if (es.empty()) return out;
    for (int k = 0; k < 3; ++k) {
      if (k == free_axis) continue;
      ElementId lo = es[0], hi = es[0];
      for (ElementId e : es) {
        const Box b = t.box(e);
        if (b.min()[k] < t.box(lo).min()[k] - 1e-9) lo = e;
        if (b.max()[k] > t.box(hi).max()[k] + 1e-9) hi = e;
      }
      if (k < 2) {
        out.push_back({{center_index(lo, k), 0.5},
                       {size_index(lo, k), -0.25},
                       {center_index(hi, k), 0.5},
                       {size_index(hi, k), 0.25}});
      } else {
        out.push_back({{center_index(lo, k), 1.0}, {size_index(lo, k), -0.5}});
      }
    }
    return out;
  }

  static std::string key_of(const std::vector<std::vector<LinearTerm>>& rows) {
    std::string k;
    for (const auto& r : rows) {
      for (const LinearTerm& t : r) k += fmt::format("{}:{:g},", t.index, t.coefficient);
      k += ';';
    }
    return k;
  }

  std::shared_ptr<Basis> basis(const std::vector<std::vector<LinearTerm>>& extra) const {
    const std::string key = key_of(extra);
    if (auto it = bases.find(key); it != bases.end()) return it->second;
    std::vector<Eigen::Triplet<double>> trip;
    for (Eigen::Index r = 0; r < A.rows(); ++r) {
      for (SparseRows::InnerIterator it(A, r); it; ++it)
        trip.emplace_back(static_cast<int>(r), static_cast<int>(it.col()), it.value());
    }
    for (std::size_t i = 0; i < extra.size(); ++i) {
      for (const LinearTerm& t : extra[i])
        trip.emplace_back(
            static_cast<int>(A.rows() + static_cast<Eigen::Index>(i)), t.index, t.coefficient);
    }
    SparseRows M(A.rows() + static_cast<Eigen::Index>(extra.size()), n);
    M.setFromTriplets(trip.begin(), trip.end());
    auto bs = std::make_shared<Basis>();
    bs->N = null_space(M, n).N;
    bs->GN = G * bs->N;
    bs->SN = S * bs->N;
    bs->PN = principal.asDiagonal() * bs->N;
    if (bases.size() > 16) bases.clear();
    bases[key] = bs;
    return bs;
  }
};

Manipulator::Manipulator(const Template& t, ManipulateOptions options, const ItemCatalog* catalog)
    : template_(&t), options_(options), catalog_(catalog), impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.n = t.q.size();
  for (std::size_t i = 0; i < t.relations.size(); ++i) {
    const Relation& r = t.relations[i];
    if (r.soft) {
      m.soft_rows.push_back(&r);
    } else if (r.equality) {
      m.eq_rows.push_back(&r);
    } else {
      m.in_rows.push_back(&r);
      m.in_ids.push_back(RelationId(static_cast<int>(i)));
    }
  }
  m.A = to_sparse(m.eq_rows, m.n, m.b);
  m.G = to_sparse(m.in_rows, m.n, m.h);
  m.S = to_sparse(m.soft_rows, m.n, m.s);
  m.principal = Eigen::VectorXd::Zero(m.n);
  for (int e = 0; e < t.element_count(); ++e) {
    if (t.element(ElementId(e)).is_principal())
      m.principal.segment<kParamsPerElement>(e * kParamsPerElement).setOnes();
  }
}

Manipulator::~Manipulator() = default;
Manipulator::Manipulator(Manipulator&&) noexcept = default;
Manipulator& Manipulator::operator=(Manipulator&&) noexcept = default;

Control Manipulator::control(NodeId node, ControlKind kind) const {
  const Template& t = *template_;
  Control c;
  c.node = node;
  c.kind = kind;
  const int k = c.axis();
  std::vector<ElementId> es = t.elements_under(node);
  std::vector<ElementId> principal;
  for (ElementId e : es) {
    if (t.element(e).is_principal()) principal.push_back(e);
  }
  if (!principal.empty()) es = principal;
  if (es.empty()) return c;
  // The elements that bound the node's box along k decide cⱼ (paper §4.2).
  ElementId lo = es[0], hi = es[0];
  for (ElementId e : es) {
    if (t.box(e).min()[k] < t.box(lo).min()[k] - 1e-9) lo = e;
    if (t.box(e).max()[k] > t.box(hi).max()[k] + 1e-9) hi = e;
  }
  if (lo == hi && es.size() == 1) {
    c.c = {{c.is_size() ? size_index(lo, k) : center_index(lo, k), 1.0}};
  } else if (c.is_size()) {
    c.c = {{center_index(hi, k), 1.0},
           {size_index(hi, k), 0.5},
           {center_index(lo, k), -1.0},
           {size_index(lo, k), 0.5}};
  } else {
    c.c = {{center_index(hi, k), 0.5},
           {size_index(hi, k), 0.25},
           {center_index(lo, k), 0.5},
           {size_index(lo, k), -0.25}};
  }
  // Merge duplicate indices (lo == hi with several elements).
  std::map<int, double> merged;
  for (const LinearTerm& term : c.c) merged[term.index] += term.coefficient;
  c.c.clear();
  for (const auto& [i, v] : merged) {
    if (std::abs(v) > 1e-15) c.c.push_back({i, v});
  }
  c.value = dot(c.c, t.q);
  c.hidden = hidden(c);
  return c;
}

std::vector<Control> Manipulator::controls(NodeId node) const {
  std::vector<Control> out;
  for (int i = 0; i < 6; ++i) out.push_back(control(node, static_cast<ControlKind>(i)));
  return out;
}

bool Manipulator::hidden(const Control& c) const {
  if (c.c.empty()) return true;
  std::lock_guard lock(impl_->mutex);
  const int free_axis = !c.is_size() && c.node == template_->root() ? c.axis() : -1;
  const auto bs = impl_->basis(options_.anchor ? impl_->anchors(*template_, free_axis)
                                               : std::vector<std::vector<LinearTerm>>{});
  Eigen::VectorXd cv = Eigen::VectorXd::Zero(impl_->n);
  for (const LinearTerm& t : c.c) cv[t.index] += t.coefficient;
  return (bs->N.transpose() * cv).norm() <= 1e-9 * std::max(1.0, cv.norm());
}

namespace {

// Whether the control got where it was asked, and if not, what stopped it.
void explain(const Template& t,
             const ItemCatalog* catalog,
             const Control& c,
             double target,
             bool is_set,
             DragResult& out) {
  out.message.clear();
  if (is_set) {
    out.reached = std::abs(out.achieved - target) <= 0.01;
  } else {
    out.reached = !out.binding.has_value();
  }
  if (out.reached || out.diagnostics.has_errors()) return;
  if (out.binding) {
    const std::string why = describe_relation(t, t.relation(*out.binding), out.q, catalog, c.node);
    out.message = fmt::format("{} of '{}' stopped at {:g} mm (asked {:g} mm): {}",
                              to_string(c.kind),
                              t.node(c.node).name,
                              out.achieved,
                              target,
                              why);
  } else if (is_set) {
    out.message = fmt::format("{} of '{}' reached {:g} mm of {:g} mm: its other relations hold it",
                              to_string(c.kind),
                              t.node(c.node).name,
                              out.achieved,
                              target);
  }
  if (is_set && !out.message.empty()) out.diagnostics.warning(codes::kConstrained, out.message);
}

DragResult run_drag(const Template& t,
                    const Eigen::VectorXd& q_cur,
                    Manipulator::Impl& m,
                    const ManipulateOptions& o,
                    const ItemCatalog* catalog,
                    const Control& c,
                    double target,
                    double weight,
                    bool is_set) {
  const auto start = Clock::now();
  DragResult out;
  out.q = q_cur;
  out.requested = target;
  const double current = dot(c.c, q_cur);
  out.achieved = current;
  const int free_axis = !c.is_size() && c.node == t.root() ? c.axis() : -1;
  std::lock_guard lock(m.mutex);
  const auto anchors = o.anchor ? m.anchors(t, free_axis) : std::vector<std::vector<LinearTerm>>{};
  const std::string key = fmt::format("{}|{}|{}|{}",
                                      Manipulator::Impl::key_of(anchors),
                                      Manipulator::Impl::key_of({c.c}),
                                      weight,
                                      o.alpha);
  std::shared_ptr<Manipulator::Impl::Session> session;
  if (auto it = m.sessions.find(key); it != m.sessions.end()) {
    session = it->second;
  } else {
    session = std::make_shared<Manipulator::Impl::Session>();
    session->basis = m.basis(anchors);
    const Eigen::MatrixXd& N = session->basis->N;
    Eigen::VectorXd cv = Eigen::VectorXd::Zero(m.n);
    for (const LinearTerm& term : c.c) cv[term.index] += term.coefficient;
    session->u = N.transpose() * cv;
    const Eigen::Index r = N.cols();
    session->H = 2.0 * (weight * session->u * session->u.transpose() +
                        o.alpha * session->basis->PN.transpose() * session->basis->PN +
                        o.placement_weight * session->basis->SN.transpose() * session->basis->SN +
                        1e-9 * Eigen::MatrixXd::Identity(r, r));
    session->llt.compute(session->H);
    if (m.sessions.size() > 32) m.sessions.clear();
    m.sessions[key] = session;
  }
  const auto& bs = *session->basis;
  if (session->u.norm() <= 1e-9) {
    out.message = fmt::format("{} of '{}' is fixed by the template's constraints",
                              to_string(c.kind),
                              t.node(c.node).name);
    out.diagnostics.error(codes::kFixedControl, out.message);
    out.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    return out;
  }
  const double delta = target - current;
  const Eigen::VectorXd soft_residual = m.s - m.S * q_cur;
  const Eigen::VectorXd g =
      -2.0 * (weight * delta * session->u + o.placement_weight * bs.SN.transpose() * soft_residual);
  const Eigen::VectorXd slack = m.h - m.G * q_cur;
  const ReducedSolution sol = solve_reduced(
      session->H, session->llt, g, bs.GN, slack, o.tolerance_mm, o.solver, o.deadline);
  out.q = q_cur + bs.N * sol.z;
  out.used_solver = sol.used_solver;
  out.solver_iterations = sol.iterations;
  out.achieved = dot(c.c, out.q);
  out.max_violation = t.max_violation(out.q);
  if (!sol.converged || out.max_violation > 1e-6) {
    out.diagnostics.error(
        codes::kSolverFailed,
        fmt::format("the QP solver did not converge ({}); largest violation {:.3g} mm",
                    sol.message.empty() ? "no message" : sol.message,
                    out.max_violation));
    out.q = q_cur;
    out.achieved = current;
  }
  // The binding constraint: the active row with the largest multiplier, preferring rows about
  // the dragged node's own elements (equivalent rows bind together: four legs, one length).
  double best = 0;
  bool best_own = false;
  for (const auto& [row, mu] : sol.active) {
    const RelationId id = m.in_ids[static_cast<std::size_t>(row)];
    bool own = false;
    for (ElementId e : t.relation(id).elements) {
      own = own || t.is_ancestor(c.node, t.element(e).node);
    }
    // How much the row opposes this control: its multiplier times its alignment with cⱼ in
    // the reduced space (a tight row at right angles to the drag does not stop it).
    const double norm = bs.GN.row(row).norm() * session->u.norm();
    const double score = norm > 0 ? mu * std::abs(bs.GN.row(row).dot(session->u)) / norm : 0.0;
    if (score <= 1e-12) continue;
    if ((own && !best_own) || (own == best_own && score > best)) {
      best = score;
      best_own = own;
      out.binding = id;
    }
  }
  explain(t, catalog, c, target, is_set, out);
  out.milliseconds = std::chrono::duration<double, std::milli>(Clock::now() - start).count();
  return out;
}

}  // namespace

DragResult Manipulator::drag(const Control& c, double delta) const {
  const Template& t = *template_;
  return run_drag(t, t.q, *impl_, options_, catalog_, c, dot(c.c, t.q) + delta, 1.0, false);
}

DragResult Manipulator::set(const Control& c, double value) const {
  // A heavily weighted target, refined from each pass's result: the proximity term's pull
  // shrinks by α/weight per pass, so a feasible target is met to rounding in a few passes and
  // an infeasible one stops at the binding constraint.
  const Template& t = *template_;
  DragResult r = run_drag(t, t.q, *impl_, options_, catalog_, c, value, options_.set_weight, true);
  double ms = r.milliseconds;
  for (int pass = 0; pass < 6 && !r.diagnostics.has_errors(); ++pass) {
    if (std::abs(r.achieved - value) < 1e-9) break;
    DragResult next =
        run_drag(t, r.q, *impl_, options_, catalog_, c, value, options_.set_weight, true);
    if (next.diagnostics.has_errors()) break;
    ms += next.milliseconds;
    const bool stuck = std::abs(next.achieved - r.achieved) < 1e-9;  // a real bound
    if (!next.binding) next.binding = r.binding;
    const bool used = r.used_solver || next.used_solver;
    const int iterations = r.solver_iterations + next.solver_iterations;
    r = std::move(next);
    r.used_solver = used;
    r.solver_iterations = iterations;
    if (stuck) break;
  }
  r.milliseconds = ms;
  // Keep errors (solver failures); the warning is rewritten for the final pass.
  Diagnostics errors;
  for (const Diagnostic& d : r.diagnostics) {
    if (d.severity == Severity::kError) errors.add(d);
  }
  r.diagnostics = errors;
  explain(t, catalog_, c, value, true, r);
  return r;
}

ProjectResult project_to_feasible(const Template& t,
                                  const Eigen::VectorXd& q_ref,
                                  const Eigen::VectorXd& weights,
                                  const std::vector<Relation>& extra,
                                  const ManipulateOptions& o) {
  ProjectResult out;
  const Eigen::Index n = t.q.size();
  std::vector<const Relation*> eq, in, soft;
  for (const Relation& r : t.relations) (r.soft ? soft : r.equality ? eq : in).push_back(&r);
  for (const Relation& r : extra) (r.soft ? soft : r.equality ? eq : in).push_back(&r);
  Eigen::VectorXd b, h, s;
  const SparseRows A = to_sparse(eq, n, b);
  const SparseRows G = to_sparse(in, n, h);
  const SparseRows S = to_sparse(soft, n, s);
  const Eigen::MatrixXd Ad(A);
  const NullSpace ns = null_space(A, n);
  // The point of A q = b nearest q_ref (in the row space of A).
  Eigen::VectorXd q0 = q_ref;
  if (ns.Y.cols() > 0) {
    const Eigen::MatrixXd AY = Ad * ns.Y;
    const Eigen::VectorXd w = AY.colPivHouseholderQr().solve(b - Ad * q_ref);
    q0 = q_ref + ns.Y * w;
  }
  const double eq_violation = A.rows() ? (Ad * q0 - b).cwiseAbs().maxCoeff() : 0.0;
  const Eigen::MatrixXd& N = ns.N;
  const Eigen::MatrixXd SN = S * N;
  const Eigen::MatrixXd WN = weights.asDiagonal() * N;
  const Eigen::Index r = N.cols();
  Eigen::MatrixXd H = 2.0 * (N.transpose() * WN + o.placement_weight * SN.transpose() * SN +
                             1e-9 * Eigen::MatrixXd::Identity(r, r));
  const Eigen::VectorXd g = 2.0 * (WN.transpose() * (q0 - q_ref)) +
                            2.0 * o.placement_weight * SN.transpose() * (S * q0 - s);
  Eigen::LLT<Eigen::MatrixXd> llt(H);
  const Eigen::MatrixXd GN = G * N;
  const Eigen::VectorXd slack = h - G * q0;
  const ReducedSolution sol =
      solve_reduced(H, llt, g, GN, slack, o.tolerance_mm, o.solver, o.deadline);
  out.q = q0 + N * sol.z;
  double violation = eq_violation;
  if (G.rows()) violation = std::max(violation, (G * out.q - h).maxCoeff());
  out.violation = std::max(0.0, violation);
  out.feasible = out.violation <= 1e-6;
  out.cost = (weights.array() * (out.q - q_ref).array().square()).sum();
  return out;
}

}  // namespace fabkit::templates

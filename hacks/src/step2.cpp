#include <fmt/format.h>

#include <algorithm>

#include "steps.h"

namespace fabkit::hacks::detail {

std::string slip_message(const Assembly& a, int index, bool at_upper) {
  const ParamInfo& p = a.parameters()[static_cast<std::size_t>(index)];
  const Connection& c = a.connection(p.connection);
  const bool first = c.first.part == p.part && c.first.primitive == p.primitive &&
                     index < c.first.offset + static_cast<int>(c.first.params.size());
  const Connector& other = first ? c.second : c.first;
  const std::string owner = a.label(p.part, p.primitive);
  const std::string guest = a.label(other.part, other.primitive);
  const double bound = at_upper ? p.spec.hi : p.spec.lo;
  const Primitive& prim = a.node(p.part).part->primitive(p.primitive);
  if (prim.type == PrimitiveType::kHemisphere) {
    return fmt::format(
        "{} tips over on {} ({} = {:g}°)", a.label(p.part), owner, p.spec.name, bound);
  }
  if (p.spec.is_angle()) {
    return fmt::format("{} slides off the open end of {} (θ = {:g}°)", guest, owner, bound);
  }
  return fmt::format(
      "{} slides off the open end of {} ({} = {:g})", guest, owner, p.spec.name, bound);
}

namespace {

// Per part: whether p moves it (not an environment, and in p's group).
std::vector<bool> moving_parts(const Problem& p) {
  const Assembly& a = *p.assembly;
  std::vector<bool> moving(a.nodes().size(), false);
  for (std::size_t i = 0; i < moving.size(); ++i) {
    moving[i] = !a.nodes()[i].environment && (p.group < 0 || p.part_group[i] == p.group);
  }
  return moving;
}

}  // namespace

void watch_contacts(Problem& p, const std::vector<double>& x) {
  p.watched.clear();
  if (!p.contacts) return;
  p.watched =
      p.contacts->watched_pairs(p.assembly->part_frames(x), moving_parts(p), kContactWatchMm);
}

Overlap deepest_overlap(const Problem& p, const std::vector<double>& x) {
  Overlap out;
  if (!p.contacts) return out;
  std::vector<double> distances;
  const std::vector<PiecePair> near =
      p.contacts->watched_pairs(p.assembly->part_frames(x), moving_parts(p), 0.0, &distances);
  for (std::size_t k = 0; k < near.size(); ++k) {
    if (-distances[k] > out.depth) out = {-distances[k], near[k]};
  }
  return out;
}

bool watch_more_contacts(Problem& p, const std::vector<double>& x) {
  if (!p.contacts) return false;
  Problem after = p;
  watch_contacts(after, x);
  bool grown = false;
  for (const PiecePair& w : after.watched) {
    const bool known = std::find(p.watched.begin(), p.watched.end(), w) != p.watched.end();
    if (!known) {
      p.watched.push_back(w);
      grown = true;
    }
  }
  return grown;
}

StepResult run_step2(Problem& p,
                     const Variables& vars,
                     const std::vector<double>& x1,
                     const SolveOptions& o) {
  if (vars.index.empty() || p.total_mass <= 0) {
    StepResult out;
    out.x = x1;
    return out;
  }
  return avoiding_contacts(
      p,
      x1,
      [&](const Problem& q, const std::vector<double>& from) {
        AssemblySolver solver(q, vars, from, Objective::kEnergy, o.deadline);
        StepResult r = solver.relax(from, iterations_for(q, o));
        if (!r.closed && !q.watched.empty()) {
          // Parts that overlap too deeply for one projection are pulled apart first.
          std::vector<double> apart = from;
          if (solver.close(apart, 100)) r = solver.relax(apart, iterations_for(q, o));
        }
        return r;
      },
      o);
}

StabilityReport check_stability(const Problem& p,
                                const Variables& vars,
                                const std::vector<double>& x,
                                const SolveOptions& o) {
  if (vars.index.empty() || p.total_mass <= 0) return {};
  // The deadline bounds the second-order check too (a Hessian costs an evaluation per
  // variable); past it the curvature is not known and the solve reports a time-out.
  AssemblySolver assembly_solver(p, vars, x, Objective::kEnergy, o.deadline);
  solvers::ManifoldSolver& solver = assembly_solver.solver();
  using Point = solvers::ManifoldSolver::Point;
  using Active = solvers::ManifoldSolver::Active;
  using solvers::ManifoldSolver;
  const double fall_threshold = o.fall_threshold;
  const int n = static_cast<int>(vars.index.size());
  StabilityReport report;
  const Assembly& a = *p.assembly;
  const Point pt = solver.evaluate(scaled(vars, x));
  const Active act = solver.active_set(pt);
  if (act.Z.cols() > 0) {
    report.equilibrium_residual =
        (act.Z.transpose() * ManifoldSolver::rows(pt.g, act.free)).cwiseAbs().maxCoeff();
  }
  const std::vector<int> off = solver.off_bounds(pt);
  const Eigen::MatrixXd J_off = ManifoldSolver::columns(pt.J, off);
  for (int k = 0; k < n; ++k) {
    const int side = solver.at_bound(pt.z, k);
    if (side == 0) continue;
    const int index = vars.index[static_cast<std::size_t>(k)];
    const ParamSpec& spec = a.parameters()[static_cast<std::size_t>(index)].spec;
    if (!(side < 0 ? spec.open_at_lo : spec.open_at_hi)) continue;
    // Move k outwards by one unit; the coordinates off their bounds follow so the cycles
    // stay closed (minimum-norm correction). If they cannot, the move is blocked.
    double slope = side * pt.g[k];
    if (pt.J.rows() > 0) {
      const Eigen::VectorXd rhs = -side * pt.J.col(k);
      Eigen::VectorXd delta = Eigen::VectorXd::Zero(static_cast<int>(off.size()));
      if (!off.empty()) delta = J_off.completeOrthogonalDecomposition().solve(rhs);
      if ((J_off * delta - rhs).norm() > 1e-6 * std::max(1.0, rhs.norm())) continue;
      slope += ManifoldSolver::rows(pt.g, off).dot(delta);
    }
    if (slope < -fall_threshold) {
      Slip slip;
      slip.connection = a.parameters()[static_cast<std::size_t>(index)].connection;
      slip.parameter = index;
      slip.message = slip_message(a, index, side > 0);
      report.slips.push_back(slip);
    }
  }
  // Second order: the curvature along the allowed motions. Neutral directions are named by
  // the parameters they move most.
  const solvers::ManifoldSolver::Curvature curv = solver.curvature(pt);
  report.neutral_threshold = curv.neutral_threshold;
  if (curv.eigenvalues.size() > 0) report.smallest_curvature = curv.eigenvalues[0];
  for (int i = 0; i < curv.eigenvalues.size(); ++i) {
    if (std::abs(curv.eigenvalues[i]) > curv.neutral_threshold) continue;
    const Eigen::VectorXd d = curv.directions.col(i);
    const double largest = d.cwiseAbs().maxCoeff();
    NeutralDirection nd;
    std::vector<double> motion(a.values().size(), 0.0);
    for (int k = 0; k < n; ++k) {
      const int index = vars.index[static_cast<std::size_t>(k)];
      motion[static_cast<std::size_t>(index)] = d[k] * vars.scale[static_cast<std::size_t>(k)];
      if (std::abs(d[k]) < 0.3 * largest) continue;
      const ParamInfo& info = a.parameters()[static_cast<std::size_t>(index)];
      nd.parameters.push_back(
          fmt::format("{} {}", a.label(info.part, info.primitive), info.spec.name));
    }
    std::string list;
    for (const std::string& name : nd.parameters) list += (list.empty() ? "" : ", ") + name;
    nd.description = fmt::format("moves {} at no cost", list);
    report.neutral_directions.push_back(std::move(nd));
    report.neutral_motions.push_back(std::move(motion));
  }
  return report;
}

}  // namespace fabkit::hacks::detail

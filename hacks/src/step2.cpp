#include <fmt/format.h>

#include <algorithm>

#include "cycle_closure.h"
#include "hanging.h"
#include "random.h"
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

// The tree connections between two parts, at most `per_side` of them from each part up
// towards their common ancestor (or the environment), nearest the parts first.
std::vector<ConnectionId> joints_between(const Assembly& a, PartId u, PartId v, int per_side) {
  const KinematicGraph& g = a.graph();
  // Each part's tree edges up to its root (KinematicGraph::path_to_root without the root).
  auto up = [&](PartId p) {
    std::vector<ConnectionId> path;
    for (PartId q : g.path_to_root(p)) {
      if (!g.is_root(q)) path.push_back(g.parent_edge(q));
    }
    return path;
  };
  std::vector<ConnectionId> from_u = up(u);
  std::vector<ConnectionId> from_v = up(v);
  // Above the common ancestor both paths share their edges: they join nothing.
  while (!from_u.empty() && !from_v.empty() && from_u.back() == from_v.back()) {
    from_u.pop_back();
    from_v.pop_back();
  }
  std::vector<ConnectionId> out;
  for (const std::vector<ConnectionId>* path : {&from_u, &from_v}) {
    const std::size_t keep = std::min(path->size(), static_cast<std::size_t>(per_side));
    out.insert(out.end(), path->begin(), path->begin() + static_cast<std::ptrdiff_t>(keep));
  }
  return out;
}

// Unfolding (below): tries, the joints redrawn on each side of the overlapping pair, and the
// stream of keyed draws they use (apart from the closure's and step 1's starts).
constexpr int kUnfoldTries = 6;
// Tries in a row that leave the overlap as deep end the unfolding: a fold comes undone in
// one or two; parts that stay inside each other try after try are not folded (the reading
// nook's crossed chains, a caddy inside its seat back), and each try costs a relaxation.
constexpr int kUnfoldMisses = 3;
constexpr int kUnfoldJointsPerSide = 2;
// The keyed draws' stream. The second unfolding (environments too, after the contact rows)
// draws from the next kUnfoldTries streams: it starts from the same plain run, and with the
// same draws it repeated the first one's tries result for result (a 24-hook span, seed 1:
// 3.70 and 3.84 mm twice, then "passes through"; with its own draws it comes apart).
constexpr int kUnfoldStream = 1000;
// A try counts only if it leaves the parts this much less deep in each other (mm).
constexpr double kUnfoldGainMm = 0.05;

}  // namespace

void watch_contacts(Problem& p, const std::vector<double>& x, double* deepest) {
  p.watched.clear();
  if (deepest) *deepest = 0;
  if (!p.contacts) return;
  double depth = 0;
  p.watched = p.contacts->watched_pairs(
      p.assembly->part_frames(x), moving_parts(p), kContactWatchMm, depth);
  if (deepest) *deepest = depth;
}

Overlap deepest_overlap(const Problem& p, const std::vector<double>& x, bool parts_only) {
  Overlap out;
  if (!p.contacts) return out;
  std::vector<double> distances;
  const std::vector<PiecePair> near =
      p.contacts->watched_pairs(p.assembly->part_frames(x), moving_parts(p), 0.0, &distances);
  const Assembly& a = *p.assembly;
  for (std::size_t k = 0; k < near.size(); ++k) {
    if (parts_only && (a.node(PartId{near[k].part_a}).environment ||
                       a.node(PartId{near[k].part_b}).environment)) {
      continue;
    }
    if (-distances[k] > out.depth) out = {-distances[k], near[k]};
  }
  return out;
}

bool watch_more_contacts(Problem& p, const std::vector<double>& x, double* deepest) {
  if (deepest) *deepest = 0;
  if (!p.contacts) return false;
  Problem after = p;
  watch_contacts(after, x, deepest);
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

bool close_again(const Problem& p,
                 const Variables& vars,
                 std::vector<double>& x,
                 const SolveOptions& o) {
  AssemblySolver closer(p, vars, x, Objective::kEnergy, o.deadline);
  if (closer.close(x, 100)) return true;
  VerifyOptions closing;
  closing.restarts = 1;
  closing.stretch_start = false;
  closing.seed = o.seed;
  closing.deadline = o.deadline;
  const ClosureResult closed = close_cycles(*p.assembly, x, closing, p.group);
  if (!closed.closed) return false;
  std::vector<char> moves(x.size(), 0);
  for (int index : vars.index) moves[static_cast<std::size_t>(index)] = 1;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!moves[i] && closed.x[i] != x[i]) return false;
  }
  x = closed.x;
  return true;
}

std::vector<std::vector<int>> twin_groups(const Problem& p,
                                          const std::vector<int>& vars,
                                          const std::vector<double>& x) {
  return twin_groups(*p.assembly, *p.parameter_keys, vars, x);
}

std::vector<std::string> draw_keys(const Problem& p,
                                   const std::vector<int>& vars,
                                   const std::vector<double>& x) {
  const std::vector<std::string> all = twin_keys(*p.assembly, *p.parameter_keys, vars, x);
  std::vector<std::string> out;
  out.reserve(vars.size());
  for (int v : vars) out.push_back(all[static_cast<std::size_t>(v)]);
  return out;
}

void draw_keyed(const Problem& p,
                const std::vector<int>& vars,
                std::uint64_t seed,
                int stream,
                bool unbounded_only,
                std::vector<double>& x) {
  const Assembly& a = *p.assembly;
  const std::vector<std::string> keys = draw_keys(p, vars, x);
  for (std::size_t k = 0; k < vars.size(); ++k) {
    const ParamSpec& s = a.parameters()[static_cast<std::size_t>(vars[k])].spec;
    if (unbounded_only && s.tag != ParamTag::kUnbounded) continue;
    double& value = x[static_cast<std::size_t>(vars[k])];
    value = drawn_value(
        value, keyed_uniform(seed, stream, keys[k]), s.lo, s.hi, s.tag == ParamTag::kUnbounded);
  }
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
  auto run = [&](const Problem& q, const std::vector<double>& from) {
    AssemblySolver solver(q, vars, from, Objective::kEnergy, o.deadline);
    StepResult r = solver.relax(from, iterations_for(q, o));
    if (!r.closed && !q.watched.empty()) {
      // Parts that overlap too deeply for one projection are pulled apart first.
      std::vector<double> apart = from;
      if (solver.close(apart, 100)) r = solver.relax(apart, iterations_for(q, o));
    }
    // A relaxation with contact rows has fewer iterations (kContactIterations); one that used
    // them up still sloping goes on once from where it stopped.
    if (r.closed && !r.converged && !q.watched.empty() && !past_deadline(q, o)) {
      StepResult more = solver.relax(r.x, iterations_for(q, o));
      if (more.closed) {
        more.iterations += r.iterations;
        r = std::move(more);
      }
    }
    return r;
  };
  // A relaxation that ends with two parts deep inside each other has most often started from
  // a closure that folds a link back over its neighbour (a chain of S-hooks slack between two
  // hooks: the cycle search closes it anyhow, and the fold is a rest state of the joints
  // alone). No local step with contact rows undoes a fold — the parts would have to pass
  // through each other — so the joints next to the deepest overlap are redrawn (keyed
  // draws: the same design, the same tries), the cycles closed again from there and the plain
  // relaxation rerun; a try is kept when the overlap shrinks, and the next starts from it.
  std::vector<char> is_variable(p.assembly->values().size(), 0);
  for (int index : vars.index) is_variable[static_cast<std::size_t>(index)] = 1;
  auto unfold = [&](const Problem& q, const StepResult& plain, double depth, bool environment) {
    std::optional<std::pair<StepResult, double>> best;
    const Assembly& a = *q.assembly;
    const StepResult* current = &plain;
    int misses = 0;
    // Apart, and at rest: a try that comes apart without coming to rest is kept, but the
    // tries go on for one that does both.
    auto done = [&] { return depth <= kPenetrationToleranceMm && best && best->first.converged; };
    for (int attempt = 0; attempt < kUnfoldTries && misses < kUnfoldMisses && !done(); ++attempt) {
      if (past_deadline(q, o)) break;
      // Parts inside each other are unfolded first, and then only those pairs; a part in an
      // environment's way (a mug through the wall it hangs by) is what the contact rows are
      // for — it comes to rest against it, as built — and is unfolded only if they fail.
      const Overlap at = deepest_overlap(q, current->x, !environment);
      if (at.depth <= kPenetrationToleranceMm) break;
      // The variables of the joints next to the overlap, each side of each.
      std::vector<int> redraw;
      for (ConnectionId c : joints_between(
               a, PartId{at.pair.part_a}, PartId{at.pair.part_b}, kUnfoldJointsPerSide)) {
        const Connection& conn = a.connection(c);
        for (const Connector* side : {&conn.first, &conn.second}) {
          for (std::size_t i = 0; i < side->params.size(); ++i) {
            const int index = side->offset + static_cast<int>(i);
            if (is_variable[static_cast<std::size_t>(index)]) redraw.push_back(index);
          }
        }
      }
      if (redraw.empty()) break;
      std::vector<double> x = current->x;
      draw_keyed(q,
                 redraw,
                 o.seed,
                 kUnfoldStream + (environment ? kUnfoldTries : 0) + attempt,
                 /*unbounded_only=*/false,
                 x);
      if (q.unfold_tries) {
        if (*q.unfold_tries <= 0) break;
        --*q.unfold_tries;
      }
      ++misses;  // until the try is kept
      if (!close_again(q, vars, x, o)) continue;
      StepResult tried = run(q, x);
      // A long slack chain can use up a run's iterations short of rest (joints at their
      // bounds let go and caught again keep the steps short): a second run goes on from there.
      if (tried.closed && !tried.converged && !past_deadline(q, o)) {
        StepResult more = run(q, tried.x);
        if (more.closed) tried = std::move(more);
      }
      if (!tried.closed) continue;
      const double d = deepest_overlap(q, tried.x).depth;
      const bool rests_apart = d <= kPenetrationToleranceMm && tried.converged;
      if (d < depth - kUnfoldGainMm || (rests_apart && !done())) {
        best.emplace(std::move(tried), d);
        current = &best->first;
        depth = d;
        misses = 0;
      }
    }
    return best;
  };
  // A long chain hung link by link from the top is at rest, or nearly (a 64-hook chain's
  // relaxation from the connects' zigzag took 24 Newton models of 197 motions, from there 2) —
  // where no parts pass through each other or the environment there. Hanging ignores contact,
  // and a chain whose links it leaves interlocked through each other may not come apart (14
  // S-hooks hung alternately by either end: 3.5 mm, "passes through", where the relaxation
  // from the verified configuration, 5 mm deep, came apart and rests).
  std::vector<double> start = x1;
  if (static_cast<int>(vars.index.size()) >= kHangFrom) {
    if (std::optional<std::vector<double>> hung = hung_from_the_top(p, vars, x1)) {
      if (deepest_overlap(p, *hung).depth <= kPenetrationToleranceMm) start = std::move(*hung);
    }
  }
  return avoiding_contacts(p, start, run, o, unfold);
}

namespace {

// Whether x is where `relaxed` ended, up to whole turns of its unbounded angles (the verdict
// is asked of the wrapped angles).
bool same_configuration(const Assembly& a,
                        const Variables& vars,
                        const std::vector<double>& x,
                        const StepResult& relaxed) {
  for (int index : vars.index) {
    const auto i = static_cast<std::size_t>(index);
    const double difference = x[i] - relaxed.x[i];
    if (difference == 0) continue;
    if (a.parameters()[i].spec.tag != ParamTag::kUnbounded) return false;
    if (std::abs(std::remainder(difference, 360.0)) > 1e-9) return false;
  }
  return true;
}

}  // namespace

StabilityReport check_stability(const Problem& p,
                                const Variables& vars,
                                const std::vector<double>& x,
                                const SolveOptions& o,
                                const StepResult* relaxed) {
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
  if (act.motions() > 0) {
    report.equilibrium_residual =
        act.onto(ManifoldSolver::rows(pt.g, act.free)).cwiseAbs().maxCoeff();
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
  // The relaxation's last model is this curvature where it was made with the same free
  // coordinates and rows, and no inequality binding (contact rows are numbered by the pairs
  // each run watched, so only the equalities are the same rows by number).
  const ManifoldSolver::Curvature* known =
      relaxed && relaxed->curvature ? &*relaxed->curvature : nullptr;
  const bool lent = known && known->binding == 0 && pt.binding.empty() && known->free == act.free &&
                    known->rows == act.rows && same_configuration(a, vars, x, *relaxed);
  const ManifoldSolver::Curvature curv = lent ? *known : solver.curvature(pt);
  report.neutral_threshold = curv.neutral_threshold;
  if (curv.eigenvalues.size() > 0) report.smallest_curvature = curv.eigenvalues[0];
  for (int i = 0; i < curv.directions.cols(); ++i) {
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

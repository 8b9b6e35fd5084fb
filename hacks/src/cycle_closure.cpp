// The only translation unit that includes Ceres for verification.
#include "cycle_closure.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <set>

#include "constraints.h"
#include "fabkit/core/stop_clock.h"
#include "kinematics.h"
#include "random.h"

namespace fabkit::hacks::detail {
namespace {

struct Layout {
  /// Variables only the newest closure moves (not on the path of a closure made before):
  /// random starts explore these and keep the cycles already closed as they are.
  std::set<int> newest_only;
  std::vector<ConnectionId> closures;
  std::vector<std::optional<Vec3>> free_axes;
  std::vector<MultiConnectionPair> multi;
  std::vector<int> variables;  // indices into x that the search moves
};

// Parameters that can move a cycle: every connector on the root paths of both sides of
// each closing connection, plus the closing connection's own. With `group` ≥ 0, only the
// cycles of that movable group: the others hang from fixed parts on their own, and nothing
// done here can open or close them.
Layout make_layout(const Assembly& a, int group) {
  Layout layout;
  std::set<int> vars;
  const std::vector<int> groups = a.graph().movable_groups();
  auto in_group = [&](ConnectionId id) {
    if (group < 0) return true;
    const Connection& c = a.connection(id);
    return groups[c.first.part.index()] == group || groups[c.second.part.index()] == group;
  };
  auto add_connector = [&](const Connector& c) {
    for (std::size_t i = 0; i < c.params.size(); ++i) {
      if (!c.params[i].constant) vars.insert(c.offset + static_cast<int>(i));
    }
  };
  auto add_path = [&](PartId p) {
    while (a.parent(p).valid()) {
      const Connection& up = a.connection(a.parent(p));
      add_connector(up.first);
      add_connector(up.second);
      p = up.first.part;
    }
  };
  std::vector<ConnectionId> cycles;
  for (ConnectionId id : a.cycle_connections()) {
    if (in_group(id)) cycles.push_back(id);
  }
  std::set<int> earlier;
  for (std::size_t k = 0; k < cycles.size(); ++k) {
    const ConnectionId id = cycles[k];
    const Connection& c = a.connection(id);
    layout.closures.push_back(id);
    layout.free_axes.push_back(free_rotation_axis(a, id));
    if (k + 1 == cycles.size()) earlier = vars;
    add_connector(c.first);
    add_connector(c.second);
    add_path(c.first.part);
    add_path(c.second.part);
  }
  for (int v : vars) {
    if (!earlier.count(v)) layout.newest_only.insert(v);
  }
  for (const MultiConnectionPair& m : multi_connection_pairs(a)) {
    bool touches = false;
    for (int i : m.params_i) touches |= vars.count(i) > 0;
    for (int j : m.params_j) touches |= vars.count(j) > 0;
    if (touches) layout.multi.push_back(m);
  }
  layout.variables.assign(vars.begin(), vars.end());
  return layout;
}

struct ClosureCost {
  const Assembly* assembly;
  const Layout* layout;
  std::vector<double> base;  // full x; the variables are overwritten
  // Weight of the orientation residuals: a start first closes the gap in position with
  // orientation loosely held, then closes orientation fully (fewer local minima).
  double rotation_weight = 1.0;
  // Per closure, a position gap the residual leaves open (mm): the drag start closes a chain
  // by pulling its end to the anchor in small steps (drag_gap shrinking to 0).
  std::vector<Vec3> drag_gap;

  int residual_count() const {
    return static_cast<int>(layout->closures.size()) * kClosureResiduals +
           static_cast<int>(layout->multi.size());
  }

  template <class T>
  bool operator()(T const* const* params, T* residuals) const {
    std::vector<T> x(base.size());
    for (std::size_t i = 0; i < base.size(); ++i) x[i] = T(base[i]);
    for (std::size_t k = 0; k < layout->variables.size(); ++k) {
      x[static_cast<std::size_t>(layout->variables[k])] = params[0][k];
    }
    T* out = residuals;
    for (std::size_t c = 0; c < layout->closures.size(); ++c) {
      closure_residuals<T>(*assembly, layout->closures[c], layout->free_axes[c], x.data(), out);
      if (!drag_gap.empty()) {
        for (int i = 0; i < 3; ++i) out[i] -= T(drag_gap[c][i]);
      }
      if (rotation_weight != 1.0) {
        for (int i = 3; i < kClosureResiduals; ++i) out[i] *= T(rotation_weight);
      }
      out += kClosureResiduals;
    }
    for (const MultiConnectionPair& m : layout->multi) {
      const T f = multi_connection_value<T>(m, x.data());
      *out++ = f < T(0) ? f : T(0);
    }
    return true;
  }
};

// Orientation weight of a start's first phase, and the (weighted) cost above which the first
// phase counts as a miss and the start is abandoned. Chosen on the bundled gallery: the bird
// feeder needs 13 starts without phase 1, one with it.
constexpr double kPhaseOneRotationWeight = 0.01;
constexpr double kPhaseOneGiveUp = 25.0;  // mm², about a 5 mm gap

// A start that has not halved its cost in ten iterations while still open has stalled. The
// paper (§4.3.2) gives up below 10 % progress; Levenberg-Marquardt converges superlinearly on
// a closure it can reach, and a start crawling at 10–25 % per ten iterations is creeping
// along its bounds to a gap it will not close (the S-hook cycles' first start spent 200
// iterations so, two thirds of their verification; every gallery cycle closes with the same
// starts either way).
constexpr double kStallFactor = 0.5;
// Iterations of each small step of a drag, and of the stretching start's final fits.
constexpr int kDragStepIterations = 15;
constexpr int kStretchIterations = 1000;
// A cycle counts as closed at a search's start below these gaps (mm, degrees).
constexpr double kClosedAtStartMm = 0.01;
constexpr double kClosedAtStartDeg = 0.01;
// Tries of the stretching start (close_cycles), each nudged another way.
constexpr int kStretchTries = 4;

// Stops a start early: as soon as the cycle is closed, or when it stalls (kStallFactor).
class StallCallback : public ceres::IterationCallback {
 public:
  StallCallback(double tolerance, std::optional<std::chrono::steady_clock::time_point> deadline)
      : tolerance_(tolerance), deadline_(deadline) {}
  void reset() { history_.clear(); }
  /// Whether a stalled fit is stopped (a nearly taut chain converges slowly but surely).
  bool stop_stalled = true;
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    const double c = 2 * s.cost;  // Ceres reports ½‖r‖²
    if (c <= tolerance_) return ceres::SOLVER_TERMINATE_SUCCESSFULLY;
    // Checked per iteration: one start's fit of a long cycle takes tens of milliseconds.
    if (deadline_passed(deadline_)) return ceres::SOLVER_ABORT;
    history_.push_back(c);
    if (stop_stalled && history_.size() > 10 && c > kStallFactor * history_[history_.size() - 11]) {
      return ceres::SOLVER_ABORT;
    }
    return ceres::SOLVER_CONTINUE;
  }

 private:
  double tolerance_;
  std::optional<std::chrono::steady_clock::time_point> deadline_;
  std::vector<double> history_;
};

// ClosureCost's rows with their exact Jacobian from the kinematic tree's twists (as the
// solvers' AnalyticEvaluator): a parameter of a tree connection turns everything below it by
// a twist, a closure's own parameter moves only its connector frame. One pass in doubles
// instead of Ceres' dual numbers through every root path, ⌈variables / 4⌉ times: the search
// that verification and step 1's random starts run got 3-4× cheaper; the same derivatives
// (tested against automatic differentiation).
class AnalyticClosureCost : public ceres::CostFunction {
 public:
  explicit AnalyticClosureCost(const ClosureCost& cost) : cost_(cost) {
    const Assembly& a = *cost.assembly;
    moving_ = a.parts_moved_by(cost.layout->variables);
    fixed_frames_ = a.all_part_frames<double>(cost.base.data());
    const std::size_t parts = a.nodes().size();
    below_.assign(a.connections().size(), std::vector<char>(parts, 0));
    for (int q = 0; q < a.part_count(); ++q) {
      PartId id{q};
      while (a.parent(id).valid()) {
        below_[a.parent(id).index()][static_cast<std::size_t>(q)] = 1;
        id = a.connection(a.parent(id)).first.part;
      }
    }
    set_num_residuals(cost.residual_count());
    mutable_parameter_block_sizes()->push_back(static_cast<int>(cost.layout->variables.size()));
  }

  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    const Assembly& a = *cost_.assembly;
    const Layout& layout = *cost_.layout;
    std::vector<double> x = cost_.base;
    const std::size_t m = layout.variables.size();
    for (std::size_t k = 0; k < m; ++k) {
      x[static_cast<std::size_t>(layout.variables[k])] = parameters[0][k];
    }
    const std::vector<Rigid<double>> frames =
        a.all_part_frames<double>(x.data(), moving_, fixed_frames_);
    struct Closure {
      Rigid<double> f1, f2;
      int part1, part2;
    };
    std::vector<Closure> closures;
    double* out = residuals;
    for (std::size_t c = 0; c < layout.closures.size(); ++c) {
      const auto [f1, f2] = a.connection_frames<double>(layout.closures[c], frames, x.data());
      const Connection& conn = a.connection(layout.closures[c]);
      closures.push_back({f1, f2, conn.first.part.value, conn.second.part.value});
      for (int i = 0; i < 3; ++i) out[i] = f1.t[i] - f2.t[i];
      if (!cost_.drag_gap.empty()) {
        for (int i = 0; i < 3; ++i) out[i] -= cost_.drag_gap[c][i];
      }
      if (layout.free_axes[c]) {
        const Vec3 d = f1.R * *layout.free_axes[c] - f2.R * *layout.free_axes[c];
        for (int i = 0; i < 3; ++i) out[3 + i] = d[i] * kRadToDeg * cost_.rotation_weight;
        for (int i = 6; i < kClosureResiduals; ++i) out[i] = 0;
      } else {
        int k = 3;
        for (int col = 0; col < 3; ++col) {
          for (int row = 0; row < 3; ++row) {
            out[k++] =
                (f1.R(row, col) - f2.R(row, col)) * kRotationResidualScale * cost_.rotation_weight;
          }
        }
      }
      out += kClosureResiduals;
    }
    std::vector<double> spacing;
    for (const MultiConnectionPair& pair : layout.multi) {
      spacing.push_back(multi_connection_value<double>(pair, x.data()));
      *out++ = std::min(spacing.back(), 0.0);
    }
    if (!jacobians || !jacobians[0]) return true;

    const int rows = num_residuals();
    double* jac = jacobians[0];
    std::fill(jac, jac + static_cast<std::size_t>(rows) * m, 0.0);
    auto put = [&](int row, std::size_t k, double v) {
      jac[static_cast<std::size_t>(row) * m + k] = v;
    };
    // Local twists per connector side, computed once per side.
    std::vector<std::array<Vec3, 3>> w(2 * a.connections().size()), v(w.size());
    std::vector<char> ready(w.size(), 0);
    for (std::size_t k = 0; k < m; ++k) {
      const int index = layout.variables[k];
      const ParamInfo& info = a.parameters()[static_cast<std::size_t>(index)];
      const Connection& conn = a.connection(info.connection);
      const bool first = index >= conn.first.offset &&
                         index < conn.first.offset + static_cast<int>(conn.first.params.size());
      const Connector& side = first ? conn.first : conn.second;
      const std::size_t side_id = 2 * info.connection.index() + (first ? 0 : 1);
      const Primitive& prim = a.node(side.part).part->primitive(side.primitive);
      if (!ready[side_id]) {
        local_connector_twists(prim, x.data() + side.offset, w[side_id].data(), v[side_id].data());
        ready[side_id] = 1;
      }
      const auto local = static_cast<std::size_t>(index - side.offset);
      // The connector frame's world twist (the screw motion of a unit step of the parameter).
      const Rigid<double> frame = frames[side.part.index()].then(side.base);
      const Vec3 spatial_w = frame.R * w[side_id][local];
      const Vec3 spatial_v = frame.R * v[side_id][local] - spatial_w.cross(frame.t);
      // A tree connection's second side moves the child by the inverse motion.
      const double sign = conn.closes_cycle || first ? 1.0 : -1.0;
      int row = 0;
      for (std::size_t c = 0; c < closures.size(); ++c) {
        const Closure& cl = closures[c];
        bool moves1 = false;
        bool moves2 = false;
        if (conn.closes_cycle) {
          moves1 = layout.closures[c] == info.connection && first;
          moves2 = layout.closures[c] == info.connection && !first;
        } else {
          moves1 = below_[info.connection.index()][static_cast<std::size_t>(cl.part1)] != 0;
          moves2 = below_[info.connection.index()][static_cast<std::size_t>(cl.part2)] != 0;
        }
        const Vec3 w1 = moves1 ? Vec3(sign * spatial_w) : Vec3::Zero();
        const Vec3 w2 = moves2 ? Vec3(sign * spatial_w) : Vec3::Zero();
        const Vec3 dt1 =
            moves1 ? Vec3(sign * (spatial_w.cross(cl.f1.t) + spatial_v)) : Vec3::Zero();
        const Vec3 dt2 =
            moves2 ? Vec3(sign * (spatial_w.cross(cl.f2.t) + spatial_v)) : Vec3::Zero();
        const Vec3 dp = dt1 - dt2;
        for (int i = 0; i < 3; ++i) put(row + i, k, dp[i]);
        if (layout.free_axes[c]) {
          const Vec3& axis = *layout.free_axes[c];
          const Vec3 dd = w1.cross(cl.f1.R * axis) - w2.cross(cl.f2.R * axis);
          for (int i = 0; i < 3; ++i)
            put(row + 3 + i, k, dd[i] * kRadToDeg * cost_.rotation_weight);
        } else {
          auto skew = [](const Vec3& u) {
            Mat3 s;
            s << 0, -u.z(), u.y(), u.z(), 0, -u.x(), -u.y(), u.x(), 0;
            return s;
          };
          const Mat3 dr = skew(w1) * cl.f1.R - skew(w2) * cl.f2.R;
          int r = row + 3;
          for (int col = 0; col < 3; ++col) {
            for (int i = 0; i < 3; ++i) {
              put(r++, k, dr(i, col) * kRotationResidualScale * cost_.rotation_weight);
            }
          }
        }
        row += kClosureResiduals;
      }
      // Spacing rows min(f, 0) with f = Σ |x_j − x_i|·L − need: piecewise linear in x.
      for (std::size_t p = 0; p < layout.multi.size(); ++p) {
        if (spacing[p] >= 0) continue;
        const MultiConnectionPair& pair = layout.multi[p];
        double g = 0;
        for (std::size_t i = 0; i < pair.params_i.size(); ++i) {
          const double d = x[static_cast<std::size_t>(pair.params_j[i])] -
                           x[static_cast<std::size_t>(pair.params_i[i])];
          const double sgn = d >= 0 ? 1.0 : -1.0;
          if (index == pair.params_j[i]) g += sgn * pair.length[i];
          if (index == pair.params_i[i]) g -= sgn * pair.length[i];
        }
        put(static_cast<int>(closures.size()) * kClosureResiduals + static_cast<int>(p), k, g);
      }
    }
    return true;
  }

 private:
  const ClosureCost& cost_;
  std::vector<std::vector<char>> below_;  // [connection][part]: part hangs below it
  // Parts the variables move, and every part's frame at the cost's base (the others stay).
  std::vector<char> moving_;
  std::vector<Rigid<double>> fixed_frames_;
};

double cost_at(const ClosureCost& functor, const std::vector<double>& z) {
  std::vector<double> r(static_cast<std::size_t>(functor.residual_count()));
  const double* blocks[] = {z.data()};
  functor(blocks, r.data());
  double s = 0;
  for (double v : r) s += v * v;
  return s;
}

}  // namespace

std::vector<MultiConnectionPair> multi_connection_pairs(const Assembly& a) {
  std::vector<MultiConnectionPair> out;
  for (int p = 0; p < a.part_count(); ++p) {
    const Part& part = *a.node(PartId{p}).part;
    for (int index = 0; index < static_cast<int>(part.primitives.size()); ++index) {
      const PrimitiveId prim{index};
      const std::vector<ConnectionId> conns = a.connections_of(PartId{p}, prim);
      if (conns.size() < 2) continue;
      const Primitive& self = part.primitive(prim);
      const std::vector<double> length = self.critical_dim();
      struct Use {
        std::vector<int> params;
        std::vector<double> cd;
        PartId neighbour;
        PrimitiveId neighbour_prim;
      };
      std::vector<Use> uses;
      std::set<int> neighbours;
      for (ConnectionId id : conns) {
        const Connection& c = a.connection(id);
        const bool self_first = c.first.part.value == p && c.first.primitive == prim;
        const Connector& mine = self_first ? c.first : c.second;
        const Connector& other = self_first ? c.second : c.first;
        if (!neighbours.insert(other.part.value).second) continue;
        Use u;
        for (std::size_t i = 0; i < mine.params.size(); ++i) {
          if (mine.params[i].critical_dim) u.params.push_back(mine.offset + static_cast<int>(i));
        }
        const Primitive& op = a.node(other.part).part->primitive(other.primitive);
        u.cd = op.connector_critical_dim();
        u.neighbour = other.part;
        u.neighbour_prim = other.primitive;
        uses.push_back(u);
      }
      for (std::size_t i = 0; i < uses.size(); ++i) {
        for (std::size_t j = i + 1; j < uses.size(); ++j) {
          const Use& ui = uses[i];
          const Use& uj = uses[j];
          if (ui.params.empty() || ui.params.size() != uj.params.size() ||
              ui.params.size() != length.size() || ui.cd.size() < length.size() ||
              uj.cd.size() < length.size()) {
            continue;
          }
          MultiConnectionPair m;
          m.params_i = ui.params;
          m.params_j = uj.params;
          m.length = length;
          for (std::size_t k = 0; k < length.size(); ++k) m.need.push_back(ui.cd[k] + uj.cd[k]);
          m.description = fmt::format("{} and {} on {}",
                                      a.label(ui.neighbour, ui.neighbour_prim),
                                      a.label(uj.neighbour, uj.neighbour_prim),
                                      a.label(PartId{p}, prim));
          out.push_back(std::move(m));
        }
      }
    }
  }
  return out;
}

std::vector<ClosureGap> closure_gaps(const Assembly& assembly, const std::vector<double>& x) {
  std::vector<ClosureGap> out;
  for (ConnectionId id : assembly.cycle_connections()) {
    const auto [f1, f2] = assembly.connection_frames<double>(id, x.data());
    ClosureGap g;
    g.connection = id;
    g.position_mm = (f1.t - f2.t).norm();
    const std::optional<Vec3> axis = free_rotation_axis(assembly, id);
    if (axis) {
      const Vec3 u = f1.R * *axis;
      const Vec3 v = f2.R * *axis;
      g.rotation_deg = std::atan2(u.cross(v).norm(), u.dot(v)) * kRadToDeg;
    } else {
      const Mat3 rel = f1.R.transpose() * f2.R;
      g.rotation_deg = Eigen::AngleAxisd(rel).angle() * kRadToDeg;
    }
    out.push_back(g);
  }
  return out;
}

ClosureResult close_cycles(const Assembly& assembly,
                           const std::vector<double>& x0,
                           const VerifyOptions& options,
                           int group) {
  const Layout layout = make_layout(assembly, group);
  ClosureResult result;
  result.x = x0;
  const std::size_t m = layout.variables.size();
  auto* functor = new ClosureCost{&assembly, &layout, x0, 1.0, {}};
  result.cost = cost_at(*functor, [&] {
    std::vector<double> z;
    for (int v : layout.variables) z.push_back(x0[static_cast<std::size_t>(v)]);
    return z;
  }());
  if (m == 0 || functor->residual_count() == 0) {
    result.closed = result.cost <= options.tolerance;
    delete functor;
    return result;
  }

  // Problem owns the cost function; the functor (its rows, weights and drag gaps) is ours.
  const std::unique_ptr<ClosureCost> owned(functor);
  auto* cost = new AnalyticClosureCost(*functor);

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::DENSE_QR;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.function_tolerance = 1e-16;
  solver_options.gradient_tolerance = 1e-16;
  solver_options.parameter_tolerance = 1e-14;
  solver_options.num_threads = 1;
  solver_options.logging_type = ceres::SILENT;
  solver_options.minimizer_progress_to_stdout = false;
  StallCallback stall(options.tolerance, options.deadline);
  solver_options.callbacks.push_back(&stall);
  solver_options.update_state_every_iteration = true;

  std::vector<double> z(m);
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  problem.AddResidualBlock(cost, nullptr, z.data());
  for (std::size_t k = 0; k < m; ++k) {
    const ParamSpec& s = assembly.parameters()[static_cast<std::size_t>(layout.variables[k])].spec;
    if (s.tag == ParamTag::kUnbounded) continue;
    problem.SetParameterLowerBound(z.data(), static_cast<int>(k), s.lo);
    problem.SetParameterUpperBound(z.data(), static_cast<int>(k), s.hi);
  }

  double best = std::numeric_limits<double>::infinity();
  auto keep_if_best = [&] {
    const double c = cost_at(*functor, z);
    if (c < best) {
      best = c;
      result.cost = c;
      for (std::size_t k = 0; k < m; ++k) {
        result.x[static_cast<std::size_t>(layout.variables[k])] = z[k];
      }
    }
    return c <= options.tolerance;
  };
  auto solve = [&](double rotation_weight) {
    ceres::Solver::Summary summary;
    functor->rotation_weight = rotation_weight;
    stall.reset();
    ceres::Solve(solver_options, &problem, &summary);
    functor->rotation_weight = 1.0;
    return 2 * summary.final_cost;
  };
  // Phase 1 closes the gap in position with orientation held loosely; phase 2 closes all.
  auto two_phase = [&] {
    if (solve(kPhaseOneRotationWeight) < kPhaseOneGiveUp) solve(1.0);
    return keep_if_best();
  };
  int nudge = 0;  // which symmetry nudge start 0 gets (the stretching start's tries)
  const std::vector<std::string> keys = assembly.parameter_keys();
  auto load_start = [&](int start) {
    for (std::size_t k = 0; k < m; ++k) {
      const int v = layout.variables[k];
      const ParamSpec& s = assembly.parameters()[static_cast<std::size_t>(v)].spec;
      if (start == 0) {
        // The current configuration, kept inside its bounds: earlier cycles are closed there.
        double val =
            x0[static_cast<std::size_t>(v)] +
            symmetry_nudge(options.seed, keys[static_cast<std::size_t>(v)], s.hi - s.lo, nudge);
        if (s.tag != ParamTag::kUnbounded) val = std::clamp(val, s.lo, s.hi);
        z[k] = val;
      } else if (layout.newest_only.empty() || layout.newest_only.count(v) || start % 2 == 0) {
        // Odd starts explore only what the newest cycle adds, keeping the cycles closed
        // before as they are; even starts explore everything.
        z[k] = drawn_value(x0[static_cast<std::size_t>(v)],
                           keyed_uniform(options.seed, start, keys[static_cast<std::size_t>(v)]),
                           s.lo,
                           s.hi,
                           s.tag == ParamTag::kUnbounded);
      } else {
        double val = x0[static_cast<std::size_t>(v)];
        if (s.tag != ParamTag::kUnbounded) val = std::clamp(val, s.lo, s.hi);
        z[k] = val;
      }
    }
  };

  // Pulls each open end to its anchor in small steps of its position gap, along `path` (the
  // gaps to leave open on the way, the last one 0 for every closure), then closes fully.
  auto drag_along = [&](const std::vector<std::vector<Vec3>>& path) {
    const int saved = solver_options.max_num_iterations;
    solver_options.max_num_iterations = kDragStepIterations;
    std::vector<Vec3> from = path.front();
    for (std::size_t leg = 1; leg < path.size(); ++leg) {
      const std::vector<Vec3>& to = path[leg];
      // Steps of about 20 mm: each fit starts close to its answer.
      double longest = 0;
      for (std::size_t c = 0; c < to.size(); ++c)
        longest = std::max(longest, (to[c] - from[c]).norm());
      const int steps = std::clamp(static_cast<int>(std::ceil(longest / 20.0)), 8, 100);
      for (int step = 1; step <= steps; ++step) {
        const double s = static_cast<double>(step) / steps;
        functor->drag_gap.clear();
        for (std::size_t c = 0; c < to.size(); ++c)
          functor->drag_gap.push_back((1 - s) * from[c] + s * to[c]);
        // Orientation matters more as the end arrives: it is aligned by the time it is there.
        double left = 0, first = 0;
        for (std::size_t c = 0; c < to.size(); ++c) {
          left = std::max(left, functor->drag_gap[c].norm());
          first = std::max(first, path.front()[c].norm());
        }
        const double keep = first > 0 ? std::min(1.0, left / first) : 0.0;
        solve(kPhaseOneRotationWeight + (1 - kPhaseOneRotationWeight) * (1 - keep) * (1 - keep));
        if (deadline_passed(options.deadline)) break;
      }
      from = to;
    }
    functor->drag_gap.clear();
    solver_options.max_num_iterations = saved;
    solve(kPhaseOneRotationWeight);
    solve(1.0);
    return keep_if_best();
  };
  // The position gap of each closure at the current configuration; with `halfway`, also the
  // gap that leaves the chain's end halfway between its anchor and its root (the first
  // connection on its path up to a fixed part: the chain's other end).
  auto current_gaps = [&](std::vector<Vec3>* halfway) {
    load_start(0);
    std::vector<double> x(x0);
    for (std::size_t k = 0; k < m; ++k) x[static_cast<std::size_t>(layout.variables[k])] = z[k];
    std::vector<Vec3> gaps;
    for (ConnectionId id : layout.closures) {
      const auto [f1, f2] = assembly.connection_frames<double>(id, x.data());
      gaps.push_back(f1.t - f2.t);
      if (!halfway) continue;
      // The side that hangs from a root moves to the midpoint; the other is the anchor.
      const Connection& c = assembly.connection(id);
      auto root_of = [&](PartId p) -> std::optional<Vec3> {
        ConnectionId top;
        for (PartId q = p; assembly.parent(q).valid(); q = assembly.connection(top).first.part) {
          top = assembly.parent(q);
        }
        if (!top.valid()) return std::nullopt;
        return assembly.connection_frames<double>(top, x.data()).first.t;
      };
      if (const auto root = root_of(c.first.part)) {
        halfway->push_back(0.5 * (*root - f2.t));  // f1 at (root + f2) / 2
      } else if (const auto other = root_of(c.second.part)) {
        halfway->push_back(0.5 * (f1.t - *other));  // f2 at (root + f1) / 2
      } else {
        halfway->push_back(Vec3::Zero());
      }
    }
    return gaps;
  };
  // The drag start: from the current configuration, pull each open end to its anchor along a
  // straight line in small steps, as a person would pull a chain taut, then close fully. Long
  // chains whose random starts fold up close this way (a 16-hook span the random starts miss).
  auto drag = [&] {
    const std::vector<Vec3> gap0 = current_gaps(nullptr);
    return drag_along({gap0, std::vector<Vec3>(gap0.size(), Vec3::Zero())});
  };
  // The stretching start, for chains nearly taut between their ends: the end is first pulled
  // to halfway between the chain's root and its anchor, then out along that line, so that the
  // chain straightens towards the line between its two ends as the span grows.
  auto stretch = [&] {
    std::vector<Vec3> halfway;
    const std::vector<Vec3> gap0 = current_gaps(&halfway);
    // Near taut the closure is nearly singular: Levenberg-Marquardt creeps there, surely but
    // slowly, so this start is neither stopped when it stalls nor held to a start's iterations.
    stall.stop_stalled = false;
    const int saved = solver_options.max_num_iterations;
    solver_options.max_num_iterations = kStretchIterations;
    const bool closed = drag_along({gap0, halfway, std::vector<Vec3>(gap0.size(), Vec3::Zero())});
    solver_options.max_num_iterations = saved;
    stall.stop_stalled = true;
    return closed;
  };

  // The direct solve below is for a start where some of the cycles are closed already
  // (verification adds one cycle at a time; symmetry nudges leave them within 10⁻³ mm): it
  // keeps them so. A random draw that opened them all (step 1's random starts) goes straight to
  // the two-phase solve: the reading nook's, which all miss, spent 40 % of their closing in
  // direct solves (its solve stage 63 -> 50 ms).
  const bool some_closed = [&] {
    for (const ClosureGap& g : closure_gaps(assembly, x0)) {
      const bool ours = std::find(layout.closures.begin(), layout.closures.end(), g.connection) !=
                        layout.closures.end();
      if (ours && g.position_mm < kClosedAtStartMm && g.rotation_deg < kClosedAtStartDeg) {
        return true;
      }
    }
    return false;
  }();
  const int starts = std::max(1, options.restarts);
  for (int start = 0; start < starts; ++start) {
    if (deadline_passed(options.deadline)) break;
    result.starts = start + 1;
    if (start == 2 && drag()) break;
    load_start(start);
    if (start == 0 && layout.closures.size() > 1 && some_closed) {
      // From the current configuration a direct solve keeps the cycles closed earlier.
      solve(1.0);
      if (keep_if_best()) break;
      load_start(0);
    }
    if (two_phase()) break;
  }
  // The stretching start, not counted among the starts: it is the last resort of every
  // search, whatever its number of random starts. It is tried from the current configuration
  // nudged one way, then others: pulled out near taut, a chain passes configurations where a
  // millionth of a parameter's range decides which way it straightens, and only some ways
  // close: a 10-hook chain between rods 408 mm apart closed for 6 of 9 seeds from one end and
  // 6 of 9 from the other with one try, for 22 of 24 seed-end pairs with four (one that closes
  // ends the search; one that misses costs 0.02-0.2 s, which is why not more: eight made a
  // failing 10-hook search 1.7 s).
  for (int k = 0; k < kStretchTries && best > options.tolerance && options.stretch_start &&
                  !deadline_passed(options.deadline);
       ++k) {
    nudge = k;
    stretch();
  }
  result.closed = best <= options.tolerance;
  return result;
}

double closure_search_jacobian_mismatch(const Assembly& assembly,
                                        const std::vector<double>& x,
                                        double rotation_weight) {
  const Layout layout = make_layout(assembly, -1);
  if (layout.variables.empty()) return 0;
  ClosureCost functor{&assembly, &layout, x, rotation_weight, {}};
  const int rows = functor.residual_count();
  const auto m = static_cast<int>(layout.variables.size());
  std::vector<double> z;
  for (int v : layout.variables) z.push_back(x[static_cast<std::size_t>(v)]);
  const double* blocks[] = {z.data()};
  std::vector<double> r_exact(static_cast<std::size_t>(rows)), r_auto(r_exact.size());
  std::vector<double> j_exact(static_cast<std::size_t>(rows * m)), j_auto(j_exact.size());
  double* jac_exact[] = {j_exact.data()};
  double* jac_auto[] = {j_auto.data()};
  const AnalyticClosureCost exact(functor);
  exact.Evaluate(blocks, r_exact.data(), jac_exact);
  // Ceres' automatic differentiation of the same rows (what the search used before).
  auto* copy = new ClosureCost(functor);
  ceres::DynamicAutoDiffCostFunction<ClosureCost, 4> automatic(copy);
  automatic.AddParameterBlock(m);
  automatic.SetNumResiduals(rows);
  automatic.Evaluate(blocks, r_auto.data(), jac_auto);
  double largest = 1e-12;
  double worst = 0;
  for (std::size_t i = 0; i < r_exact.size(); ++i)
    worst = std::max(worst, std::abs(r_exact[i] - r_auto[i]));
  for (std::size_t i = 0; i < j_exact.size(); ++i) {
    largest = std::max(largest, std::abs(j_auto[i]));
    worst = std::max(worst, std::abs(j_exact[i] - j_auto[i]));
  }
  return worst / largest;
}

std::vector<std::vector<int>> twin_groups(const Assembly& a,
                                          const std::vector<std::string>& keys,
                                          const std::vector<int>& vars,
                                          const std::vector<double>& x) {
  std::map<std::string, std::vector<int>> by_key;
  for (int v : vars) by_key[keys[static_cast<std::size_t>(v)]].push_back(v);
  // Where each twin is: its value, then where its connection is in the world. A name or a
  // connect's place in the file could tell them apart too, but then renaming the parts or
  // building in another order would hand the draws round differently.
  auto where = [&](int v) {
    const ParamInfo& info = a.parameters()[static_cast<std::size_t>(v)];
    const Vec3 at = a.connection_frames<double>(info.connection, x.data()).first.t;
    return std::array<double, 4>{x[static_cast<std::size_t>(v)], at.x(), at.y(), at.z()};
  };
  std::vector<std::vector<int>> out;
  for (const auto& [key, group] : by_key) {
    if (group.size() < 2) continue;
    std::vector<std::pair<std::array<double, 4>, int>> ranked;
    for (int v : group) ranked.emplace_back(where(v), v);
    std::stable_sort(ranked.begin(), ranked.end(), [](const auto& l, const auto& r) {
      return l.first < r.first;
    });
    std::vector<int>& ordered = out.emplace_back();
    for (const auto& [at, v] : ranked) ordered.push_back(v);
  }
  return out;
}

std::vector<std::string> twin_keys(const Assembly& a,
                                   const std::vector<std::string>& keys,
                                   const std::vector<int>& vars,
                                   const std::vector<double>& x) {
  std::vector<std::string> out = keys;
  for (const std::vector<int>& twins : twin_groups(a, keys, vars, x)) {
    for (std::size_t r = 1; r < twins.size(); ++r) {
      std::string& key = out[static_cast<std::size_t>(twins[r])];
      key = fmt::format("{}#twin{}", key, r);
    }
  }
  return out;
}

}  // namespace fabkit::hacks::detail

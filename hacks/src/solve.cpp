// The two-step solve of paper §4.3.3. Step 1 is bounded nonlinear least squares (Ceres,
// automatic derivatives, seeded multi-start); step 2 minimises the gravitational potential
// subject to the cycle closures with a reduced-space Newton method on gradients from the same
// automatic differentiation; then the falls-apart verdict. Ceres stays inside this file.
#include "fabkit/hacks/solve.h"

#include <ceres/ceres.h>
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <set>

#include "constraints.h"
#include "cycle_closure.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "random.h"
#include "solve_internal.h"

namespace fabkit::hacks {
namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

inline double value_of(double v) {
  return v;
}
template <class T, int N>
double value_of(const ceres::Jet<T, N>& j) {
  return j.a;
}

// ---- the target ---------------------------------------------------------------------------

// Symmetries of a primitive as a target, in its own frame: a free axis (a rod spins about its
// axis, a ring about its own) and a half-turn that maps it onto itself (a rod end for end).
struct TargetSymmetry {
  std::optional<Vec3> free_axis;
  std::optional<Vec3> half_turn_axis;
};

TargetSymmetry target_symmetry(PrimitiveType t) {
  switch (t) {
    case PrimitiveType::kRod:
    case PrimitiveType::kTube:
      return {Vec3::UnitZ(), Vec3::UnitX()};
    case PrimitiveType::kRing:
      return {Vec3::UnitX(), Vec3::UnitY()};
    case PrimitiveType::kHemisphere:
      return {Vec3::UnitZ(), std::nullopt};
    case PrimitiveType::kClip:
    case PrimitiveType::kSurface:
      return {std::nullopt, Vec3::UnitZ()};
    case PrimitiveType::kEdge:
      return {std::nullopt, Vec3::UnitY()};
    case PrimitiveType::kHook:
      return {};
  }
  return {};
}

struct TargetModel {
  PartId part;
  Rigid<double> base;         // target primitive in its part
  Rigid<double> goal;         // where it should be
  Rigid<double> goal_turned;  // goal turned by the half-turn symmetry (if any)
  TargetSymmetry symmetry;
};

std::optional<TargetModel> make_target(const Assembly& a) {
  if (!a.target()) return std::nullopt;
  const std::optional<PartId> id = a.find(a.target()->part.get());
  if (!id) return std::nullopt;
  TargetModel t;
  t.part = *id;
  const Primitive& p =
      a.target()->part->primitives[static_cast<std::size_t>(a.target()->primitive)];
  t.base = Rigid<double>::from_matrix(p.frame.matrix());
  t.goal = Rigid<double>::from_matrix(a.target()->frame.matrix());
  t.symmetry = target_symmetry(p.type);
  t.goal_turned = t.goal;
  if (t.symmetry.half_turn_axis) {
    t.goal_turned.R = t.goal.R * Eigen::AngleAxisd(std::numbers::pi, *t.symmetry.half_turn_axis);
  }
  return t;
}

constexpr int kTargetResiduals = 12;

// Position gap (mm) and orientation gap (≈ degrees) of the target, modulo its symmetries.
template <class T>
void target_residuals(const TargetModel& t, const Rigid<T>& part_frame, T* out) {
  const Rigid<T> actual = part_frame.then(t.base);
  for (int i = 0; i < 3; ++i) out[i] = actual.t[i] - T(t.goal.t[i]);
  for (int i = 3; i < kTargetResiduals; ++i) out[i] = T(0);
  if (t.symmetry.free_axis) {
    const Vec3T<T> u = actual.R * t.symmetry.free_axis->cast<T>();
    Vec3 g = t.goal.R * *t.symmetry.free_axis;
    if (t.symmetry.half_turn_axis) {
      // An axis symmetric end for end matches either direction: take the nearer.
      double d = 0;
      for (int i = 0; i < 3; ++i) d += value_of(u[i]) * g[i];
      if (d < 0) g = -g;
    }
    for (int i = 0; i < 3; ++i) out[3 + i] = (u[i] - T(g[i])) * T(kRadToDeg);
    return;
  }
  const Rigid<double>* goal = &t.goal;
  if (t.symmetry.half_turn_axis) {
    double d0 = 0;
    double d1 = 0;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) {
        d0 += std::pow(value_of(actual.R(r, c)) - t.goal.R(r, c), 2);
        d1 += std::pow(value_of(actual.R(r, c)) - t.goal_turned.R(r, c), 2);
      }
    }
    if (d1 < d0) goal = &t.goal_turned;
  }
  int k = 3;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) {
      out[k++] = (actual.R(r, c) - T(goal->R(r, c))) * T(detail::kRotationResidualScale);
    }
  }
}

PoseError pose_error(const TargetModel& t, const Rigid<double>& part_frame) {
  const Rigid<double> actual = part_frame.then(t.base);
  PoseError e;
  e.position_mm = (actual.t - t.goal.t).norm();
  auto angle_between = [](const Vec3& u, const Vec3& v) {
    return std::atan2(u.cross(v).norm(), u.dot(v)) * kRadToDeg;
  };
  if (t.symmetry.free_axis) {
    const Vec3 u = actual.R * *t.symmetry.free_axis;
    const Vec3 g = t.goal.R * *t.symmetry.free_axis;
    e.rotation_deg = angle_between(u, g);
    if (t.symmetry.half_turn_axis) e.rotation_deg = std::min(e.rotation_deg, angle_between(u, -g));
    return e;
  }
  auto geodesic = [&](const Mat3& goal) {
    return Eigen::AngleAxisd(Mat3(goal.transpose() * actual.R)).angle() * kRadToDeg;
  };
  e.rotation_deg = geodesic(t.goal.R);
  if (t.symmetry.half_turn_axis)
    e.rotation_deg = std::min(e.rotation_deg, geodesic(t.goal_turned.R));
  return e;
}

// ---- shared layout ------------------------------------------------------------------------

struct Problem {
  const Assembly* assembly;
  std::optional<TargetModel> target;
  std::vector<ConnectionId> closures;
  std::vector<std::optional<Vec3>> free_axes;
  std::vector<detail::MultiConnectionPair> multi;
  std::vector<double> masses;  // per part; 0 for environments
  std::vector<Vec3> coms;      // per part, in part coordinates
  double total_mass = 0;
};

Problem make_problem(const Assembly& a) {
  Problem p;
  p.assembly = &a;
  p.target = make_target(a);
  p.closures = a.cycle_connections();
  for (ConnectionId c : p.closures) p.free_axes.push_back(detail::free_rotation_axis(a, c));
  p.multi = detail::multi_connection_pairs(a);
  for (const PartNode& n : a.nodes()) {
    const double m = n.environment ? 0.0 : std::max(0.0, n.part->mass);
    p.masses.push_back(m);
    p.coms.push_back(n.part->center_of_mass);
    p.total_mass += m;
  }
  return p;
}

// Maps the optimiser's variables into the full parameter vector.
struct Variables {
  std::vector<int> index;     // into x
  std::vector<double> scale;  // x = z * scale (z in ≈ mm of motion)
};

Variables select_variables(const Assembly& a, bool physics) {
  Variables v;
  for (int i = 0; i < a.parameter_count(); ++i) {
    const ParamInfo& p = a.parameters()[static_cast<std::size_t>(i)];
    if (p.spec.constant) continue;
    if (physics && p.spec.fixed_under_physics) continue;
    v.index.push_back(i);
    double scale = 1.0;
    if (!p.spec.is_angle()) {
      const Primitive& prim =
          a.node(p.part).part->primitives[static_cast<std::size_t>(p.primitive)];
      const std::vector<double> cd = prim.critical_dim();
      double length = cd.empty() ? 100.0 : cd[0];
      if (p.spec.name == "t" && prim.type == PrimitiveType::kClip) length = prim.shape.height;
      if (p.spec.name == "t2" && cd.size() > 1) length = cd[1];
      scale = 1.0 / std::max(length, 1.0);
    }
    v.scale.push_back(scale);
  }
  return v;
}

template <class T>
std::vector<T> expand(const Variables& v, const std::vector<double>& base, const T* z) {
  std::vector<T> x(base.size());
  for (std::size_t i = 0; i < base.size(); ++i) x[i] = T(base[i]);
  for (std::size_t k = 0; k < v.index.size(); ++k) {
    x[static_cast<std::size_t>(v.index[k])] = z[k] * T(v.scale[k]);
  }
  return x;
}

std::vector<double> to_z(const Variables& v, const std::vector<double>& x) {
  std::vector<double> z;
  for (std::size_t k = 0; k < v.index.size(); ++k) {
    z.push_back(x[static_cast<std::size_t>(v.index[k])] / v.scale[k]);
  }
  return z;
}

void from_z(const Variables& v, const std::vector<double>& z, std::vector<double>& x) {
  for (std::size_t k = 0; k < v.index.size(); ++k) {
    x[static_cast<std::size_t>(v.index[k])] = z[k] * v.scale[k];
  }
}

double max_gap(const Assembly& a, const std::vector<double>& x, double* deg = nullptr) {
  double mm = 0;
  double angle = 0;
  for (const detail::ClosureGap& g : detail::closure_gaps(a, x)) {
    mm = std::max(mm, g.position_mm);
    angle = std::max(angle, g.rotation_deg);
  }
  if (deg) *deg = angle;
  return mm;
}

// ---- the functions both steps work with ---------------------------------------------------

enum class Objective {
  kTarget,  ///< step 1: the target's pose residuals (least squares)
  kEnergy,  ///< step 2: the mean height of the centres of mass (mm)
};

// [objective rows..., closure equalities..., multi-connection inequalities (≤ 0)...],
// differentiated automatically.
struct ManifoldCost {
  const Problem* problem;
  const Variables* vars;
  std::vector<double> base;
  Objective objective;

  int objective_count() const { return objective == Objective::kTarget ? kTargetResiduals : 1; }
  int equality_count() const {
    int n = 0;
    for (const auto& axis : problem->free_axes) n += axis ? 5 : 6;
    return n;
  }
  int residual_count() const {
    return objective_count() + equality_count() + static_cast<int>(problem->multi.size());
  }

  template <class T>
  bool operator()(T const* const* params, T* out) const {
    const std::vector<T> x = expand<T>(*vars, base, params[0]);
    const Assembly& a = *problem->assembly;
    const std::vector<Rigid<T>> frames = a.all_part_frames<T>(x.data());
    if (objective == Objective::kTarget) {
      target_residuals<T>(
          *problem->target, frames[static_cast<std::size_t>(problem->target->part.value)], out);
    } else {
      T energy(0);
      for (std::size_t i = 0; i < frames.size(); ++i) {
        if (problem->masses[i] == 0) continue;
        const Vec3T<T> com = frames[i].R * problem->coms[i].cast<T>() + frames[i].t;
        energy += com[2] * T(problem->masses[i] / problem->total_mass);
      }
      out[0] = energy;
    }
    T* eq = out + objective_count();
    for (std::size_t c = 0; c < problem->closures.size(); ++c) {
      const auto [f1, f2] = a.connection_frames<T>(problem->closures[c], frames, x.data());
      for (int i = 0; i < 3; ++i) *eq++ = f1.t[i] - f2.t[i];
      // Minimal orientation residuals (≈ degrees), in the first connector's frame. They vanish
      // at a half turn too; configurations closed from far away are checked for that.
      const Mat3T<T> rel = f1.R.transpose() * f2.R;
      if (problem->free_axes[c]) {
        // Only the free axis has to line up: two components across it.
        const Vec3 axis = *problem->free_axes[c];
        const Vec3 b = axis.unitOrthogonal();
        const Vec3 d = axis.cross(b);
        const Vec3T<T> turned = rel * axis.cast<T>();
        *eq++ = turned.dot(b.cast<T>()) * T(kRadToDeg);
        *eq++ = turned.dot(d.cast<T>()) * T(kRadToDeg);
      } else {
        *eq++ = (rel(2, 1) - rel(1, 2)) * T(0.5 * kRadToDeg);
        *eq++ = (rel(0, 2) - rel(2, 0)) * T(0.5 * kRadToDeg);
        *eq++ = (rel(1, 0) - rel(0, 1)) * T(0.5 * kRadToDeg);
      }
    }
    for (const detail::MultiConnectionPair& m : problem->multi) {
      *eq++ = -detail::multi_connection_value<T>(m, x.data());
    }
    return true;
  }
};

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

// Values and exact Jacobian of ManifoldCost from the kinematic tree's structure: a parameter
// of a tree connection turns the whole subtree below it by a twist (screw motion) computed
// from its connector's local derivative; every row's derivative follows from the twists of
// the frames it reads. One pass over the parameters instead of automatic differentiation
// through every frame: the same numbers (checked against ManifoldEvaluator in the tests) at a
// fraction of the cost on long chains.
class AnalyticEvaluator {
 public:
  AnalyticEvaluator(const Problem& p, const Variables& v, std::vector<double> base, Objective o)
      : problem_(p),
        vars_(v),
        base_(std::move(base)),
        objective_(o),
        cost_{&p, &v, base_, o},
        n_(static_cast<int>(v.index.size())) {
    const Assembly& a = *p.assembly;
    rows_ = cost_.residual_count();
    // Parts below each tree connection (the child and its descendants).
    below_.resize(a.connections().size());
    for (int q = 0; q < a.part_count(); ++q) {
      PartId id{q};
      while (a.node(id).parent.valid()) {
        below_[static_cast<std::size_t>(a.node(id).parent.value)].push_back(q);
        id = a.connection(a.node(id).parent).first.part;
      }
    }
    // Which connector side and slot each variable belongs to.
    for (int k = 0; k < n_; ++k) {
      const int index = v.index[static_cast<std::size_t>(k)];
      const ParamInfo& info = a.parameters()[static_cast<std::size_t>(index)];
      const Connection& c = a.connection(info.connection);
      Slot slot;
      slot.connection = info.connection.value;
      slot.first = index < c.first.offset + static_cast<int>(c.first.params.size()) &&
                   index >= c.first.offset;
      const Connector& side = slot.first ? c.first : c.second;
      slot.offset = side.offset;
      slot.local = index - side.offset;
      slot.scale = v.scale[static_cast<std::size_t>(k)];
      slots_.push_back(slot);
    }
  }

  void evaluate(const double* z) {
    if (!values_.empty() && std::equal(z, z + n_, last_.begin())) return;
    last_.assign(z, z + n_);
    const Assembly& a = *problem_.assembly;
    const std::vector<double> x = expand<double>(vars_, base_, z);
    values_.assign(static_cast<std::size_t>(rows_), 0.0);
    jacobian_.assign(static_cast<std::size_t>(rows_ * n_), 0.0);
    const double* blocks[] = {z};
    cost_(blocks, values_.data());
    const std::vector<Rigid<double>> frames = a.all_part_frames<double>(x.data());

    // Closure frames, once.
    struct ClosureFrames {
      Rigid<double> f1, f2;
      int part1, part2;
    };
    std::vector<ClosureFrames> cf;
    for (ConnectionId c : problem_.closures) {
      const auto [f1, f2] = a.connection_frames<double>(c, frames, x.data());
      const Connection& conn = a.connection(c);
      cf.push_back({f1, f2, conn.first.part.value, conn.second.part.value});
    }
    const int no = cost_.objective_count();
    std::optional<Rigid<double>> target_frame;
    if (objective_ == Objective::kTarget) {
      target_frame =
          frames[static_cast<std::size_t>(problem_.target->part.value)].then(problem_.target->base);
    }

    for (int k = 0; k < n_; ++k) {
      const Slot& slot = slots_[static_cast<std::size_t>(k)];
      const Connection& c = a.connections()[static_cast<std::size_t>(slot.connection)];
      const Connector& side = slot.first ? c.first : c.second;
      const Primitive& prim =
          a.node(side.part).part->primitives[static_cast<std::size_t>(side.primitive)];
      // Local derivative of the connector transform L(q) (primitive coordinates).
      const Twist local = connector_twist(prim, x.data() + side.offset, slot.local);
      const Rigid<double>& owner = frames[static_cast<std::size_t>(side.part.value)];
      // World twist of the moving frame: the connector frame on this side.
      const Twist spatial = adjoint(owner.then(side.base), local);
      auto put = [&](int row, double v) {
        jacobian_[static_cast<std::size_t>(row * n_ + k)] = v * slot.scale;
      };
      if (!c.closes_cycle) {
        // Tree connection: the child and everything below it turn by ±spatial.
        const Twist tau = slot.first ? spatial : -spatial;
        const std::vector<int>& moving = below_[static_cast<std::size_t>(slot.connection)];
        auto moves = [&](int part) {
          return std::find(moving.begin(), moving.end(), part) != moving.end();
        };
        // Objective rows.
        if (objective_ == Objective::kEnergy) {
          double dz = 0;
          for (int q : moving) {
            const double m = problem_.masses[static_cast<std::size_t>(q)];
            if (m == 0) continue;
            const Rigid<double>& f = frames[static_cast<std::size_t>(q)];
            const Vec3 com = f.R * problem_.coms[static_cast<std::size_t>(q)] + f.t;
            dz += m / problem_.total_mass * tau.velocity(com).z();
          }
          put(0, dz);
        } else if (moves(problem_.target->part.value)) {
          target_derivative(*target_frame, tau, [&](int row, double v) { put(row, v); });
        }
        // Closure rows.
        int row = no;
        for (std::size_t i = 0; i < cf.size(); ++i) {
          const Twist t1 = moves(cf[i].part1) ? tau : Twist{};
          const Twist t2 = moves(cf[i].part2) ? tau : Twist{};
          row = closure_derivative(i, cf[i].f1, cf[i].f2, t1, t2, row, put);
        }
      } else {
        // A cycle-closing connection's own parameter moves only its connector frame.
        int row = no;
        for (std::size_t i = 0; i < cf.size(); ++i) {
          const bool mine = problem_.closures[i].value == slot.connection;
          const Twist t1 = mine && slot.first ? spatial : Twist{};
          const Twist t2 = mine && !slot.first ? spatial : Twist{};
          row = closure_derivative(i, cf[i].f1, cf[i].f2, t1, t2, row, put);
        }
      }
    }
    // Spacing rows depend on the t parameters directly: row = -(Σ |Δt|·L - need).
    int row = no + cost_.equality_count();
    for (const detail::MultiConnectionPair& m : problem_.multi) {
      for (std::size_t a_i = 0; a_i < m.params_i.size(); ++a_i) {
        const double d = x[static_cast<std::size_t>(m.params_j[a_i])] -
                         x[static_cast<std::size_t>(m.params_i[a_i])];
        const double sgn = d >= 0 ? 1.0 : -1.0;
        for (int k = 0; k < n_; ++k) {
          const int idx = vars_.index[static_cast<std::size_t>(k)];
          double g = 0;
          if (idx == m.params_j[a_i]) g = -sgn * m.length[a_i];
          if (idx == m.params_i[a_i]) g = sgn * m.length[a_i];
          if (g != 0)
            jacobian_[static_cast<std::size_t>(row * n_ + k)] +=
                g * vars_.scale[static_cast<std::size_t>(k)];
        }
      }
      ++row;
    }
  }

  int objectives() const { return cost_.objective_count(); }
  int equalities() const { return cost_.equality_count(); }
  int inequalities() const { return rows_ - objectives() - equalities(); }
  double value(int row) const { return values_[static_cast<std::size_t>(row)]; }
  double gradient(int row, int col) const {
    return jacobian_[static_cast<std::size_t>(row * n_ + col)];
  }

 private:
  // Velocity field of a rigid motion: v(p) = w × p + v0 (world coordinates).
  struct Twist {
    Vec3 w = Vec3::Zero();
    Vec3 v = Vec3::Zero();
    Vec3 velocity(const Vec3& p) const { return w.cross(p) + v; }
    Twist operator-() const { return {-w, -v}; }
  };

  struct Slot {
    int connection = 0;
    bool first = true;
    int offset = 0;
    int local = 0;
    double scale = 1;
  };

  // Twist dL/dq_j · L⁻¹ of a connector's local transform, in primitive coordinates.
  static Twist connector_twist(const Primitive& prim, const double* q, int j) {
    using Jet1 = ceres::Jet<double, 1>;
    const int dof = connector_dof(prim.connector_kind());
    Jet1 qj[3];
    for (int i = 0; i < dof; ++i) qj[i] = Jet1(q[i]);
    qj[j].v[0] = 1.0;
    Rigid<Jet1> l;
    apply_connector<Jet1>(prim.connector_kind(), prim.shape, qj, l);
    Mat3 r, dr;
    Vec3 t, dt;
    for (int a = 0; a < 3; ++a) {
      t[a] = l.t[a].a;
      dt[a] = l.t[a].v[0];
      for (int b = 0; b < 3; ++b) {
        r(a, b) = l.R(a, b).a;
        dr(a, b) = l.R(a, b).v[0];
      }
    }
    const Mat3 omega = dr * r.transpose();
    Twist tw;
    tw.w = Vec3(omega(2, 1), omega(0, 2), omega(1, 0));
    tw.v = dt - tw.w.cross(t);
    return tw;
  }

  // A twist given in frame F's coordinates, expressed in world coordinates.
  static Twist adjoint(const Rigid<double>& f, const Twist& local) {
    Twist out;
    out.w = f.R * local.w;
    out.v = f.R * local.v - out.w.cross(f.t);
    return out;
  }

  template <class Put>
  void target_derivative(const Rigid<double>& actual, const Twist& tau, Put put) const {
    const Vec3 dp = tau.velocity(actual.t);
    for (int i = 0; i < 3; ++i) put(i, dp[i]);
    const TargetModel& t = *problem_.target;
    if (t.symmetry.free_axis) {
      const Vec3 u = actual.R * *t.symmetry.free_axis;
      const Vec3 du = tau.w.cross(u);
      for (int i = 0; i < 3; ++i) put(3 + i, du[i] * kRadToDeg);
      return;
    }
    Mat3 skew;
    skew << 0, -tau.w.z(), tau.w.y(), tau.w.z(), 0, -tau.w.x(), -tau.w.y(), tau.w.x(), 0;
    const Mat3 dr = skew * actual.R;
    int k = 3;
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) put(k++, dr(r, c) * detail::kRotationResidualScale);
    }
  }

  template <class Put>
  int closure_derivative(std::size_t i,
                         const Rigid<double>& f1,
                         const Rigid<double>& f2,
                         const Twist& t1,
                         const Twist& t2,
                         int row,
                         Put put) const {
    const Vec3 dp = t1.velocity(f1.t) - t2.velocity(f2.t);
    for (int a = 0; a < 3; ++a) put(row++, dp[a]);
    // d(R1ᵀ R2) = R1ᵀ [w2 - w1]× R2.
    const Vec3 dw = t2.w - t1.w;
    Mat3 skew;
    skew << 0, -dw.z(), dw.y(), dw.z(), 0, -dw.x(), -dw.y(), dw.x(), 0;
    const Mat3 drel = f1.R.transpose() * skew * f2.R;
    if (problem_.free_axes[i]) {
      const Vec3 axis = *problem_.free_axes[i];
      const Vec3 b = axis.unitOrthogonal();
      const Vec3 d = axis.cross(b);
      const Vec3 dturned = drel * axis;
      put(row++, dturned.dot(b) * kRadToDeg);
      put(row++, dturned.dot(d) * kRadToDeg);
    } else {
      put(row++, (drel(2, 1) - drel(1, 2)) * 0.5 * kRadToDeg);
      put(row++, (drel(0, 2) - drel(2, 0)) * 0.5 * kRadToDeg);
      put(row++, (drel(1, 0) - drel(0, 1)) * 0.5 * kRadToDeg);
    }
    return row;
  }

  const Problem& problem_;
  const Variables& vars_;
  std::vector<double> base_;
  Objective objective_;
  ManifoldCost cost_;
  int n_;
  int rows_ = 0;
  std::vector<std::vector<int>> below_;
  std::vector<Slot> slots_;
  std::vector<double> last_, values_, jacobian_;
};

struct StepResult {
  std::vector<double> x;
  bool converged = true;
  bool closed = true;
  int iterations = 0;
  std::string note;
};

struct StabilityReport {
  std::vector<Slip> slips;
  double equilibrium_residual = 0;
};

std::string slip_message(const Assembly& a, int index, bool at_upper) {
  const ParamInfo& p = a.parameters()[static_cast<std::size_t>(index)];
  const Connection& c = a.connection(p.connection);
  const bool first = c.first.part == p.part && c.first.primitive == p.primitive &&
                     index < c.first.offset + static_cast<int>(c.first.params.size());
  const Connector& other = first ? c.second : c.first;
  const std::string owner = a.label(p.part, p.primitive);
  const std::string guest = a.label(other.part, other.primitive);
  const double bound = at_upper ? p.spec.hi : p.spec.lo;
  const Primitive& prim = a.node(p.part).part->primitives[static_cast<std::size_t>(p.primitive)];
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

// Optimisation on the constraint manifold. Every iterate keeps the cycle closures exactly: a
// trial step is projected back onto them by minimum-norm Gauss-Newton, which tolerates the
// redundant equations fixed joints create. Bounds are an active set. Steps are taken in the
// null space of the active constraints:
//  - fit(): Levenberg-Marquardt on the target residuals (step 1);
//  - relax(): Newton on the potential with the Hessian of the Lagrangian (finite differences
//    of automatic derivatives), eigenvalues made positive so every step descends (step 2).
// A direction the objective does not change along (a hook on a level rod) gets no step.
class ManifoldSolver {
 public:
  ManifoldSolver(const Problem& p,
                 const Variables& v,
                 const std::vector<double>& x,
                 Objective o,
                 std::optional<Clock::time_point> deadline = std::nullopt)
      : problem_(p),
        vars_(v),
        eval_(p, v, x, o),
        n_(static_cast<int>(v.index.size())),
        deadline_(deadline) {
    lo_ = Eigen::VectorXd::Constant(n_, -std::numeric_limits<double>::infinity());
    hi_ = Eigen::VectorXd::Constant(n_, std::numeric_limits<double>::infinity());
    for (int k = 0; k < n_; ++k) {
      const ParamSpec& s =
          p.assembly->parameters()[static_cast<std::size_t>(v.index[static_cast<std::size_t>(k)])]
              .spec;
      if (s.tag == ParamTag::kUnbounded) continue;
      lo_[k] = s.lo / v.scale[static_cast<std::size_t>(k)];
      hi_[k] = s.hi / v.scale[static_cast<std::size_t>(k)];
    }
  }

  /// Closes the cycles from an arbitrary configuration (Levenberg-Marquardt on the closure
  /// residuals, within the bounds), as a random start needs. Returns false if they stay open.
  bool close(std::vector<double>& x, int max_iterations) {
    Point cur = evaluate(to_vector(x));
    double mu = 1e-3;
    for (int it = 0; it < max_iterations; ++it) {
      if (cur.h.size() == 0 || cur.h.cwiseAbs().maxCoeff() < 1e-7) break;
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
    }
    if (!project(cur)) return false;
    std::vector<double> z(cur.z.data(), cur.z.data() + cur.z.size());
    std::vector<double> closed = x;
    from_z(vars_, z, closed);
    // The minimal orientation residuals also vanish at a half turn: check the real gaps.
    for (const detail::ClosureGap& g : detail::closure_gaps(*problem_.assembly, closed)) {
      if (g.rotation_deg > 1e-3) return false;
    }
    x = std::move(closed);
    return true;
  }

  /// `give_up`: a start whose objective is still above this after 15 iterations is abandoned
  /// (a random start that is not going to beat the best one so far).
  StepResult fit(const std::vector<double>& x0,
                 int max_iterations,
                 double give_up = std::numeric_limits<double>::infinity()) {
    StepResult out;
    Point cur = start(x0, out);
    if (!out.closed) return out;
    double mu = 1e-4;
    int it = 0;
    for (; it < max_iterations; ++it) {
      if (it == 15 && cur.f > give_up) break;
      if (out_of_time()) break;
      const Active act = active_set(cur);
      if (act.Z.cols() == 0) break;
      const Eigen::MatrixXd A = columns(cur.Jr, act.free) * act.Z;
      const Eigen::VectorXd b = A.transpose() * cur.r;
      if (b.cwiseAbs().maxCoeff() < kGradTol) break;
      Eigen::MatrixXd N = A.transpose() * A;
      const double scale = std::max(1e-12, N.diagonal().maxCoeff());
      bool moved = false;
      for (int tries = 0; tries < 12 && !moved; ++tries) {
        Eigen::MatrixXd M = N;
        M.diagonal().array() += mu * scale;
        const Eigen::VectorXd p = -M.ldlt().solve(b);
        Point trial = step(cur, act, act.Z * p);
        if (trial.valid && trial.f < cur.f) {
          moved = cur.f - trial.f > 1e-14 * std::max(1.0, cur.f);
          cur = std::move(trial);
          mu = std::max(1e-12, mu / 3);
          if (!moved) break;
          moved = true;
        } else {
          mu *= 8;
        }
      }
      if (!moved) break;
    }
    return finish(cur, it, max_iterations, out);
  }

  StepResult relax(const std::vector<double>& x0, int max_iterations) {
    StepResult out;
    Point cur = start(x0, out);
    if (!out.closed) return out;
    int it = 0;
    for (; it < max_iterations; ++it) {
      const Active act = active_set(cur);
      if (act.Z.cols() == 0) break;
      const Eigen::VectorXd rg = act.Z.transpose() * rows(cur.g, act.free);
      if (rg.cwiseAbs().maxCoeff() < kGradTol) break;  // equilibrium
      Eigen::MatrixXd H = act.Z.transpose() * lagrangian_hessian(cur, act) * act.Z;
      H = 0.5 * (H + H.transpose());
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
      const double floor = std::max(1e-10, 1e-8 * eig.eigenvalues().cwiseAbs().maxCoeff());
      const Eigen::VectorXd ev = eig.eigenvalues().cwiseAbs().cwiseMax(floor);
      const Eigen::VectorXd p =
          -eig.eigenvectors() * (eig.eigenvectors().transpose() * rg).cwiseQuotient(ev);
      bool moved = false;
      const double slope = rg.dot(p);
      for (double alpha = 1.0; alpha > 1e-10; alpha *= 0.5) {
        Point trial = step(cur, act, alpha * (act.Z * p));
        if (!trial.valid) continue;
        if (trial.f <= cur.f + 1e-4 * alpha * std::min(slope, 0.0)) {
          moved = trial.f < cur.f;
          cur = std::move(trial);
          break;
        }
      }
      if (!moved) break;  // no further decrease within round-off
    }
    return finish(cur, it, max_iterations, out);
  }

  /// The verdict at `x`: the equilibrium residual (largest slope of the potential along the
  /// motions the connections and bounds allow, mm of mean height per mm or degree) and every
  /// open bound that the potential pulls a connection out of.
  StabilityReport stability(const std::vector<double>& x, double fall_threshold) {
    StabilityReport report;
    const Assembly& a = *problem_.assembly;
    const Point p = evaluate(to_vector(x));
    const Active act = active_set(p);
    if (act.Z.cols() > 0) {
      report.equilibrium_residual = (act.Z.transpose() * rows(p.g, act.free)).cwiseAbs().maxCoeff();
    }
    const std::vector<int> off = off_bounds(p);
    const Eigen::MatrixXd J_off = columns(p.J, off);
    for (int k = 0; k < n_; ++k) {
      const int side = at_bound(p.z, k);
      if (side == 0) continue;
      const int index = vars_.index[static_cast<std::size_t>(k)];
      const ParamSpec& spec = a.parameters()[static_cast<std::size_t>(index)].spec;
      if (!(side < 0 ? spec.open_at_lo : spec.open_at_hi)) continue;
      // Move k outwards by one unit; the coordinates off their bounds follow so the cycles
      // stay closed (minimum-norm correction). If they cannot, the move is blocked.
      double slope = side * p.g[k];
      if (p.J.rows() > 0) {
        const Eigen::VectorXd rhs = -side * p.J.col(k);
        Eigen::VectorXd delta = Eigen::VectorXd::Zero(static_cast<int>(off.size()));
        if (!off.empty()) delta = J_off.completeOrthogonalDecomposition().solve(rhs);
        if ((J_off * delta - rhs).norm() > 1e-6 * std::max(1.0, rhs.norm())) continue;
        slope += rows(p.g, off).dot(delta);
      }
      if (slope < -fall_threshold) {
        Slip slip;
        slip.connection = a.parameters()[static_cast<std::size_t>(index)].connection;
        slip.parameter = index;
        slip.message = slip_message(a, index, side > 0);
        report.slips.push_back(slip);
      }
    }
    return report;
  }

 private:
  bool out_of_time() const { return deadline_ && Clock::now() > *deadline_; }

  static constexpr double kGradTol = 1e-9;   // objective slope per mm (or degree) of motion
  static constexpr double kFeasTol = 1e-10;  // closure residual (mm, degrees)

  struct Point {
    Eigen::VectorXd z;
    bool valid = true;
    double f = 0;       // objective: ½‖r‖² or the potential
    Eigen::VectorXd g;  // its gradient
    Eigen::VectorXd r;  // target residuals (fit only)
    Eigen::MatrixXd Jr;
    Eigen::VectorXd h;  // closures, then active spacing constraints
    Eigen::MatrixXd J;
  };

  struct Active {
    std::vector<int> free;  // coordinates that may move
    Eigen::MatrixXd Z;      // null space of the constraints on them
  };

  Eigen::VectorXd to_vector(const std::vector<double>& x) const {
    const std::vector<double> z = to_z(vars_, x);
    return Eigen::Map<const Eigen::VectorXd>(z.data(), n_).cwiseMax(lo_).cwiseMin(hi_);
  }

  Point start(const std::vector<double>& x0, StepResult& out) {
    out.x = x0;
    Point cur = evaluate(to_vector(x0));
    out.closed = project(cur);
    if (!out.closed) out.note = "the cycles could not be kept closed";
    return cur;
  }

  StepResult& finish(const Point& cur, int iterations, int max_iterations, StepResult& out) {
    out.iterations = iterations;
    out.converged = iterations < max_iterations;
    std::vector<double> z(cur.z.data(), cur.z.data() + cur.z.size());
    from_z(vars_, z, out.x);
    return out;
  }

  int at_bound(const Eigen::VectorXd& z, int k) const {
    const double tol = 1e-9 * std::max(1.0, hi_[k] - lo_[k]);
    if (std::isfinite(lo_[k]) && z[k] <= lo_[k] + tol) return -1;
    if (std::isfinite(hi_[k]) && z[k] >= hi_[k] - tol) return +1;
    return 0;
  }

  std::vector<int> off_bounds(const Point& p) const {
    std::vector<int> f;
    for (int k = 0; k < n_; ++k) {
      if (at_bound(p.z, k) == 0) f.push_back(k);
    }
    return f;
  }

  static Eigen::MatrixXd columns(const Eigen::MatrixXd& m, const std::vector<int>& cols) {
    Eigen::MatrixXd out(m.rows(), static_cast<int>(cols.size()));
    for (std::size_t i = 0; i < cols.size(); ++i) out.col(static_cast<int>(i)) = m.col(cols[i]);
    return out;
  }
  static Eigen::VectorXd rows(const Eigen::VectorXd& v, const std::vector<int>& idx) {
    Eigen::VectorXd out(static_cast<int>(idx.size()));
    for (std::size_t i = 0; i < idx.size(); ++i) out[static_cast<int>(i)] = v[idx[i]];
    return out;
  }

  // Orthonormal basis of the null space of m; all of R^n if m has no rows.
  static Eigen::MatrixXd null_space(const Eigen::MatrixXd& m) {
    const int n = static_cast<int>(m.cols());
    if (m.rows() == 0 || n == 0) return Eigen::MatrixXd::Identity(n, n);
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(m, Eigen::ComputeFullV);
    const Eigen::VectorXd& sv = svd.singularValues();
    const double tol = std::max(1e-12, 1e-9 * (sv.size() ? sv[0] : 0.0));
    int rank = 0;
    for (int i = 0; i < sv.size(); ++i) rank += sv[i] > tol ? 1 : 0;
    return svd.matrixV().rightCols(n - rank);
  }

  // Least-squares multipliers: g_F ≈ J_Fᵀ λ.
  static Eigen::VectorXd multipliers(const Point& p, const std::vector<int>& free) {
    if (p.J.rows() == 0) return Eigen::VectorXd();
    if (free.empty()) return Eigen::VectorXd::Zero(p.J.rows());
    return columns(p.J, free).transpose().completeOrthogonalDecomposition().solve(rows(p.g, free));
  }

  // Coordinates at a bound stay there unless the objective, after the constraints take their
  // share, pulls them back inside.
  Active active_set(const Point& p) const {
    Active act;
    const std::vector<int> off = off_bounds(p);
    const Eigen::VectorXd lambda = multipliers(p, off);
    const Eigen::VectorXd reduced =
        lambda.size() ? Eigen::VectorXd(p.g - p.J.transpose() * lambda) : p.g;
    for (int k = 0; k < n_; ++k) {
      const int side = at_bound(p.z, k);
      if (side == 0 || side * reduced[k] > kGradTol) act.free.push_back(k);
    }
    act.Z = null_space(columns(p.J, act.free));
    return act;
  }

  Point evaluate(const Eigen::VectorXd& z) {
    Point p;
    p.z = z;
    eval_.evaluate(z.data());
    const int no = eval_.objectives();
    const int m = eval_.equalities();
    std::vector<int> active;
    for (int i = 0; i < eval_.inequalities(); ++i) {
      if (eval_.value(no + m + i) > -1e-6) active.push_back(no + m + i);
    }
    const int rows_total = m + static_cast<int>(active.size());
    p.h.resize(rows_total);
    p.J.resize(rows_total, n_);
    for (int r = 0; r < rows_total; ++r) {
      const int row = r < m ? no + r : active[static_cast<std::size_t>(r - m)];
      // A spacing constraint binds only while active; a satisfied one contributes 0.
      p.h[r] = r < m ? eval_.value(row) : std::max(0.0, eval_.value(row));
      for (int k = 0; k < n_; ++k) p.J(r, k) = eval_.gradient(row, k);
    }
    if (no == 1) {
      p.f = eval_.value(0);
      p.g.resize(n_);
      for (int k = 0; k < n_; ++k) p.g[k] = eval_.gradient(0, k);
    } else {
      p.r.resize(no);
      p.Jr.resize(no, n_);
      for (int i = 0; i < no; ++i) {
        p.r[i] = eval_.value(i);
        for (int k = 0; k < n_; ++k) p.Jr(i, k) = eval_.gradient(i, k);
      }
      p.f = 0.5 * p.r.squaredNorm();
      p.g = p.Jr.transpose() * p.r;
    }
    return p;
  }

  // Minimum-norm Gauss-Newton back onto h = 0, moving only coordinates off their bounds.
  bool project(Point& p) {
    for (int iter = 0; iter < 30; ++iter) {
      if (p.h.size() == 0 || p.h.cwiseAbs().maxCoeff() < kFeasTol) return true;
      const std::vector<int> free = off_bounds(p);
      if (free.empty()) return false;
      const Eigen::VectorXd delta =
          columns(p.J, free).completeOrthogonalDecomposition().solve(-p.h);
      Eigen::VectorXd z = p.z;
      for (std::size_t i = 0; i < free.size(); ++i) z[free[i]] += delta[static_cast<int>(i)];
      const double before = p.h.norm();
      p = evaluate(z.cwiseMax(lo_).cwiseMin(hi_));
      if (p.h.norm() > before && iter > 3) return false;
    }
    return p.h.size() == 0 || p.h.cwiseAbs().maxCoeff() < 1e-7;
  }

  Point step(const Point& from, const Active& act, const Eigen::VectorXd& dF) {
    Eigen::VectorXd z = from.z;
    for (std::size_t i = 0; i < act.free.size(); ++i) z[act.free[i]] += dF[static_cast<int>(i)];
    Point trial = evaluate(z.cwiseMax(lo_).cwiseMin(hi_));
    trial.valid = project(trial);
    return trial;
  }

  // Hessian of f - λᵀh on the free coordinates, by forward differences of exact gradients.
  Eigen::MatrixXd lagrangian_hessian(const Point& p, const Active& act) {
    const Eigen::VectorXd lambda = multipliers(p, act.free);
    const int nf = static_cast<int>(act.free.size());
    Eigen::MatrixXd H(nf, nf);
    auto grad_l = [&](const Point& q) {
      Eigen::VectorXd gl = q.g;
      if (lambda.size() && q.J.rows() >= lambda.size()) {
        gl -= q.J.topRows(lambda.size()).transpose() * lambda;
      }
      return rows(gl, act.free);
    };
    const Eigen::VectorXd g0 = grad_l(p);
    for (int i = 0; i < nf; ++i) {
      const int k = act.free[static_cast<std::size_t>(i)];
      const double eps = 1e-6 * std::max(1.0, std::abs(p.z[k]));
      Eigen::VectorXd zp = p.z;
      zp[k] += eps;
      H.col(i) = (grad_l(evaluate(zp)) - g0) / eps;
    }
    return H;
  }

  const Problem& problem_;
  const Variables& vars_;
  AnalyticEvaluator eval_;
  int n_;
  Eigen::VectorXd lo_, hi_;
  std::optional<Clock::time_point> deadline_;
};

// ---- step 1: the target -------------------------------------------------------------------

struct Step1Result {
  std::vector<double> x;
  PoseError error;
  int starts = 0;
  bool closed = false;
  bool hit_iteration_limit = false;
};

PoseError error_at(const Problem& p, const std::vector<double>& x) {
  const std::vector<Mat4> frames = p.assembly->part_frames(x);
  return pose_error(
      *p.target,
      Rigid<double>::from_matrix(frames[static_cast<std::size_t>(p.target->part.value)]));
}

// Start 0 is the configuration the connects verified; the others are seeded random
// configurations, closed first by the verification's cycle search.
Step1Result run_step1(const Problem& p, const SolveOptions& o) {
  const Assembly& a = *p.assembly;
  Step1Result best;
  best.x = a.values();
  best.closed = true;
  if (!p.target) return best;
  best.error = error_at(p, best.x);
  const Variables vars = select_variables(a, /*physics=*/false);
  if (vars.index.empty()) return best;

  auto score = [](const PoseError& e) {
    return e.position_mm * e.position_mm + e.rotation_deg * e.rotation_deg;
  };
  double best_score = score(best.error);
  detail::SplitMix rng(o.seed);
  for (int start = 0; start < std::max(1, o.target_starts); ++start) {
    // Nothing can beat a target that is already reached.
    if (best.error.position_mm < 1e-4 && best.error.rotation_deg < 1e-4) break;
    std::vector<double> x0 = a.values();
    if (start > 0) {
      for (int v : vars.index) {
        const ParamSpec& s = a.parameters()[static_cast<std::size_t>(v)].spec;
        x0[static_cast<std::size_t>(v)] = s.lo + rng.uniform() * (s.hi - s.lo);
      }
    }
    if (o.deadline && Clock::now() > *o.deadline) break;
    ManifoldSolver solver(p, vars, x0, Objective::kTarget, o.deadline);
    if (start > 0 && !solver.close(x0, 100)) {
      // The local closing failed from this start: the verification's global search (two
      // phases, stall detection) usually gets there.
      VerifyOptions v;
      v.restarts = 1;
      v.deadline = o.deadline;
      const detail::ClosureResult closed = detail::close_cycles(a, x0, v);
      if (!closed.closed) continue;
      x0 = closed.x;
    }
    // Random starts explore: a fifth of the iterations of the verified start, and they stop
    // early when they are far from beating the best start so far (f = ½‖r‖²).
    StepResult r = start == 0 ? solver.fit(x0, o.max_iterations)
                              : solver.fit(x0, o.max_iterations / 5, 5 * best_score);
    best.starts = start + 1;
    if (!r.closed) continue;
    for (std::size_t i = 0; i < r.x.size(); ++i) {
      if (a.parameters()[i].spec.tag == ParamTag::kUnbounded) r.x[i] = wrap_360(r.x[i]);
    }
    const PoseError e = error_at(p, r.x);
    if (score(e) < best_score - 1e-9) {
      best_score = score(e);
      best.x = r.x;
      best.error = e;
      best.hit_iteration_limit = !r.converged;
    }
  }
  return best;
}

// ---- step 2 and the verdict ----------------------------------------------------------------

StepResult run_step2(const Problem& p,
                     const Variables& vars,
                     const std::vector<double>& x1,
                     const SolveOptions& o) {
  if (vars.index.empty() || p.total_mass <= 0) {
    StepResult out;
    out.x = x1;
    return out;
  }
  ManifoldSolver solver(p, vars, x1, Objective::kEnergy, o.deadline);
  return solver.relax(x1, o.max_iterations);
}

StabilityReport check_stability(const Problem& p,
                                const Variables& vars,
                                const std::vector<double>& x,
                                const SolveOptions& o) {
  if (vars.index.empty() || p.total_mass <= 0) return {};
  ManifoldSolver solver(p, vars, x, Objective::kEnergy);
  return solver.stability(x, o.fall_threshold);
}

}  // namespace

namespace detail {

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

}  // namespace detail

std::string_view to_string(Termination t) {
  switch (t) {
    case Termination::kConverged:
      return "CONVERGED";
    case Termination::kNoTarget:
      return "NO_TARGET";
    case Termination::kInfeasible:
      return "INFEASIBLE";
    case Termination::kMaxIterations:
      return "MAX_ITERATIONS";
    case Termination::kTimeout:
      return "TIMEOUT";
  }
  return "CONVERGED";
}

PoseError target_error(const Assembly& assembly, const std::vector<double>& x) {
  const std::optional<TargetModel> t = make_target(assembly);
  if (!t) return {};
  const std::vector<Mat4> frames = assembly.part_frames(x);
  return pose_error(*t,
                    Rigid<double>::from_matrix(frames[static_cast<std::size_t>(t->part.value)]));
}

SolveResult solve(const Assembly& assembly, const SolveOptions& options) {
  SolveResult result;
  const Problem problem = make_problem(assembly);
  if (assembly.part_count() == 0) {
    result.termination = Termination::kInfeasible;
    result.message = "the assembly is empty";
    result.diagnostics.error(codes::kNoEnvironment, "solve: the assembly is empty");
    return result;
  }
  if (!problem.target) {
    result.termination = Termination::kNoTarget;
    result.diagnostics.warning(codes::kTargetMissing,
                               assembly.target() ? "the target is not connected to the hack; "
                                                   "step 1 is skipped"
                                                 : "the design has no target (end_with); step 1 "
                                                   "is skipped");
  }
  // The starting point must be a closed configuration (connect verified it).
  if (max_gap(assembly, assembly.values()) > 1e-3) {
    result.termination = Termination::kInfeasible;
    result.message = "the cycles of the assembly are not closed";
    result.diagnostics.error(codes::kCycleNotClosable,
                             "solve: the assembly's cycles are not closed; verify its connects");
    return result;
  }

  auto announce = [&](std::string_view stage) {
    if (options.on_stage) options.on_stage(stage);
  };
  // Step 1.
  announce("step1");
  auto t1 = Clock::now();
  const Step1Result step1 = run_step1(problem, options);
  result.timings.push_back({"step1", ms_since(t1)});
  result.step1_parameters = step1.x;
  result.step1_starts = step1.starts;
  result.target_step1 = step1.error;
  if (!step1.closed) {
    result.termination = Termination::kInfeasible;
    result.message = "step 1 found no configuration that keeps every cycle closed";
    result.diagnostics.error(codes::kCycleNotClosable, result.message);
    return result;
  }
  result.feasible = true;

  // Step 2.
  const Variables vars = select_variables(assembly, /*physics=*/true);
  std::vector<double> x = step1.x;
  bool converged = !step1.hit_iteration_limit;
  if (options.relax) {
    announce("step2");
    auto t2 = Clock::now();
    StepResult step2 = run_step2(problem, vars, step1.x, options);
    x = step2.x;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (assembly.parameters()[i].spec.tag == ParamTag::kUnbounded) x[i] = wrap_360(x[i]);
    }
    if (!step2.closed || max_gap(assembly, x) > options.closure_tolerance_mm) {
      result.diagnostics.warning(codes::kCycleNotClosable,
                                 "relaxation left a cycle open by more than the tolerance");
    }
    converged = converged && step2.converged;
    if (!step2.note.empty()) result.stability_notes.push_back(step2.note);
    result.timings.push_back({"step2", ms_since(t2)});
  }
  result.parameters = x;

  // Verdict.
  announce("stability");
  auto t3 = Clock::now();
  const StabilityReport stability = check_stability(problem, vars, x, options);
  result.slips = stability.slips;
  result.equilibrium_residual = stability.equilibrium_residual;
  result.stable = result.slips.empty();
  result.timings.push_back({"stability", ms_since(t3)});

  const std::vector<Mat4> frames = assembly.part_frames(x);
  for (int i = 0; i < assembly.part_count(); ++i) {
    const PartNode& n = assembly.node(PartId{i});
    result.parts.push_back({assembly.label(PartId{i}),
                            n.part->type_name,
                            n.environment,
                            problem.target && problem.target->part.value == i,
                            Frame::from_matrix(frames[static_cast<std::size_t>(i)])});
  }
  if (problem.target) {
    result.target = pose_error(
        *problem.target,
        Rigid<double>::from_matrix(frames[static_cast<std::size_t>(problem.target->part.value)]));
  }
  result.max_gap_mm = max_gap(assembly, x, &result.max_gap_deg);
  double energy = 0;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    energy += problem.masses[i] * (frames[i].topLeftCorner<3, 3>() * problem.coms[i] +
                                   frames[i].topRightCorner<3, 1>())[2];
  }
  result.energy = energy;
  if (!converged && result.termination == Termination::kConverged) {
    result.termination = Termination::kMaxIterations;
  }
  if (options.deadline && Clock::now() > *options.deadline) {
    result.termination = Termination::kTimeout;
    result.diagnostics.error(codes::kTimeLimit,
                             "the solve stopped at its time limit; the result is incomplete");
  }
  if (result.stable) {
    std::string how = "nothing slides off under gravity";
    if (problem.target) {
      // How far gravity moved the target from where step 1 put it: a sag, not a failure.
      const std::size_t t = static_cast<std::size_t>(problem.target->part.value);
      const Mat4 before = assembly.part_frames(step1.x)[t] * problem.target->base.matrix();
      const Mat4 after = frames[t] * problem.target->base.matrix();
      const double moved = (after.topRightCorner<3, 1>() - before.topRightCorner<3, 1>()).norm();
      const double turned = Eigen::AngleAxisd(Mat3(before.topLeftCorner<3, 3>().transpose() *
                                                   after.topLeftCorner<3, 3>()))
                                .angle() *
                            kRadToDeg;
      if (moved > 0.05 || turned > 0.05) {
        how = fmt::format(
            "nothing slides off; under gravity the target sags {:.1f} mm and tilts "
            "{:.1f}° from step 1",
            moved,
            turned);
      }
    }
    result.stability_notes.push_back(fmt::format("stable: {}", how));
    result.message = "stable";
  } else {
    result.message = fmt::format("falls apart: {}", result.slips.front().message);
  }
  return result;
}

std::string SolveResult::summary() const {
  std::string s;
  s += "FabHaL solve report\n";
  s += fmt::format("  {:<28}{}\n", "termination", to_string(termination));
  s += fmt::format(
      "  {:<28}{}\n", "verdict", stable ? "STABLE" : (feasible ? "FALLS APART" : "INFEASIBLE"));
  s += fmt::format("  {:<28}{:.3f} mm, {:.3f}°  ({} start{})\n",
                   "target error after step 1",
                   target_step1.position_mm,
                   target_step1.rotation_deg,
                   step1_starts,
                   step1_starts == 1 ? "" : "s");
  s += fmt::format("  {:<28}{:.3f} mm, {:.3f}°\n",
                   "target error after step 2",
                   target.position_mm,
                   target.rotation_deg);
  s += fmt::format(
      "  {:<28}{:.2e} mm, {:.2e}°\n", "largest connection gap", max_gap_mm, max_gap_deg);
  s += fmt::format("  {:<28}{:.2e} (slope of the potential, mm per mm or degree)\n",
                   "equilibrium residual",
                   equilibrium_residual);
  for (const Slip& slip : slips) s += fmt::format("  {:<28}{}\n", "slips", slip.message);
  for (const std::string& n : stability_notes) s += fmt::format("  {:<28}{}\n", "note", n);
  std::string times;
  for (const StageTiming& t : timings)
    times += fmt::format("{} {:.1f} ms  ", t.stage, t.milliseconds);
  s += fmt::format("  {:<28}{}\n", "time", times);
  return s;
}

}  // namespace fabkit::hacks

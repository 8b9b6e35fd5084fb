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
#include <cstdio>
#include <cstdlib>
#include <set>

#include "constraints.h"
#include "cycle_closure.h"

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

void set_bounds(ceres::Problem& problem, double* z, const Assembly& a, const Variables& v) {
  for (std::size_t k = 0; k < v.index.size(); ++k) {
    const ParamSpec& s = a.parameters()[static_cast<std::size_t>(v.index[k])].spec;
    if (s.tag == ParamTag::kUnbounded) continue;
    problem.SetParameterLowerBound(z, static_cast<int>(k), s.lo / v.scale[k]);
    problem.SetParameterUpperBound(z, static_cast<int>(k), s.hi / v.scale[k]);
  }
}

ceres::Solver::Options least_squares_options(int max_iterations) {
  ceres::Solver::Options o;
  o.linear_solver_type = ceres::DENSE_QR;
  o.max_num_iterations = max_iterations;
  o.function_tolerance = 1e-14;
  o.gradient_tolerance = 1e-14;
  o.parameter_tolerance = 1e-12;
  o.num_threads = 1;
  o.logging_type = ceres::SILENT;
  return o;
}

// ---- step 1: the target -------------------------------------------------------------------

struct TargetCost {
  const Problem* problem;
  const Variables* vars;
  std::vector<double> base;
  double weight;

  int residual_count() const {
    return (problem->target ? kTargetResiduals : 0) +
           static_cast<int>(problem->closures.size()) * detail::kClosureResiduals +
           static_cast<int>(problem->multi.size());
  }

  template <class T>
  bool operator()(T const* const* params, T* residuals) const {
    const std::vector<T> x = expand<T>(*vars, base, params[0]);
    const Assembly& a = *problem->assembly;
    const std::vector<Rigid<T>> frames = a.all_part_frames<T>(x.data());
    T* out = residuals;
    if (problem->target) {
      target_residuals<T>(
          *problem->target, frames[static_cast<std::size_t>(problem->target->part.value)], out);
      out += kTargetResiduals;
    }
    for (std::size_t c = 0; c < problem->closures.size(); ++c) {
      const auto [f1, f2] = a.connection_frames<T>(problem->closures[c], frames, x.data());
      for (int i = 0; i < 3; ++i) out[i] = (f1.t[i] - f2.t[i]) * T(weight);
      if (problem->free_axes[c]) {
        const Vec3T<T> axis = problem->free_axes[c]->template cast<T>();
        const Vec3T<T> d = f1.R * axis - f2.R * axis;
        for (int i = 0; i < 3; ++i) out[3 + i] = d[i] * T(kRadToDeg * weight);
        for (int i = 6; i < detail::kClosureResiduals; ++i) out[i] = T(0);
      } else {
        int k = 3;
        for (int col = 0; col < 3; ++col) {
          for (int row = 0; row < 3; ++row) {
            out[k++] =
                (f1.R(row, col) - f2.R(row, col)) * T(detail::kRotationResidualScale * weight);
          }
        }
      }
      out += detail::kClosureResiduals;
    }
    for (const detail::MultiConnectionPair& m : problem->multi) {
      const T f = detail::multi_connection_value<T>(m, x.data());
      *out++ = (f < T(0) ? f : T(0)) * T(weight);
    }
    return true;
  }
};

class SplitMix {
 public:
  explicit SplitMix(std::uint64_t seed) : state_(seed) {}
  double uniform() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

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

double multi_violation(const Problem& p, const std::vector<double>& x) {
  double worst = 0;
  for (const detail::MultiConnectionPair& m : p.multi) {
    worst = std::max(worst, -detail::multi_connection_value<double>(m, x.data()));
  }
  return worst;
}

// Re-closes the cycles from `x` with a local least-squares solve (removes the penalty's
// residual gap). Returns false if they do not close.
bool polish_closures(const Assembly& a, std::vector<double>& x, const SolveOptions& o) {
  if (a.cycle_connections().empty()) return true;
  VerifyOptions v;
  v.restarts = 1;
  v.tolerance = 1e-16;
  v.max_iterations = 50;
  const detail::ClosureResult r = detail::close_cycles(a, x, v);
  if (max_gap(a, r.x) <= o.closure_tolerance_mm) {
    x = r.x;
    return true;
  }
  return max_gap(a, x) <= o.closure_tolerance_mm;
}

struct Step1Result {
  std::vector<double> x;
  PoseError error;
  int starts = 0;
  bool closed = false;
  bool hit_iteration_limit = false;
};

Step1Result run_step1(const Problem& p, const SolveOptions& o) {
  const Assembly& a = *p.assembly;
  Step1Result best;
  best.x = a.values();
  const std::vector<Mat4> frames0 = a.part_frames(best.x);
  best.error = p.target ? pose_error(*p.target,
                                     Rigid<double>::from_matrix(
                                         frames0[static_cast<std::size_t>(p.target->part.value)]))
                        : PoseError{};
  best.closed = max_gap(a, best.x) <= o.closure_tolerance_mm;
  if (!p.target) return best;

  const Variables vars = select_variables(a, /*physics=*/false);
  if (vars.index.empty()) return best;
  auto* functor = new TargetCost{&p, &vars, a.values(), o.constraint_weight};
  auto* cost = new ceres::DynamicAutoDiffCostFunction<TargetCost, 4>(functor);
  cost->AddParameterBlock(static_cast<int>(vars.index.size()));
  cost->SetNumResiduals(functor->residual_count());
  std::vector<double> z(vars.index.size());
  ceres::Problem problem;
  problem.AddResidualBlock(cost, nullptr, z.data());
  set_bounds(problem, z.data(), a, vars);
  const ceres::Solver::Options options = least_squares_options(o.max_iterations);

  SplitMix rng(o.seed);
  auto score = [](const PoseError& e) {
    return e.position_mm * e.position_mm + e.rotation_deg * e.rotation_deg;
  };
  double best_score = best.closed ? score(best.error) : std::numeric_limits<double>::infinity();
  for (int start = 0; start < std::max(1, o.target_starts); ++start) {
    const std::vector<double> z0 = to_z(vars, a.values());
    for (std::size_t k = 0; k < z.size(); ++k) {
      const ParamSpec& s = a.parameters()[static_cast<std::size_t>(vars.index[k])].spec;
      z[k] = start == 0 ? z0[k] : (s.lo + rng.uniform() * (s.hi - s.lo)) / vars.scale[k];
    }
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    best.starts = start + 1;
    std::vector<double> x = a.values();
    from_z(vars, z, x);
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (a.parameters()[i].spec.tag == ParamTag::kUnbounded) x[i] = wrap_360(x[i]);
    }
    if (!polish_closures(a, x, o)) continue;
    if (multi_violation(p, x) > 1e-3) continue;
    const std::vector<Mat4> frames = a.part_frames(x);
    const PoseError e = pose_error(
        *p.target,
        Rigid<double>::from_matrix(frames[static_cast<std::size_t>(p.target->part.value)]));
    if (score(e) < best_score - 1e-12) {
      best_score = score(e);
      best.x = x;
      best.error = e;
      best.closed = true;
      best.hit_iteration_limit = summary.termination_type == ceres::NO_CONVERGENCE;
    }
  }
  return best;
}

// ---- step 2: relaxation under gravity -----------------------------------------------------

// Everything step 2 needs at one point, differentiated: [energy, equalities..., inequalities...].
struct PhysicsCost {
  const Problem* problem;
  const Variables* vars;
  std::vector<double> base;

  int equality_count() const {
    int n = 0;
    for (const auto& axis : problem->free_axes) n += axis ? 5 : 6;
    return n;
  }
  int residual_count() const {
    return 1 + equality_count() + static_cast<int>(problem->multi.size());
  }

  template <class T>
  bool operator()(T const* const* params, T* out) const {
    const std::vector<T> x = expand<T>(*vars, base, params[0]);
    const Assembly& a = *problem->assembly;
    const std::vector<Rigid<T>> frames = a.all_part_frames<T>(x.data());
    // Mass-weighted mean height of the centres of mass, mm.
    T energy(0);
    for (std::size_t i = 0; i < frames.size(); ++i) {
      if (problem->masses[i] == 0) continue;
      const Vec3T<T> com = frames[i].R * problem->coms[i].cast<T>() + frames[i].t;
      energy += com[2] * T(problem->masses[i] / problem->total_mass);
    }
    out[0] = energy;
    T* eq = out + 1;
    for (std::size_t c = 0; c < problem->closures.size(); ++c) {
      const auto [f1, f2] = a.connection_frames<T>(problem->closures[c], frames, x.data());
      for (int i = 0; i < 3; ++i) *eq++ = f1.t[i] - f2.t[i];
      // Minimal orientation residuals (in the first frame), scaled to ≈ degrees·mm⁰.
      const Mat3T<T> rel = f1.R.transpose() * f2.R;
      if (problem->free_axes[c]) {
        // Only the free axis must line up: two components perpendicular to it.
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
      *eq++ = -detail::multi_connection_value<T>(m, x.data());  // ≤ 0
    }
    return true;
  }
};

// Evaluates PhysicsCost with its Jacobian, caching the last point (NLopt asks for the
// objective and the constraints separately at the same point).
class PhysicsEvaluator {
 public:
  PhysicsEvaluator(const Problem& p, const Variables& v, std::vector<double> base)
      : functor_(new PhysicsCost{&p, &v, std::move(base)}),
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
  int rows() const { return rows_; }
  int equalities() const { return functor_->equality_count(); }
  int inequalities() const { return rows_ - 1 - equalities(); }
  double value(int row) const { return values_[static_cast<std::size_t>(row)]; }
  double gradient(int row, int col) const {
    return jacobian_[static_cast<std::size_t>(row * n_ + col)];
  }

 private:
  PhysicsCost* functor_;  // owned by cost_
  ceres::DynamicAutoDiffCostFunction<PhysicsCost, 4> cost_;
  int rows_;
  int n_;
  std::vector<double> last_, values_, jacobian_;
};

struct Step2Result {
  std::vector<double> x;
  bool converged = true;
  std::string note;
};

// One evaluation of step 2's functions at z: energy, gradient, the equality rows (cycle
// closures) and the active inequality rows (multi-connection spacing), with Jacobians.
struct Point {
  Eigen::VectorXd z;
  double energy = 0;
  Eigen::VectorXd g;
  Eigen::VectorXd h;  // equalities, then the active inequalities
  Eigen::MatrixXd J;
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
  if (p.spec.name == "phi") {
    return fmt::format("{} tilts off {} (φ = {:g}°)", guest, owner, bound);
  }
  if (p.spec.is_angle()) {
    return fmt::format("{} slides off the open end of {} (θ = {:g}°)", guest, owner, bound);
  }
  return fmt::format(
      "{} slides off the open end of {} ({} = {:g})", guest, owner, p.spec.name, bound);
}

// Step 2 as a reduced-space Newton method on the constraint manifold: the closure equations
// are kept exactly by projecting every trial point back onto them (minimum-norm Gauss-Newton,
// which tolerates the redundant equations fixed joints create); bounds are an active set; the
// Newton system uses the Hessian of the Lagrangian (finite differences of automatic
// derivatives), with its eigenvalues made positive so every step descends. Directions the
// energy does not change along (a hook on a level rod) get no gradient and therefore no step.
class Relaxation {
 public:
  Relaxation(const Problem& p, const Variables& v, const std::vector<double>& x1)
      : problem_(p), vars_(v), eval_(p, v, x1), n_(static_cast<int>(v.index.size())) {
    lo_ = Eigen::VectorXd::Constant(n_, -std::numeric_limits<double>::infinity());
    hi_ = Eigen::VectorXd::Constant(n_, std::numeric_limits<double>::infinity());
    for (int k = 0; k < n_; ++k) {
      const ParamSpec& s =
          p.assembly->parameters()[static_cast<std::size_t>(v.index[static_cast<std::size_t>(k)])].spec;
      if (s.tag == ParamTag::kUnbounded) continue;
      lo_[k] = s.lo / v.scale[static_cast<std::size_t>(k)];
      hi_[k] = s.hi / v.scale[static_cast<std::size_t>(k)];
    }
  }

  Step2Result run(const std::vector<double>& x1, int max_iterations) {
    Step2Result out;
    out.x = x1;
    Eigen::VectorXd z = Eigen::Map<const Eigen::VectorXd>(to_z(vars_, x1).data(), n_);
    z = z.cwiseMax(lo_).cwiseMin(hi_);
    Point cur = evaluate(z, {});
    if (!project(cur)) {
      out.converged = false;
      out.note = "relaxation could not keep the cycles closed";
      return out;
    }
    int it = 0;
    for (; it < max_iterations; ++it) {
      // Active bounds: at a bound, and the energy (after the constraints take their share)
      // pushes further out.
      const Eigen::VectorXd lambda = multipliers(cur, all_free(cur));
      const Eigen::VectorXd reduced = cur.g - cur.J.transpose() * lambda;
      std::vector<int> free;
      for (int k = 0; k < n_; ++k) {
        const int side = at_bound(cur.z, k);
        if (side == 0 || side * reduced[k] > kGradTol) free.push_back(k);
      }
      const Eigen::MatrixXd JF = columns(cur.J, free);
      const Eigen::VectorXd gF = rows(cur.g, free);
      const Eigen::MatrixXd Z = null_space(JF);
      if (Z.cols() == 0) break;
      const Eigen::VectorXd rg = Z.transpose() * gF;
      if (std::getenv("FABKIT_DEBUG_SOLVE")) {
        std::fprintf(stderr, "iter %d E=%.12g |rg|=%.3g free=%zu Z=%ld\n", it, cur.energy, rg.size() ? rg.cwiseAbs().maxCoeff() : 0.0, free.size(), (long)Z.cols());
      }
      if (rg.cwiseAbs().maxCoeff() < kGradTol) break;  // equilibrium
      const Eigen::VectorXd lam = multipliers(cur, free);
      Eigen::MatrixXd H = Z.transpose() * lagrangian_hessian(cur, free, lam) * Z;
      H = 0.5 * (H + H.transpose());
      Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(H);
      const double floor = std::max(1e-10, 1e-8 * eig.eigenvalues().cwiseAbs().maxCoeff());
      Eigen::VectorXd ev = eig.eigenvalues().cwiseAbs().cwiseMax(floor);
      const Eigen::VectorXd p =
          -eig.eigenvectors() * (eig.eigenvectors().transpose() * rg).cwiseQuotient(ev);
      Eigen::VectorXd d = Eigen::VectorXd::Zero(n_);
      const Eigen::VectorXd dF = Z * p;
      for (std::size_t i = 0; i < free.size(); ++i) d[free[i]] = dF[static_cast<int>(i)];
      // Backtracking on the energy; every trial is projected back onto the constraints.
      bool moved = false;
      const double slope = cur.g.dot(d);
      for (double alpha = 1.0; alpha > 1e-10; alpha *= 0.5) {
        Point trial = evaluate((cur.z + alpha * d).cwiseMax(lo_).cwiseMin(hi_), free);
        if (!project(trial)) continue;
        if (trial.energy <= cur.energy + 1e-4 * alpha * std::min(slope, 0.0)) {
          moved = trial.energy < cur.energy;
          cur = std::move(trial);
          break;
        }
      }
      if (!moved) break;  // no further decrease within round-off
    }
    out.converged = it < max_iterations;
    Eigen::VectorXd zf = cur.z;
    std::vector<double> zv(zf.data(), zf.data() + zf.size());
    from_z(vars_, zv, out.x);
    return out;
  }

  /// The verdict at `x`: the equilibrium residual (largest slope of the potential along
  /// directions the constraints and bounds allow, mm of mean height per mm or degree of
  /// motion) and every OPEN parameter at its bound that the potential pulls further out.
  StabilityReport stability(const std::vector<double>& x, double fall_threshold) {
    StabilityReport report;
    const Assembly& a = *problem_.assembly;
    Eigen::VectorXd z = Eigen::Map<const Eigen::VectorXd>(to_z(vars_, x).data(), n_);
    const Point p = evaluate(z.cwiseMax(lo_).cwiseMin(hi_), {});
    const std::vector<int> off = all_free(p);  // coordinates not at a bound
    const Eigen::VectorXd lambda = multipliers(p, off);
    const Eigen::VectorXd reduced = lambda.size() ? Eigen::VectorXd(p.g - p.J.transpose() * lambda) : p.g;
    std::vector<int> free = off;
    for (int k = 0; k < n_; ++k) {
      const int side = at_bound(p.z, k);
      if (side != 0 && side * reduced[k] > kGradTol) free.push_back(k);
    }
    std::sort(free.begin(), free.end());
    const Eigen::MatrixXd Z = null_space(columns(p.J, free));
    if (Z.cols() > 0) report.equilibrium_residual = (Z.transpose() * rows(p.g, free)).cwiseAbs().maxCoeff();

    const Eigen::MatrixXd J_off = columns(p.J, off);
    for (int k = 0; k < n_; ++k) {
      const int side = at_bound(p.z, k);
      if (side == 0) continue;
      const int index = vars_.index[static_cast<std::size_t>(k)];
      const ParamSpec& spec = a.parameters()[static_cast<std::size_t>(index)].spec;
      if (!(side < 0 ? spec.open_at_lo : spec.open_at_hi)) continue;
      // Move k outwards by one unit; the coordinates off their bounds follow so the cycles stay
      // closed (minimum-norm correction). If they cannot, the move is blocked.
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
  static constexpr double kGradTol = 1e-9;    // mm of mean height per mm of motion
  static constexpr double kFeasTol = 1e-10;   // closure residual (mm, degrees)

  int at_bound(const Eigen::VectorXd& z, int k) const {
    const double tol = 1e-9 * std::max(1.0, hi_[k] - lo_[k]);
    if (std::isfinite(lo_[k]) && z[k] <= lo_[k] + tol) return -1;
    if (std::isfinite(hi_[k]) && z[k] >= hi_[k] - tol) return +1;
    return 0;
  }

  std::vector<int> all_free(const Point& p) const {
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

  // Orthonormal basis of the null space of m (columns); all of R^n if m has no rows.
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
    const Eigen::MatrixXd JF = columns(p.J, free);
    const Eigen::VectorXd gF = rows(p.g, free);
    return JF.transpose().completeOrthogonalDecomposition().solve(gF);
  }

  Point evaluate(const Eigen::VectorXd& z, const std::vector<int>& /*free*/) {
    Point p;
    p.z = z;
    eval_.evaluate(z.data());
    const int m = eval_.equalities();
    std::vector<int> active_ineq;
    for (int i = 0; i < eval_.inequalities(); ++i) {
      if (eval_.value(1 + m + i) > -1e-6) active_ineq.push_back(1 + m + i);
    }
    const int rows_total = m + static_cast<int>(active_ineq.size());
    p.energy = eval_.value(0);
    p.g.resize(n_);
    p.h.resize(rows_total);
    p.J.resize(rows_total, n_);
    for (int k = 0; k < n_; ++k) p.g[k] = eval_.gradient(0, k);
    for (int r = 0; r < rows_total; ++r) {
      const int row = r < m ? 1 + r : active_ineq[static_cast<std::size_t>(r - m)];
      // Inequalities enter as equalities only while active; a satisfied one contributes 0.
      p.h[r] = r < m ? eval_.value(row) : std::max(0.0, eval_.value(row));
      for (int k = 0; k < n_; ++k) p.J(r, k) = eval_.gradient(row, k);
    }
    return p;
  }

  // Minimum-norm Gauss-Newton back onto h = 0, moving only coordinates off their bounds.
  bool project(Point& p) {
    for (int iter = 0; iter < 30; ++iter) {
      if (p.h.size() == 0 || p.h.cwiseAbs().maxCoeff() < kFeasTol) return true;
      const std::vector<int> free = all_free(p);
      if (free.empty()) return false;
      const Eigen::MatrixXd JF = columns(p.J, free);
      const Eigen::VectorXd step = JF.completeOrthogonalDecomposition().solve(-p.h);
      Eigen::VectorXd z = p.z;
      for (std::size_t i = 0; i < free.size(); ++i) z[free[i]] += step[static_cast<int>(i)];
      const double before = p.h.norm();
      p = evaluate(z.cwiseMax(lo_).cwiseMin(hi_), free);
      if (p.h.norm() > before && iter > 3) return false;
    }
    return p.h.size() == 0 || p.h.cwiseAbs().maxCoeff() < 1e-7;
  }

  // Hessian of E - λᵀh on the free coordinates, by central differences of the exact
  // gradients.
  Eigen::MatrixXd lagrangian_hessian(const Point& p, const std::vector<int>& free,
                                     const Eigen::VectorXd& lambda) {
    const int nf = static_cast<int>(free.size());
    Eigen::MatrixXd H(nf, nf);
    auto grad_l = [&](const Eigen::VectorXd& z) {
      const Point q = evaluate(z, free);
      Eigen::VectorXd gl = q.g;
      if (lambda.size() && q.J.rows() >= lambda.size()) {
        gl -= q.J.topRows(lambda.size()).transpose() * lambda;
      }
      return rows(gl, free);
    };
    for (int i = 0; i < nf; ++i) {
      const double eps = 1e-5 * std::max(1.0, std::abs(p.z[free[static_cast<std::size_t>(i)]]));
      Eigen::VectorXd zp = p.z, zm = p.z;
      zp[free[static_cast<std::size_t>(i)]] += eps;
      zm[free[static_cast<std::size_t>(i)]] -= eps;
      H.col(i) = (grad_l(zp) - grad_l(zm)) / (2 * eps);
    }
    return H;
  }

  const Problem& problem_;
  const Variables& vars_;
  PhysicsEvaluator eval_;
  int n_;
  Eigen::VectorXd lo_, hi_;
};

Step2Result run_step2(const Problem& p,
                      const Variables& vars,
                      const std::vector<double>& x1,
                      const SolveOptions& o) {
  if (vars.index.empty() || p.total_mass <= 0) {
    Step2Result out;
    out.x = x1;
    return out;
  }
  Relaxation relaxation(p, vars, x1);
  return relaxation.run(x1, o.max_iterations);
}

// ---- stability ----------------------------------------------------------------------------

StabilityReport check_stability(const Problem& p,
                                const Variables& vars,
                                const std::vector<double>& x,
                                const SolveOptions& o) {
  if (vars.index.empty() || p.total_mass <= 0) return {};
  Relaxation relaxation(p, vars, x);
  return relaxation.stability(x, o.fall_threshold);
}

}  // namespace

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
    result.diagnostics.error(DiagnosticCode::kNoEnvironment, "solve: the assembly is empty");
    return result;
  }
  if (!problem.target) {
    result.termination = Termination::kNoTarget;
    result.diagnostics.warning(DiagnosticCode::kTargetMissing,
                               assembly.target() ? "the target is not connected to the hack; "
                                                   "step 1 is skipped"
                                                 : "the design has no target (end_with); step 1 "
                                                   "is skipped");
  }
  // The starting point must be a closed configuration (connect verified it).
  if (max_gap(assembly, assembly.values()) > 1e-3) {
    result.termination = Termination::kInfeasible;
    result.message = "the cycles of the assembly are not closed";
    result.diagnostics.error(DiagnosticCode::kCycleNotClosable,
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
    result.diagnostics.error(DiagnosticCode::kCycleNotClosable, result.message);
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
    Step2Result step2 = run_step2(problem, vars, step1.x, options);
    x = step2.x;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (assembly.parameters()[i].spec.tag == ParamTag::kUnbounded) x[i] = wrap_360(x[i]);
    }
    if (!polish_closures(assembly, x, options)) {
      result.diagnostics.warning(DiagnosticCode::kCycleNotClosable,
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
  s += fmt::format(
      "  {:<28}{:.2e} mm per unit parameter\n", "equilibrium residual", equilibrium_residual);
  for (const Slip& slip : slips) s += fmt::format("  {:<28}{}\n", "slips", slip.message);
  for (const std::string& n : stability_notes) s += fmt::format("  {:<28}{}\n", "note", n);
  std::string times;
  for (const StageTiming& t : timings)
    times += fmt::format("{} {:.1f} ms  ", t.stage, t.milliseconds);
  s += fmt::format("  {:<28}{}\n", "time", times);
  return s;
}

}  // namespace fabkit::hacks

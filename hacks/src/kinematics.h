#pragma once
// The kinematics both solve steps work on: which parameters move (scaled to ≈ mm of motion),
// the rows (target residuals or the potential, cycle closures, spacing inequalities), and
// their exact Jacobian from the kinematic tree's twists.

#include <algorithm>
#include <array>
#include <optional>
#include <vector>

#include "constraints.h"
#include "contacts.h"
#include "cycle_closure.h"
#include "fabkit/core/solvers/manifold_solver.h"
#include "fabkit/hacks/assembly.h"
#include "target.h"
#include "tolerances.h"

namespace fabkit::hacks::detail {

/// The twists (angular w[j], linear v[j]) dL/dq_j · L⁻¹ of the local connector transform L(q)
/// of `prim`, in primitive coordinates, for every j < connector_dof(prim.connector_kind()),
/// in one forward-mode pass (kinematics.cpp).
void local_connector_twists(const Primitive& prim, const double* q, Vec3* w, Vec3* v);

/// Everything about an assembly that the solve steps share.
struct Problem {
  const Assembly* assembly;
  std::optional<TargetModel> target;
  std::vector<ConnectionId> closures;
  std::vector<std::optional<Vec3>> free_axes;
  std::vector<MultiConnectionPair> multi;
  std::vector<double> masses;  // per part; 0 for environments and parts of other groups
  std::vector<Vec3> coms;      // per part, in part coordinates
  double total_mass = 0;
  /// The movable group this problem covers (KinematicGraph::movable_groups), -1 for all.
  /// Groups hang from fixed parts independently, so each is solved on its own.
  int group = -1;
  std::vector<int> part_group;  // per part; -1 for environments
  /// Assembly::parameter_keys(), once per problem: they seed every random start.
  std::shared_ptr<const std::vector<std::string>> parameter_keys;
  /// Contacts: every part's collision body (shared by the problems of one solve) and the piece
  /// pairs kept apart, one inequality row each (−distance ≤ 0). None: parts may overlap.
  std::shared_ptr<const ContactModel> contacts;
  std::vector<PiecePair> watched;
  /// The solve's deadline, shared by its problems: a step that could not finish before it
  /// calls it, and every later step sees it. None: only SolveOptions::deadline is looked at.
  std::shared_ptr<const StopClock> stop;
  /// Step 2's tries at unfolding (step2.cpp) left to the relaxations of this problem and its
  /// copies (one group's candidates share them). None: each relaxation gets its own.
  std::shared_ptr<int> unfold_tries;
  /// Set once a relaxation of this problem or a copy (one group's candidates share it) came to
  /// rest against an environment only with its contact rows: the next ones watch contacts from
  /// the start instead of first running without them (avoiding_contacts). None: never.
  std::shared_ptr<bool> contacts_first;
  /// Whether connection `c` moves parts of this problem's group.
  bool covers(const Assembly& a, ConnectionId c) const;
};

/// The problem of the whole assembly (group -1) or of one movable group.
Problem make_problem(const Assembly& a, int group = -1);
/// The number of movable groups.
int group_count(const Assembly& a);

// Maps the optimiser's variables into the full parameter vector.
struct Variables {
  std::vector<int> index;     // into x
  std::vector<double> scale;  // x = z * scale (z in ≈ mm of motion)
};

/// The parameters that may move: all but constants; with `physics`, also not those pinned
/// under gravity (clip jaws, fixed joints, surface contacts).
Variables select_variables(const Assembly& a, bool physics, const Problem* only = nullptr);

template <class T>
std::vector<T> expand(const Variables& v, const std::vector<double>& base, const T* z) {
  std::vector<T> x(base.size());
  for (std::size_t i = 0; i < base.size(); ++i) x[i] = T(base[i]);
  for (std::size_t k = 0; k < v.index.size(); ++k) {
    x[static_cast<std::size_t>(v.index[k])] = z[k] * T(v.scale[k]);
  }
  return x;
}

std::vector<double> to_z(const Variables& v, const std::vector<double>& x);
void from_z(const Variables& v, const std::vector<double>& z, std::vector<double>& x);
/// The potential at x of the parts p weighs (a group's, or the whole assembly's): Σ m·z of
/// their centres of mass (mass units · mm).
double group_energy(const Problem& p, const std::vector<double>& x);
/// Largest closure gap at x (mm; degrees in *deg).
double max_gap(const Assembly& a, const std::vector<double>& x, double* deg = nullptr);

enum class Objective {
  kTarget,  ///< step 1: the target's pose residuals (least squares)
  kEnergy,  ///< step 2: the mean height of the centres of mass (mm)
  /// Between the steps: the mean height, with the target held where the problem's target
  /// goal is (its pose residuals join the equalities): the rest of the hack settles as it
  /// would while a hand holds the target where step 1 put it.
  kEnergyHoldingTarget,
};

// [objective rows..., closure equalities..., multi-connection inequalities (≤ 0)...],
// differentiated automatically.
struct ManifoldCost {
  const Problem* problem;
  const Variables* vars;
  std::vector<double> base;
  Objective objective;

  int objective_count() const { return objective == Objective::kTarget ? kTargetResiduals : 1; }
  bool holds_target() const { return objective == Objective::kEnergyHoldingTarget; }
  int closure_equality_count() const {
    int n = 0;
    for (const auto& axis : problem->free_axes) n += axis ? 5 : 6;
    return n;
  }
  int equality_count() const {
    return closure_equality_count() + (holds_target() ? kTargetResiduals : 0);
  }
  int contact_row() const {
    return objective_count() + equality_count() + static_cast<int>(problem->multi.size());
  }
  // The contact rows come last; the analytic evaluator fills them (FCL, not templated).
  int residual_count() const { return contact_row() + static_cast<int>(problem->watched.size()); }

  template <class T>
  bool operator()(T const* const* params, T* out) const {
    const std::vector<T> x = expand<T>(*vars, base, params[0]);
    fill<T>(x, problem->assembly->all_part_frames<T>(x.data()), out);
    return true;
  }

  /// The rows at parameters x whose part frames are `frames` (contact rows excluded).
  template <class T>
  void fill(const std::vector<T>& x, const std::vector<Rigid<T>>& frames, T* out) const {
    const Assembly& a = *problem->assembly;
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
    if (holds_target()) {
      target_residuals<T>(
          *problem->target, frames[static_cast<std::size_t>(problem->target->part.value)], eq);
      eq += kTargetResiduals;
    }
    for (const MultiConnectionPair& m : problem->multi) {
      *eq++ = -multi_connection_value<T>(m, x.data());
    }
  }
};

// Values and exact Jacobian of ManifoldCost from the kinematic tree's structure: a parameter
// of a tree connection turns the whole subtree below it by a twist (screw motion) computed
// from its connector's local derivative; every row's derivative follows from the twists of
// the frames it reads. One pass over the parameters instead of automatic differentiation
// through every frame: the same numbers (checked against ManifoldEvaluator in the tests) at a
// fraction of the cost on long chains.
class AnalyticEvaluator : public solvers::ManifoldProblem {
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
    moving_ = a.parts_moved_by(v.index);
    fixed_frames_ = a.all_part_frames<double>(base_.data());
    // Parts below each tree connection (the child and its descendants).
    below_.resize(a.connections().size());
    is_below_.assign(a.connections().size(), std::vector<char>(a.nodes().size(), 0));
    for (int q = 0; q < a.part_count(); ++q) {
      PartId id{q};
      while (a.parent(id).valid()) {
        below_[static_cast<std::size_t>(a.parent(id).value)].push_back(q);
        is_below_[static_cast<std::size_t>(a.parent(id).value)][static_cast<std::size_t>(q)] = 1;
        id = a.connection(a.parent(id)).first.part;
      }
    }
    // The part just below each tree connection.
    child_.assign(a.connections().size(), -1);
    for (int q = 0; q < a.part_count(); ++q) {
      const ConnectionId up = a.parent(PartId{q});
      if (up.valid()) child_[up.index()] = q;
    }
    // The share of the total mass below each tree connection.
    mass_below_.assign(a.connections().size(), 0.0);
    for (std::size_t c = 0; c < below_.size(); ++c) {
      for (int q : below_[c]) mass_below_[c] += p.masses[static_cast<std::size_t>(q)];
      if (p.total_mass > 0) mass_below_[c] /= p.total_mass;
    }
    twists_ready_.assign(2 * a.connections().size(), 0);
    twist_w_.assign(2 * a.connections().size(), {});
    twist_v_.assign(2 * a.connections().size(), {});
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

  int variables() const override { return n_; }
  int objectives() const override { return cost_.objective_count(); }
  int equalities() const override { return cost_.equality_count(); }
  int inequalities() const override { return rows_ - objectives() - equalities(); }
  /// Contact rows (the last inequalities) are flat where they bind: see ManifoldProblem.
  bool flat_inequality(int i) const override {
    return i >= static_cast<int>(problem_.multi.size());
  }
  /// The turns on the two sides of a tree connection about one axis (a flexible hook's φ on
  /// another's): the part frames depend on one combination of them (kinematics.cpp).
  std::vector<GaugePair> gauge_pairs() const override;
  /// The closures' minimal orientation residuals also vanish at a half turn: refuse those.
  bool acceptable(const double* z) override {
    if (problem_.closures.empty()) return true;
    const std::vector<double> x = expand<double>(vars_, base_, z);
    for (const ClosureGap& g : closure_gaps(*problem_.assembly, x)) {
      if (g.rotation_deg > kHalfTurnCheckDeg) return false;
    }
    return true;
  }

  void evaluate(const double* z, double* values, double* jacobian) override {
    evaluate(z);
    std::copy(values_.begin(), values_.end(), values);
    std::copy(jacobian_.begin(), jacobian_.end(), jacobian);
  }
  /// The values alone (a trial step the solver may reject); the Jacobian at the same z, if
  /// asked next, reuses them and their distance queries.
  void evaluate_values(const double* z, double* values) override {
    evaluate(z, /*contacts=*/true, /*jacobian=*/false);
    std::copy(values_.begin(), values_.end(), values);
  }
  /// Without the contact rows (flat, so a differenced Hessian does not read them): their
  /// distance queries were half of a differenced Hessian's cost on the diaper caddy.
  void evaluate_slopes(const double* z, double* values, double* jacobian) override {
    evaluate(z, /*contacts=*/false);
    std::copy(values_.begin(), values_.end(), values);
    std::copy(jacobian_.begin(), jacobian_.end(), jacobian);
  }

  /// Values and (with `jacobian`) the Jacobian at z into values_ and jacobian_; without
  /// `contacts` the contact rows are left 0.
  void evaluate(const double* z, bool contacts = true, bool jacobian = true) {
    const bool same_values = !values_.empty() && std::equal(z, z + n_, last_.begin()) &&
                             (last_has_contacts_ || !contacts);
    if (same_values && (last_has_jacobian_ || !jacobian)) return;
    if (!same_values) fill_values(z, contacts);
    if (jacobian) fill_jacobian();
  }

  /// The rows' values at z, and what their Jacobian needs of the point (x, frames, the near
  /// pairs' distance queries) for fill_jacobian().
  void fill_values(const double* z, bool contacts) {
    last_.assign(z, z + n_);
    last_has_contacts_ = contacts;
    last_has_jacobian_ = false;
    const Assembly& a = *problem_.assembly;
    x_ = expand<double>(vars_, base_, z);
    values_.assign(static_cast<std::size_t>(rows_), 0.0);
    frames_ = a.all_part_frames<double>(x_.data(), moving_, fixed_frames_);
    cost_.fill<double>(x_, frames_, values_.data());
    // Contact rows: −signed distance of each watched pair. A row binds only within
    // kInequalityMargin of touching, and only binding rows are read (their values, slopes and
    // multipliers), so a pair whose bounds put it farther apart than kApart needs no exact
    // query: its row gets the bound, as far from binding as its distance is. First their
    // boxes, then the pieces along the line of their centres.
    constexpr double kApart = 1000 * kInequalityMargin;
    near_.clear();
    if (contacts && !problem_.watched.empty()) {
      std::vector<Mat4> mats;
      mats.reserve(frames_.size());
      for (const Rigid<double>& f : frames_) mats.push_back(f.matrix());
      const int first = cost_.contact_row();
      for (std::size_t i = 0; i < problem_.watched.size(); ++i) {
        const PiecePair& w = problem_.watched[i];
        const std::size_t row = static_cast<std::size_t>(first) + i;
        double gap = problem_.contacts->gap_bound(w, mats);
        if (gap <= kApart) gap = std::max(gap, problem_.contacts->distance_bounds(w, mats).lower);
        if (gap > kApart) {
          values_[row] = -gap;
          continue;
        }
        const collision::Proximity at = problem_.contacts->distance(w, mats);
        values_[row] = -at.distance;
        near_.push_back({row, i, at});
      }
    }
  }

  /// The Jacobian at the point fill_values() last evaluated.
  void fill_jacobian() {
    last_has_jacobian_ = true;
    const Assembly& a = *problem_.assembly;
    const std::vector<double>& x = x_;
    const std::vector<Rigid<double>>& frames = frames_;
    jacobian_.assign(static_cast<std::size_t>(rows_ * n_), 0.0);
    // What hangs below each tree connection, for the potential's slope.
    std::vector<Vec3> weighted_below;
    if (objective_ != Objective::kTarget) weighted_below = weighted_centres_below(frames);
    // Local twists of each connector side, computed once per side (all its parameters in one
    // pass) when its first variable needs them.
    std::fill(twists_ready_.begin(), twists_ready_.end(), 0);

    // Closure frames, once.
    std::vector<ClosureFrames> cf;
    for (std::size_t i = 0; i < problem_.closures.size(); ++i) {
      const auto [f1, f2] = a.connection_frames<double>(problem_.closures[i], frames, x.data());
      const Connection& conn = a.connection(problem_.closures[i]);
      cf.push_back({f1, f2, conn.first.part.value, conn.second.part.value, Mat3::Zero()});
      // The orientation rows are linear in dw = w₂ − w₁ (they read R₁ᵀ[dw]×R₂): their map,
      // column by column, once per evaluation instead of two 3×3 products per parameter.
      for (int e = 0; e < 3; ++e) {
        cf.back().orientation.col(e) = orientation_derivative(i, f1, f2, Vec3::Unit(e));
      }
    }
    const int no = cost_.objective_count();
    const std::vector<Near>& near = near_;
    std::optional<Rigid<double>> target_frame;
    // Where the target's rows are: the objective (step 1) or after the closures (held).
    const int target_row =
        objective_ == Objective::kTarget ? 0 : no + cost_.closure_equality_count();
    if (objective_ != Objective::kEnergy) {
      target_frame =
          frames[static_cast<std::size_t>(problem_.target->part.value)].then(problem_.target->base);
    }

    // Contact rows are filled after the loop over parameters, row by row (a long chain has
    // thousands of them: written column by column, every entry was a cache miss); each
    // parameter's twist and what it moves are kept for them.
    std::vector<Twist> contact_tau;
    std::vector<const std::vector<char>*> contact_below;
    if (!near.empty()) {
      contact_tau.resize(static_cast<std::size_t>(n_));
      contact_below.assign(static_cast<std::size_t>(n_), nullptr);
    }
    for (int k = 0; k < n_; ++k) {
      const Slot& slot = slots_[static_cast<std::size_t>(k)];
      const Connection& c = a.connections()[static_cast<std::size_t>(slot.connection)];
      const Connector& side = slot.first ? c.first : c.second;
      const Primitive& prim = a.node(side.part).part->primitive(side.primitive);
      // Local derivative of the connector transform L(q) (primitive coordinates).
      const std::size_t side_id =
          2 * static_cast<std::size_t>(slot.connection) + (slot.first ? 0 : 1);
      if (!twists_ready_[side_id]) {
        local_connector_twists(
            prim, x.data() + side.offset, twist_w_[side_id].data(), twist_v_[side_id].data());
        twists_ready_[side_id] = 1;
      }
      const Twist local{twist_w_[side_id][static_cast<std::size_t>(slot.local)],
                        twist_v_[side_id][static_cast<std::size_t>(slot.local)]};
      const Rigid<double>& owner = frames[side.part.index()];
      // World twist of the moving frame: the connector frame on this side.
      const Twist spatial = adjoint(owner.then(side.base), local);
      auto put = [&](int row, double v) {
        jacobian_[static_cast<std::size_t>(row * n_ + k)] = v * slot.scale;
      };
      if (!c.closes_cycle) {
        // Tree connection: the child and everything below it turn by ±spatial.
        const Twist tau = slot.first ? spatial : -spatial;
        const std::vector<char>& below = is_below_[static_cast<std::size_t>(slot.connection)];
        auto moves = [&](int part) { return below[static_cast<std::size_t>(part)] != 0; };
        // Objective rows: the mean height moves by τ's velocity at the weighted centre of
        // mass below (w × Σ mᵢcᵢ + v Σ mᵢ, over the total mass).
        if (objective_ != Objective::kTarget) {
          const auto c_index = static_cast<std::size_t>(slot.connection);
          put(0, (tau.w.cross(weighted_below[c_index]) + tau.v * mass_below_[c_index]).z());
        }
        if (target_frame && moves(problem_.target->part.value)) {
          target_derivative(
              *target_frame, tau, [&](int row, double v) { put(target_row + row, v); });
        }
        // Closure rows.
        int row = no;
        for (std::size_t i = 0; i < cf.size(); ++i) {
          const Twist t1 = moves(cf[i].part1) ? tau : Twist{};
          const Twist t2 = moves(cf[i].part2) ? tau : Twist{};
          row = closure_derivative(i, cf[i], t1, t2, row, put);
        }
        if (!near.empty()) {
          contact_tau[static_cast<std::size_t>(k)] = tau;
          contact_below[static_cast<std::size_t>(k)] = &below;
        }
      } else {
        // A cycle-closing connection's own parameter moves only its connector frame.
        int row = no;
        for (std::size_t i = 0; i < cf.size(); ++i) {
          const bool mine = problem_.closures[i].value == slot.connection;
          const Twist t1 = mine && slot.first ? spatial : Twist{};
          const Twist t2 = mine && !slot.first ? spatial : Twist{};
          row = closure_derivative(i, cf[i], t1, t2, row, put);
        }
      }
    }
    // Contact rows: d(−distance) = −n·(v_b(p_b) − v_a(p_a)), for the tree parameters.
    for (const Near& touch : near) {
      const PiecePair& w = problem_.watched[touch.pair];
      double* row = jacobian_.data() + touch.row * static_cast<std::size_t>(n_);
      for (int k = 0; k < n_; ++k) {
        const std::vector<char>* below = contact_below[static_cast<std::size_t>(k)];
        if (!below) continue;
        const Twist& tau = contact_tau[static_cast<std::size_t>(k)];
        const Vec3 va = (*below)[static_cast<std::size_t>(w.part_a)] != 0
                            ? tau.velocity(touch.at.point_a)
                            : Vec3::Zero();
        const Vec3 vb = (*below)[static_cast<std::size_t>(w.part_b)] != 0
                            ? tau.velocity(touch.at.point_b)
                            : Vec3::Zero();
        row[k] = -touch.at.normal.dot(vb - va) * slots_[static_cast<std::size_t>(k)].scale;
      }
    }
    // Spacing rows depend on the t parameters directly: row = -(Σ |Δt|·L - need).
    int row = no + cost_.equality_count();
    for (const MultiConnectionPair& m : problem_.multi) {
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

  double value(int row) const { return values_[static_cast<std::size_t>(row)]; }
  double gradient(int row, int col) const {
    return jacobian_[static_cast<std::size_t>(row * n_ + col)];
  }

  /// The Hessian of the Lagrangian of step 2's potential (kEnergy, kEnergyHoldingTarget), or
  /// of step 1's ½‖r‖² (kTarget: JᵀJ + Σ rᵢ∇²rᵢ, for the Newton finish of its fits), in the
  /// scaled variables, from the tree's twists (kinematics.cpp): O(n²) products instead of the
  /// n evaluations of a finite-difference Hessian. Curving rows may be the held target's (and
  /// the spacing rows, piecewise linear); false for closure rows.
  bool lagrangian_hessian(const double* z,
                          const std::vector<int>& rows,
                          const Eigen::VectorXd& lambda,
                          Eigen::MatrixXd& hessian) override {
    // Inline, like every other virtual here: an out-of-line one becomes the class's key
    // function, and the solve measured 10–25 % slower with the vtable in one file.
    return exact_lagrangian_hessian(z, rows, lambda, hessian);
  }
  bool exact_lagrangian_hessian(const double* z,
                                const std::vector<int>& rows,
                                const Eigen::VectorXd& lambda,
                                Eigen::MatrixXd& hessian);

 private:
  // Velocity field of a rigid motion: v(p) = w × p + v0 (world coordinates).
  struct Twist {
    Vec3 w = Vec3::Zero();
    Vec3 v = Vec3::Zero();
    Vec3 velocity(const Vec3& p) const { return w.cross(p) + v; }
    Twist operator-() const { return {-w, -v}; }
    Twist operator+(const Twist& o) const { return {w + o.w, v + o.v}; }
    Twist operator*(double s) const { return {w * s, v * s}; }
    /// How this field changes when the body carrying it moves by `by`: the Lie bracket
    /// [by, this] of spatial twists.
    Twist moved_by(const Twist& by) const { return {by.w.cross(w), by.w.cross(v) - w.cross(by.v)}; }
  };

  struct Slot {
    int connection = 0;
    bool first = true;
    int offset = 0;
    int local = 0;
    double scale = 1;
  };

  // The mass-weighted centre of mass below each tree connection (over the total mass, zero
  // below a closing connection), summed child to parent: parents precede children.
  std::vector<Vec3> weighted_centres_below(const std::vector<Rigid<double>>& frames) const {
    const Assembly& a = *problem_.assembly;
    std::vector<Vec3> subtree(frames.size(), Vec3::Zero());
    for (std::size_t q = frames.size(); q-- > 0;) {
      const double m = problem_.masses[q];
      if (m != 0) {
        subtree[q] += m / problem_.total_mass * (frames[q].R * problem_.coms[q] + frames[q].t);
      }
      const ConnectionId up = a.parent(PartId{static_cast<int>(q)});
      if (up.valid()) subtree[a.connection(up).first.part.index()] += subtree[q];
    }
    std::vector<Vec3> below(child_.size(), Vec3::Zero());
    for (std::size_t c = 0; c < child_.size(); ++c) {
      if (child_[c] >= 0) below[c] = subtree[static_cast<std::size_t>(child_[c])];
    }
    return below;
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
      for (int r = 0; r < 3; ++r) put(k++, dr(r, c) * kRotationResidualScale);
    }
  }

  // A closure's connector frames at the point being evaluated, and the orientation rows'
  // derivative with respect to dw = w₂ − w₁ (2 or 3 rows used).
  struct ClosureFrames {
    Rigid<double> f1, f2;
    int part1, part2;
    Mat3 orientation;
  };

  // The orientation rows' change when the second frame turns by dw relative to the first:
  // d(R₁ᵀR₂) = R₁ᵀ[dw]×R₂.
  Vec3 orientation_derivative(std::size_t i,
                              const Rigid<double>& f1,
                              const Rigid<double>& f2,
                              const Vec3& dw) const {
    Mat3 skew;
    skew << 0, -dw.z(), dw.y(), dw.z(), 0, -dw.x(), -dw.y(), dw.x(), 0;
    const Mat3 drel = f1.R.transpose() * skew * f2.R;
    if (problem_.free_axes[i]) {
      const Vec3 axis = *problem_.free_axes[i];
      const Vec3 b = axis.unitOrthogonal();
      const Vec3 d = axis.cross(b);
      const Vec3 dturned = drel * axis;
      return Vec3(dturned.dot(b) * kRadToDeg, dturned.dot(d) * kRadToDeg, 0);
    }
    return Vec3((drel(2, 1) - drel(1, 2)) * 0.5 * kRadToDeg,
                (drel(0, 2) - drel(2, 0)) * 0.5 * kRadToDeg,
                (drel(1, 0) - drel(0, 1)) * 0.5 * kRadToDeg);
  }

  template <class Put>
  int closure_derivative(std::size_t i,
                         const ClosureFrames& c,
                         const Twist& t1,
                         const Twist& t2,
                         int row,
                         Put put) const {
    const Vec3 dp = t1.velocity(c.f1.t) - t2.velocity(c.f2.t);
    for (int a = 0; a < 3; ++a) put(row++, dp[a]);
    const Vec3 orientation = c.orientation * (t2.w - t1.w);
    const int rows = problem_.free_axes[i] ? 2 : 3;
    for (int a = 0; a < rows; ++a) put(row++, orientation[a]);
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
  std::vector<std::vector<char>> is_below_;  // [connection][part]: part is below it
  std::vector<double> mass_below_;           // [connection]: share of the total mass below it
  std::vector<int> child_;                   // [connection]: the part just below it, or -1
  // Parts the variables move, and every part's frame at base_ (the others stay there).
  std::vector<char> moving_;
  std::vector<Rigid<double>> fixed_frames_;
  std::vector<Slot> slots_;
  std::vector<double> last_, values_, jacobian_;
  bool last_has_contacts_ = false;  // whether values_ and jacobian_ at last_ have the contact rows
  bool last_has_jacobian_ = false;  // whether jacobian_ is at last_ (or only values_)
  // The point fill_values() evaluated last, for fill_jacobian(): the full parameter vector,
  // every part's frame, and the near pairs' distance queries (row, watched pair, query).
  struct Near {
    std::size_t row;
    std::size_t pair;
    collision::Proximity at;
  };
  std::vector<double> x_;
  std::vector<Rigid<double>> frames_;
  std::vector<Near> near_;
  // Per connector side (2 per connection): its local twists at the point being evaluated.
  std::vector<char> twists_ready_;
  std::vector<std::array<Vec3, 3>> twist_w_, twist_v_;
};

/// The scaled variables of `vars` for x, and their bounds (±∞ for unbounded angles).
Eigen::VectorXd scaled(const Variables& vars, const std::vector<double>& x);
void scaled_bounds(const Assembly& a,
                   const Variables& vars,
                   Eigen::VectorXd& lo,
                   Eigen::VectorXd& hi);

}  // namespace fabkit::hacks::detail

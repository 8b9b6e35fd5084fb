#pragma once
/// Structure-preserving manipulation (paper §4.2): dragging control j of a node solves
///
///   q* = argmin ‖cⱼᵀq − (cⱼᵀq_cur + δ)‖² + α‖q − q_cur‖²   s.t.  A·q = b,  G·q ≤ h
///
/// with A·q = b, G·q ≤ h the template's relations (plus anchors that keep the model where it is:
/// the root's centre in x and y and its bottom on the floor). The α term acts on principal
/// elements; connecting elements follow their soft placement relations instead (§3.2). The
/// equality part is eliminated once per drag session (an orthonormal null-space basis); each
/// step solves the reduced QP in closed form when no inequality binds, and with the QP solver
/// (NLopt SLSQP by default, Ipopt on request) on the binding rows otherwise.
///
///   Manipulator m(model);
///   Control width = m.control(model.find("shelf"), ControlKind::kSizeX);
///   if (!m.hidden(width)) {
///     DragResult r = m.set(width, 900);     // r.q: every relation holds; r.message if clipped
///     model.q = r.q;
///   }

#include <Eigen/Core>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/catalog.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates {

/// The six controls of a node's bounding box (paper Fig. 7: arrows translate, spheres scale).
enum class ControlKind { kCenterX, kCenterY, kCenterZ, kSizeX, kSizeY, kSizeZ };
/// "center_x", "center_y", "center_z", "size_x", "size_y", "size_z".
std::string_view to_string(ControlKind k);
std::optional<ControlKind> control_from_string(std::string_view s);

/// A control: cⱼᵀq is the centre or size of the node's bounding box along one axis (mm).
struct Control {
  NodeId node;
  ControlKind kind = ControlKind::kSizeX;
  std::vector<LinearTerm> c;  ///< cⱼ, sparse
  double value = 0;           ///< cⱼᵀq at the current parameters, mm
  bool hidden = false;        ///< fully constrained: cⱼ lies in the row space of A (hidden)
  int axis() const { return static_cast<int>(kind) % 3; }
  bool is_size() const { return static_cast<int>(kind) >= 3; }
};

/// Which QP solver handles inequality-constrained steps.
enum class QpSolver { kSlsqp, kIpopt };
std::string_view to_string(QpSolver s);

struct ManipulateOptions {
  /// The paper's α (< 1): how much every other principal parameter resists. Many parameters
  /// move together in a furniture template, so a step reaches about 1/(1 + α·k) of δ with k
  /// the parameters that follow; 0.01 keeps a 20-parameter drag above 80 %.
  double alpha = 0.01;
  double placement_weight = 1.0;  ///< weight of connecting elements' soft placement
  double set_weight = 1e3;        ///< target weight of set() (refined: reached when feasible)
  double tolerance_mm = 1e-10;    ///< constraint tolerance of the solution, mm
  bool anchor = true;             ///< keep the root's centre (x, y) and its bottom (z) fixed
  QpSolver solver = QpSolver::kSlsqp;
  /// Stop the inequality solver here (a check's deadline); what it returns then is not
  /// converged, so a projection cut short is not feasible.
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

/// The outcome of one drag or set.
struct DragResult {
  Eigen::VectorXd q;     ///< the new parameters (every hard relation holds)
  double requested = 0;  ///< cⱼᵀq asked for, mm
  double achieved = 0;   ///< cⱼᵀq reached, mm
  bool reached = false;  ///< achieved within 0.01 mm of requested (set) — or drag unclipped
  std::optional<RelationId> binding;  ///< the constraint that stopped it
  std::string message;       ///< "'shelf' cannot be lower than the top of 'slide' (305 mm)"
  bool used_solver = false;  ///< an inequality was active: the QP solver ran
  int solver_iterations = 0;
  double max_violation = 0;  ///< of the hard relations at q, mm
  double milliseconds = 0;
  Diagnostics diagnostics;  ///< constrained / fixed-control / solver-failed
};

/// Human words for a relation at parameters q ("'leg' cannot be longer than 3658 mm, ...").
std::string describe_relation(const Template& t,
                              const Relation& r,
                              const Eigen::VectorXd& q,
                              const ItemCatalog* catalog = nullptr,
                              NodeId moving = NodeId());

/// Drags a template's controls. Keeps the factorisation of A between steps of the same
/// control (a drag session), so each step costs a few small dense solves.
class Manipulator {
 public:
  explicit Manipulator(const Template& t,
                       ManipulateOptions options = {},
                       const ItemCatalog* catalog = nullptr);
  ~Manipulator();
  Manipulator(Manipulator&&) noexcept;
  Manipulator& operator=(Manipulator&&) noexcept;

  /// The control of `node` at the template's current q (hidden flag computed).
  Control control(NodeId node, ControlKind kind) const;
  /// All six, in ControlKind order.
  std::vector<Control> controls(NodeId node) const;
  /// Whether `c` is fully constrained (linearly dependent on the equality rows and anchors).
  bool hidden(const Control& c) const;

  /// Paper eq. 2: moves the control by `delta` mm from the template's current q.
  DragResult drag(const Control& c, double delta) const;
  /// Sets the control to `value` mm if any feasible shape has it, else the nearest feasible
  /// shape, with the binding constraint named.
  DragResult set(const Control& c, double value) const;

  const Template& model() const { return *template_; }
  const ManipulateOptions& options() const { return options_; }

  struct Impl;

 private:
  const Template* template_;
  ManipulateOptions options_;
  const ItemCatalog* catalog_;
  std::unique_ptr<Impl> impl_;
};

/// Hard-constrained least squares used by snapping and connecting (paper eqs. 3 and 4):
/// minimise Σ wᵢ (qᵢ − q_refᵢ)² + placement terms subject to the relations of `t` plus `extra`
/// (equalities and inequalities). Returns nullopt when the constraints cannot all hold (with
/// the largest violation in `violation`).
struct ProjectResult {
  Eigen::VectorXd q;
  double cost = 0;       ///< Σ wᵢ (qᵢ − q_refᵢ)², mm²
  double violation = 0;  ///< largest violated hard relation, mm (0 when feasible)
  bool feasible = false;
};
ProjectResult project_to_feasible(const Template& t,
                                  const Eigen::VectorXd& q_ref,
                                  const Eigen::VectorXd& weights,
                                  const std::vector<Relation>& extra = {},
                                  const ManipulateOptions& options = {});

}  // namespace fabkit::templates

#pragma once
/// Stability (paper §4.6): the model at rest on the floor. Connecting elements are left out as
/// bodies (their mass is negligible) but the joints they make are kept: principal elements
/// held together by a connection form one rigid body. Bodies touch each other and the floor
/// at contact rectangles; at each corner a contact force lies in a linearised friction cone
/// (a pyramid of `cone_edges` edges). The forces that best balance gravity and the user's loads
/// are found by a bound-constrained least-squares QP (the kit's QP solver); a body whose
/// forces and torques do not balance is unstable (drawn red), the others stable (green).
/// Differs from the paper (one step of staggered projections): the same contact and friction
/// model, solved as a static equilibrium instead of a dynamics step.

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/catalog.h"
#include "fabkit/templates/manipulate.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates {

/// A force on a part (a person leaning on the table, a push at the top of a shelf).
struct Load {
  ElementId element;
  Vec3 point = Vec3::Zero();  ///< mm, world frame
  Vec3 force = Vec3::Zero();  ///< N
};

struct StabilityOptions {
  double friction = 0.5;  ///< Coulomb coefficient at every contact (wood on wood 0.3–0.6)
  int cone_edges = 4;     ///< edges of the linearised friction cone (4 or 8)
  double contact_tolerance_mm = 0.5;
  double gravity = 9.81;  ///< m/s², along −z
  /// A body is unbalanced when its leftover force exceeds this fraction of its weight plus
  /// loads (or its torque, of weight × size).
  double imbalance = 1e-3;
  std::vector<Load> loads;
  /// The QP solver; unset: chosen by size as measured (docs/benchmarks.md): SLSQP up to
  /// `slsqp_up_to` friction-cone variables (0.4 ms at 64), Ipopt above (10 ms at 192, where
  /// SLSQP's quasi-Newton steps take 130 ms on this rank-deficient least squares).
  std::optional<QpSolver> solver;
  int slsqp_up_to = 96;
  /// Stop the contact-force QP at this time (a check's deadline); a verdict cut short says so.
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

/// One rigid body: principal elements joined by connections.
struct Body {
  std::vector<ElementId> elements;
  double mass_kg = 0;
  Vec3 center_of_mass = Vec3::Zero();  ///< mm
  bool anchored = false;               ///< held by the environment (screwed to a wall)
  bool stable = true;
  Vec3 unbalanced_force = Vec3::Zero();   ///< N, what the contacts cannot balance
  Vec3 unbalanced_torque = Vec3::Zero();  ///< N·m about the centre of mass
  std::string verdict;                    ///< "stable", "tips", "slides"
};

struct StabilityResult {
  bool stable = false;
  /// The contact-force QP was stopped by StabilityOptions::deadline: the verdict is unknown.
  bool timed_out = false;
  std::vector<Body> bodies;
  std::vector<char> element_stable;  ///< per element of the template (connecting: 1)
  int contacts = 0;                  ///< contact rectangles (floor included)
  int variables = 0;                 ///< friction-cone coefficients in the QP
  double milliseconds = 0;
  Diagnostics diagnostics;  ///< one unstable error per unstable body
};

/// Checks `t` at its current q. Masses come from the catalog (density × volume for cut goods,
/// the item's mass for hardware). The floor is the lowest principal element's bottom.
StabilityResult check_stability(const Template& t,
                                const ItemCatalog& catalog,
                                const StabilityOptions& options = {});

}  // namespace fabkit::templates

#pragma once
/// Snapping (paper §4.4): positions and sizes an added template so that it fits the working
/// model. First the coplanarities the template had with the parts it was joined to in its
/// source design are re-created against the K nearest parallel planes of the model (K^R least
/// squares solves, cheapest wins); then its remaining prominent planes are aligned with model
/// planes closer than a threshold. Planes of every rest pose count (doors shut and open).

#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/database.h"
#include "fabkit/templates/manipulate.h"
#include "fabkit/templates/working_model.h"

namespace fabkit::templates {

struct SnapOptions {
  int k = 4;                      ///< candidate planes per source constraint (paper: K = 4)
  int max_combinations = 256;     ///< K is lowered so that N = K^R stays at most this
  double align_distance_mm = 50;  ///< remaining planes closer than this are aligned
  ManipulateOptions manipulate;
};

/// One plane of the added template put onto a plane of the model.
struct SnapConstraint {
  PlaneRef added;            ///< the added template's plane (model element ids)
  PlaneRef target;           ///< the model's plane it now lies in
  double value = 0;          ///< mm along the axis
  bool from_source = false;  ///< re-created from the source design (else: aligned)
};

struct SnapResult {
  bool snapped = false;               ///< a feasible configuration was found (q is it)
  Eigen::VectorXd q;                  ///< the model's parameters after snapping
  int source_constraints = 0;         ///< R: independent constraints from the source design
  int candidates_per_constraint = 0;  ///< K used
  int combinations = 0;               ///< N = K^R least-squares problems solved
  std::vector<SnapConstraint> chosen;
  double cost = 0;  ///< Σ (q − q_current)² of the added template, mm²
  double milliseconds = 0;
  Diagnostics diagnostics;
};

/// Snaps composition `added` of `model` (its elements move; the rest of the model stays).
SnapResult snap(const WorkingModel& model,
                const Composition& added,
                const TemplateDatabase& db,
                const SnapOptions& options = {});

}  // namespace fabkit::templates

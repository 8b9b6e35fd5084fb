#pragma once
/// Checking a working model: compose it from its file (add, reshape, snap, connect, adjust),
/// then the findings a builder needs — constraints clipped, joints not found, parts that overlap
/// or float, stability at rest and under the file's loads, and whether every piece can be cut
/// from stock. Returns named findings (Diagnostics); never prints.

#include <chrono>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/bom.h"
#include "fabkit/templates/connect.h"
#include "fabkit/templates/database.h"
#include "fabkit/templates/design_file.h"
#include "fabkit/templates/snap.h"
#include "fabkit/templates/stability.h"
#include "fabkit/templates/working_model.h"

namespace fabkit::templates {

struct CheckOptions {
  SnapOptions snap;
  ConnectOptions connect;
  StabilityOptions stability;  ///< its friction and loads are taken from the model file
  BomOptions bom;
  double overlap_tolerance_mm = 0.5;  ///< principal parts may interpenetrate this much
  /// Stop composing and checking once this has passed: a time-limit error says after how many
  /// steps; cut plans get at most half the time left. None: no limit.
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

/// What one model step did.
struct StepReport {
  std::string text;  ///< "add shelf = bookshelf/shelves/bottom_shelf at [0, 0, 40]"
  SourceLocation where;
  bool ok = true;
  std::string outcome;  ///< "snapped to 5 planes (4 from its design); connected to 4 of 4"
  std::optional<SnapResult> snap;
  std::optional<ConnectResult> connect;
};

/// A model composed from its file.
struct ComposedModel {
  std::string name;
  std::string description;
  WorkingModel model;
  std::vector<StepReport> steps;
  std::vector<Load> loads;
  double friction = 0.5;
  Diagnostics diagnostics;  ///< reading and composing
  bool readable = false;    ///< the file was understood (no input errors)
  double milliseconds = 0;
};

/// Reads and composes a `fabkit: templates/1` model file (`model:`). A source design file
/// (`design:`) is accepted too: it is composed as a model of that one template.
ComposedModel compose_model(std::string_view yaml,
                            std::string_view file,
                            const TemplateDatabase& db,
                            const CheckOptions& options = {});

struct CheckResult {
  StabilityResult stability;
  std::optional<BillOfMaterials> bom;
  Diagnostics diagnostics;  ///< composition's, then every check's
  /// "feasible", "infeasible", "unstable", "unreadable"
  std::string verdict;
};

/// Every check of a composed model (stability with its loads and friction, overlaps, floating
/// parts, stock sizes).
CheckResult check(const ComposedModel& model,
                  const TemplateDatabase& db,
                  const CheckOptions& options = {});

}  // namespace fabkit::templates

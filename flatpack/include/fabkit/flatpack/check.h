#pragma once
/// Checking a design: solve its dimensions, place every component (Alg. 1), merge coplanar
/// pieces and find every intersection (Alg. 2), cut the joints (Appendix A) and find a
/// press-fit assembly order. This is what `fabkit check` reports and what build() and the
/// front ends start from; it never prints and never writes files.

#include <chrono>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/flatpack/design.h"
#include "fabkit/flatpack/model.h"

namespace fabkit::flatpack {

struct CheckOptions {
  double cycle_tolerance_mm = 0.01;   ///< a cycle of connections must close to this
  double cycle_tolerance_deg = 0.01;  ///< and to this
  double coplanar_tolerance_mm = 0.01;
  double min_joint_length_mm = 0.5;  ///< shorter intersections are contacts, not joints
  bool assembly_order = true;        ///< look for a press-fit order
  int max_components = 2000;         ///< refuse larger designs (limit-exceeded)
  /// 0: every group of components no connection links to the first is placed at the origin
  /// (as Alg. 1 does). > 0: each such group is laid beside the groups before it, this far
  /// apart along world x (mm), so that it neither overlaps nor merges with them (the editor,
  /// while a design is being connected).
  double separate_groups_mm = 0;
  /// Stop between stages once this has passed (a time-limit error names the last stage done).
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

struct StageTiming {
  std::string stage;  ///< "solve", "place", "detect", "joints", "assembly", "nest", "write"
  double milliseconds = 0;
};

/// How well a connection that closes a cycle of connections agrees with the placement the
/// others give (Alg. 1): the largest distance between where its component is and where the
/// connection would put it, over the component's outline (mm), and the angle between the two.
struct CycleResidual {
  int connection = -1;    ///< index of the connection
  std::string name;       ///< "c3"
  std::string component;  ///< the component the two placements disagree on
  double position_mm = 0;
  double angle_deg = 0;
  bool closes = true;  ///< within CheckOptions' cycle tolerances
  /// Where this connection would put the component (component frame → world), to show next to
  /// where it is (PlacedComponent::frame).
  Mat4 frame = Mat4::Identity();
};

/// Everything check() found.
struct Analysis {
  std::string name;
  std::map<std::string, double> values;  ///< every quantity, solved ("l1", "A.w", ...)
  std::vector<std::string> meta_parameters;
  /// Each meta-parameter → the component dimensions it drives ("top.l"), found by solving
  /// again with that parameter changed: what a maker re-sizes by turning that one knob.
  std::map<std::string, std::vector<std::string>> meta_drives;
  int dimension_count = 0;  ///< component dimensions the constraints determine
  std::vector<PlacedComponent> components;
  std::vector<Piece> pieces;
  std::vector<Joint> joints;
  /// Connections that merged two coplanar components into one piece (indices).
  std::vector<int> merging_connections;
  std::vector<AssemblyStep> assembly;  ///< press-fit order (empty if none found)
  std::vector<int> not_insertable;     ///< pieces no order can insert (indices)
  std::vector<StageTiming> timings;
  /// One per connection that closes a cycle (in the order placement met them).
  std::vector<CycleResidual> residuals;
  Diagnostics diagnostics;
  bool placed = false;  ///< solving and placement succeeded (pieces are meaningful)

  /// The paper's counts (§4.4): user connections, joints in the connectivity graph (one per
  /// user connection that makes a joint or a merge, plus each automatic one), automatic ones.
  int user_connection_joints() const;
  int automatic_joints() const;
  int graph_joints() const { return user_connection_joints() + automatic_joints(); }
  int joints_of(JointKind kind) const;
};

Analysis check(const Design& design, const CheckOptions& options = {});

}  // namespace fabkit::flatpack

#pragma once
// Polygon-inequality quick reject for cycle-closing connects (paper §4.3.2).

#include <string>
#include <vector>

#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks::detail {

/// Range of distances between the connector points of two primitives of one rigid body,
/// over their full parameter domains: sampled, then sharpened by a local search; `margin`
/// bounds how far the true extremes can lie beyond (from the sampling density).
struct DistanceRange {
  double lo = 0;
  double hi = 0;
  double margin = 0;  ///< how far the true extremes can lie beyond lo and hi
};

/// Distance range between connector points of primitive `a` placed by `frame_a` and
/// primitive `b` placed by `frame_b` (both rigidly in the same body or both fixed). When
/// `same_point_set` is true (a and b are the same primitive), lo is 0.
DistanceRange connector_distance_range(const Primitive& a,
                                       const Mat4& frame_a,
                                       const Primitive& b,
                                       const Mat4& frame_b,
                                       bool same_point_set);

/// One rigid piece of a cycle and the distance its two connection points can span.
struct CycleSegment {
  std::string description;  ///< "between Rods.rod1 and Rods.rod2", "across HookEye#1"
  DistanceRange range;
};

struct PolygonVerdict {
  bool feasible = true;
  int failing = -1;        ///< segment whose minimum exceeds what the others span
  double others_span = 0;  ///< Σ hi of the other segments
  /// Where the loop closes: the segment whose minimum comes nearest to what the others span
  /// (the failing one when there is one), and that span. A search that finds no closure says
  /// how near the bounds are to ruling one out.
  int tightest = -1;
  double tightest_others_span = 0;
  /// How far the segments' true extremes can lie beyond their measured ranges, together (the
  /// sampling's covering margin): a reject needs a minimum beyond the others' span by more.
  double margin = 0;
  std::vector<CycleSegment> segments;
};

/// k segments with lengths in [lo_i, hi_i] close into a loop iff lo_k ≤ Σ_{j≠k} hi_j for
/// every k (the paper's linear program, solved in closed form).
PolygonVerdict check_cycle_polygon(const Assembly& assembly, ConnectionId closing);

}  // namespace fabkit::hacks::detail

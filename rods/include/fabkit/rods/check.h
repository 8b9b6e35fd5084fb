#pragma once
/// The checks of RodSteward §3.1 and beyond, as named findings the designer colours red and the
/// command line prints. Checks never block: a design with findings still has joints, lengths
/// and a cut plan.
///
///   Layout layout = compute_layout(structure, parameters);
///   CheckReport report = check(structure, parameters, layout);
///   for (const Diagnostic& d : report.findings) ...          // rods-intersect, unbalanced, ...
///   report.red_rods[e], report.red_joints[i]                 // what to draw red

#include <Eigen/Core>
#include <optional>
#include <span>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/rods/layout.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

/// Closest points of segments [p0, p1] and [q0, q1]: distance (mm) and the parameters s, t in
/// [0, 1] of the closest points (exact up to rounding, parallel and degenerate segments
/// included).
struct SegmentDistance {
  double distance = 0;
  double s = 0;
  double t = 0;
};
SegmentDistance segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);

/// Two rods that share no joint and come closer than 2r.
struct RodPair {
  int rod_a = 0;
  int rod_b = 0;
  double distance = 0;        ///< mm between the rods' axes (closest points)
  double clearance = 0;       ///< mm between their surfaces: distance − 2r (negative: overlap)
  Vec3 point = Vec3::Zero();  ///< mm, midway between the closest points
};

/// Mass of one joint (kg) and where its centre of mass is (world, mm).
struct JointMass {
  double mass = 0;
  Vec3 center = Vec3::Zero();
};

/// Whether the structure stands (§3.1, Fig. 7).
struct Balance {
  double mass = 0;                     ///< kg: rods and joints
  Vec3 center_of_mass = Vec3::Zero();  ///< world, mm
  double ground_z = 0;                 ///< mm: the floor (lowest node)
  std::vector<int> ground_nodes;       ///< nodes touching the floor (within the tolerance)
  std::vector<Eigen::Vector2d> support_polygon;  ///< convex hull of their xy, counter-clockwise
  /// mm from the centre of mass's projection to the support polygon's boundary: positive
  /// inside (stands), negative outside (tips over).
  double margin = 0;
  bool stands = false;
};

struct CheckOptions {
  double ground_tolerance = 1.0;  ///< mm: nodes this close to the lowest node touch the floor
  double near_miss = 10.0;        ///< mm: report the closest pair of rods within this clearance
  bool balance = true;
  /// Downward loads count as weight at their nodes (a laptop on a table's corner tips it as
  /// much as a heavy joint there would); gravity in m/s² converts them to mass.
  std::vector<PointLoad> loads;
  double gravity = 9.81;
};

struct CheckReport {
  /// Every finding: errors of class check (rods-intersect, joint-swallows-rod, rod-too-short,
  /// unbalanced), infeasible no-rod-left, warnings and notes (closest rods, margin).
  Diagnostics findings;
  std::vector<RodPair> intersections;
  std::optional<RodPair> closest_pair;  ///< the nearest non-adjacent rods within near_miss
  std::vector<int> swallowed_rods;
  std::vector<int> short_rods;
  Balance balance;
  std::vector<bool> red_rods;    ///< per rod: part of a failed check
  std::vector<bool> red_joints;  ///< per node
  bool passed() const { return !findings.has_errors(); }
};

/// Estimated joint masses from the primitives (hull + prisms − sockets), without booleans.
std::vector<JointMass> estimate_joint_masses(const Structure& s,
                                             const Parameters& p,
                                             const Layout& l);
/// Balance from rod masses (density · area · ℓ), the given joint masses, and the downward
/// part of `loads` as weight (N → kg by `gravity`).
Balance compute_balance(const Structure& s,
                        const Parameters& p,
                        const Layout& l,
                        std::span<const JointMass> joints,
                        double ground_tolerance,
                        std::span<const PointLoad> loads = {},
                        double gravity = 9.81);

/// Rods sharing no joint that intersect (closest axis distance < 2r), found with a sweep over
/// bounding boxes: O(m log m + pairs) for m rods.
std::vector<RodPair> find_rod_intersections(const Structure& s,
                                            const Parameters& p,
                                            const Layout& l,
                                            double extra_clearance = 0,
                                            std::optional<RodPair>* closest = nullptr);

/// Every check of §3.1 (rod intersections, swallowed rods, short rods, balance).
/// `joint_masses` (from exact joints) replaces the estimate when given.
CheckReport check(const Structure& s,
                  const Parameters& p,
                  const Layout& l,
                  const CheckOptions& options = {},
                  std::span<const JointMass> joint_masses = {});

}  // namespace fabkit::rods

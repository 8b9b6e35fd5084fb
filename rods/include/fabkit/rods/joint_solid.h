#pragma once
/// Exact, printable joints (Appendix A, Eq. 9): J_i = (H_i ∪ ⋃ C_ij) \ ⋃ E_ij by exact booleans
/// (CGAL, fabkit::geometry), engraved with the joint's ID (§4.1) and posed for printing.

#include <chrono>
#include <optional>
#include <string>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"
#include "fabkit/core/mesh_boolean.h"
#include "fabkit/rods/engraving.h"
#include "fabkit/rods/layout.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

struct JointSolidOptions {
  bool engrave = true;
  EngravingOptions engraving;
  /// Checked between the joint's boolean operations: past it, nullopt with a time-limit error.
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

struct JointSolid {
  int node = 0;
  /// The joint in its local frame: the node at the origin, world axes, mm. Closed, manifold.
  TriangleMesh mesh;
  /// Local frame → print bed (sum of rod directions along +z, resting on z = 0).
  Mat4 print_pose = Mat4::Identity();
  std::optional<EngravingSpot> engraving;  ///< where the ID is (local frame)
  std::string label;                       ///< the engraved ID ("07")
  double text_height = 0;                  ///< mm
  double text_area = 0;                    ///< mm², inked area of the label
  double engraved_volume = 0;              ///< mm³ the engraving removed
  double volume = 0;                       ///< mm³ of the finished joint
  Vec3 centroid = Vec3::Zero();            ///< local frame, mm
  SolidCheck solid;                        ///< closed, manifold, self-intersection (checked)
  double milliseconds = 0;
};

/// Builds joint `node`. nullopt with a diagnostic naming the joint if a boolean fails or the
/// result is not a valid solid (an internal error: the construction guarantees it).
std::optional<JointSolid> make_joint_solid(const Structure& s,
                                           const Parameters& p,
                                           const Layout& l,
                                           int node,
                                           const JointSolidOptions& options,
                                           Diagnostics& diags);

}  // namespace fabkit::rods

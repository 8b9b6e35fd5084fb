#pragma once
/// The order in which to put a structure together (RodSteward §5): a depth-first traversal of
/// the joints; after placing a joint, each of its rods not yet placed, then the next joint not
/// yet placed along them. The placed parts always form one connected piece.

#include <string>
#include <vector>

#include "fabkit/rods/layout.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

struct AssemblyStep {
  enum class Kind { kJoint, kRod };
  Kind kind = Kind::kJoint;
  int joint = -1;         ///< kJoint: the node placed
  int rod = -1;           ///< kRod: the rod placed
  int from_joint = -1;    ///< kRod: the placed joint it goes into
  int to_joint = -1;      ///< kRod: the joint at its other end
  double rod_length = 0;  ///< kRod: mm, as cut
  /// "place joint 07" / "insert rod 07-12 (412.3 mm) into joint 07, towards joint 12"
  std::string text;
};

/// Steps for every joint and rod, starting at `start` (a node index; −1: the lowest node, the
/// first in order among equals). A structure in several pieces continues with the next piece.
std::vector<AssemblyStep> assembly_order(const Structure& s, const Layout& l, int start = -1);

/// Whether, after every step, the placed joints and rods form one connected set (within each
/// piece of the structure) and every rod is placed after one of its joints: the guarantee of
/// the depth-first order, for tests and for orders edited by hand.
bool placed_set_stays_connected(const Structure& s, const std::vector<AssemblyStep>& steps);

}  // namespace fabkit::rods

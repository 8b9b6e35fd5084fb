#pragma once
/// The rods kit's diagnostic codes, each with its class (core/diagnostics.h). The codes every
/// kit shares (malformed input, invalid value, ...) are reachable here too: rods::codes::X
/// finds fabkit::codes::X.

#include <span>

#include "fabkit/core/cut_plan.h"
#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh_boolean.h"

namespace fabkit::rods::codes {

using namespace fabkit::codes;

// Input: the network cannot be understood.
/// An edge names a node that does not exist.
inline constexpr DiagnosticCode kNoSuchNode{"no-such-node", DiagnosticClass::kInput};
/// An edge joins a node to itself (possibly after merging coincident nodes).
inline constexpr DiagnosticCode kZeroLengthEdge{"zero-length-edge", DiagnosticClass::kInput};
/// The same two nodes are joined twice.
inline constexpr DiagnosticCode kDuplicateEdge{"duplicate-edge", DiagnosticClass::kInput};
/// A node no edge uses: it would be a joint holding nothing.
inline constexpr DiagnosticCode kIsolatedNode{"isolated-node", DiagnosticClass::kInput};
/// Two edges leave a node in the same direction: the rods would lie inside each other.
inline constexpr DiagnosticCode kOverlappingEdges{"overlapping-edges", DiagnosticClass::kInput};

/// Nodes closer than the merge tolerance became one joint (a note).
inline constexpr DiagnosticCode kNodesMerged{"nodes-merged", DiagnosticClass::kInput};

// Infeasible: no rod can be cut.
/// The offsets at both ends leave nothing of the rod (ℓ ≤ 0).
inline constexpr DiagnosticCode kNoRodLeft{"no-rod-left", DiagnosticClass::kInfeasible};

// Checks (RodSteward §3.1 and beyond): the design builds, but it should not be built as is.
/// Two rods that share no joint intersect.
inline constexpr DiagnosticCode kRodsIntersect{"rods-intersect", DiagnosticClass::kCheck};
/// The joints at both ends of a rod overlap: g_ij + g_ji + 2h > edge length.
inline constexpr DiagnosticCode kJointSwallowsRod{"joint-swallows-rod", DiagnosticClass::kCheck};
/// A rod is shorter than the minimum the maker can cut and hold.
inline constexpr DiagnosticCode kRodTooShort{"rod-too-short", DiagnosticClass::kCheck};
/// The centre of mass projects outside the support polygon: the structure tips over.
inline constexpr DiagnosticCode kUnbalanced{"unbalanced", DiagnosticClass::kCheck};
/// A rod's stress or compression exceeds its strength or buckling load.
inline constexpr DiagnosticCode kRodOverstressed{"rod-overstressed", DiagnosticClass::kCheck};
/// The frame cannot carry load (a mechanism: the supports or joints leave it free to move).
inline constexpr DiagnosticCode kMechanism{"mechanism", DiagnosticClass::kCheck};
/// The structure is in several pieces (a warning).
inline constexpr DiagnosticCode kDisconnected{"disconnected", DiagnosticClass::kCheck};
/// A joint has little flat room: its engraved ID is small (a warning).
inline constexpr DiagnosticCode kSmallEngraving{"small-engraving", DiagnosticClass::kCheck};
/// Joints reused from another design (a note).
inline constexpr DiagnosticCode kJointsReused{"joints-reused", DiagnosticClass::kCheck};

}  // namespace fabkit::rods::codes

namespace fabkit::rods {
/// The rods kit's own codes (not the shared ones), for documentation and tests.
std::span<const DiagnosticCode> rods_codes();
}  // namespace fabkit::rods

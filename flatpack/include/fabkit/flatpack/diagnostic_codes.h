#pragma once
/// The flatpack kit's diagnostic codes, each with its class (core/diagnostics.h). The codes every
/// kit shares are reachable here too: flatpack::codes::X finds fabkit::codes::X.

#include <span>

#include "fabkit/core/diagnostics.h"

namespace fabkit::flatpack::codes {

using namespace fabkit::codes;

inline constexpr DiagnosticCode kUnknownComponent{"unknown-component", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kUnknownEdge{"unknown-edge", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kBadExpression{"bad-expression", DiagnosticClass::kInput};
/// A quantity no constraint (and no default) determines.
inline constexpr DiagnosticCode kUnderConstrained{"under-constrained", DiagnosticClass::kInput};
/// Constraints that contradict each other.
inline constexpr DiagnosticCode kOverConstrained{"over-constrained", DiagnosticClass::kInput};
/// A component's solved dimensions make no shape (negative length, notch wider than the panel).
inline constexpr DiagnosticCode kBadShape{"bad-shape", DiagnosticClass::kInfeasible};
/// A cycle of connections that does not close.
inline constexpr DiagnosticCode kCycleMismatch{"cycle-mismatch", DiagnosticClass::kInfeasible};
/// Components not reachable from the first one through connections (a warning).
inline constexpr DiagnosticCode kNotConnected{"not-connected", DiagnosticClass::kInfeasible};
/// A user connection whose pieces do not meet (a warning).
inline constexpr DiagnosticCode kConnectionMakesNoJoint{"connection-makes-no-joint",
                                                        DiagnosticClass::kCheck};
/// Pieces meeting at an angle other than 90° (a warning: the joints only fit 90°).
inline constexpr DiagnosticCode kNotPerpendicular{"not-perpendicular", DiagnosticClass::kCheck};
/// A piece not deep or long enough for its fingers (a warning).
inline constexpr DiagnosticCode kJointFit{"joint-fit", DiagnosticClass::kCheck};
/// Pieces that overlap in a way no joint can make (coplanar with different materials, ...).
inline constexpr DiagnosticCode kOverlap{"overlap", DiagnosticClass::kCheck};
/// No press-fit order inserts every piece along a free direction.
inline constexpr DiagnosticCode kNotAssemblable{"not-assemblable", DiagnosticClass::kCheck};

}  // namespace fabkit::flatpack::codes

namespace fabkit::flatpack {
/// The flatpack kit's own codes (not the shared ones), for documentation and tests.
std::span<const DiagnosticCode> flatpack_codes();
}  // namespace fabkit::flatpack

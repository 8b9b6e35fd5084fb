#pragma once
/// The hacks kit's diagnostic codes, each with its class (core/diagnostics.h). The codes every
/// kit shares (malformed input, invalid value, ...) are reachable here too: hacks::codes::X
/// finds fabkit::codes::X.

#include <span>

#include "fabkit/core/diagnostics.h"

namespace fabkit::hacks::codes {

using namespace fabkit::codes;

inline constexpr DiagnosticCode kUnknownPart{"unknown-part", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kUnknownPrimitive{"unknown-primitive", DiagnosticClass::kInput};
/// Neither primitive's part is in the assembly yet.
inline constexpr DiagnosticCode kNotInAssembly{"not-in-assembly", DiagnosticClass::kInfeasible};
/// The two primitive types cannot connect (paper Table 1).
inline constexpr DiagnosticCode kPairNotAllowed{"pair-not-allowed", DiagnosticClass::kInfeasible};
/// Both primitives are closed: there is no way to slide one on.
inline constexpr DiagnosticCode kBothClosed{"both-closed", DiagnosticClass::kInfeasible};
/// The primitives' sizes do not fit (hook opening vs rod radius, ...).
inline constexpr DiagnosticCode kDimensionMismatch{"dimension-mismatch",
                                                   DiagnosticClass::kInfeasible};
/// The available critical dimension is used up.
inline constexpr DiagnosticCode kNoSpaceLeft{"no-space-left", DiagnosticClass::kInfeasible};
/// A clip/hemisphere already holds something.
inline constexpr DiagnosticCode kSingleConnection{"single-connection",
                                                  DiagnosticClass::kInfeasible};
/// The same two primitives are connected already.
inline constexpr DiagnosticCode kAlreadyConnected{"already-connected",
                                                  DiagnosticClass::kInfeasible};
/// Several connections on one primitive cannot be spaced apart.
inline constexpr DiagnosticCode kMultiConnection{"multi-connection", DiagnosticClass::kInfeasible};
/// Polygon-inequality proof that a cycle-closing connect cannot close.
inline constexpr DiagnosticCode kCycleTooLong{"cycle-too-long", DiagnosticClass::kInfeasible};
/// The cycle-closure search found no configuration that closes it.
inline constexpr DiagnosticCode kCycleNotClosable{"cycle-not-closable",
                                                  DiagnosticClass::kInfeasible};
/// An assembly needs an environment before anything else.
inline constexpr DiagnosticCode kNoEnvironment{"no-environment", DiagnosticClass::kInfeasible};
/// No end_with target, or it is not connected.
inline constexpr DiagnosticCode kTargetMissing{"target-missing", DiagnosticClass::kInfeasible};
/// A part is in the design but connected to nothing (a warning).
inline constexpr DiagnosticCode kNotConnected{"not-connected", DiagnosticClass::kInfeasible};
/// Step 2 ended away from a rest state (the potential slopes or curves down there).
inline constexpr DiagnosticCode kNotAtRest{"not-at-rest", DiagnosticClass::kInfeasible};
/// Two parts pass through each other in the reported pose (deeper than the tolerance).
inline constexpr DiagnosticCode kPartsOverlap{"parts-overlap", DiagnosticClass::kCheck};
/// A connection slips off under gravity.
inline constexpr DiagnosticCode kFallsApart{"falls-apart", DiagnosticClass::kFallsApart};
/// A part could not be exported as one closed solid (a piece of its mesh is not closed, or the
/// union failed); it is exported as its display mesh instead (a warning).
inline constexpr DiagnosticCode kNotASolid{"not-a-solid", DiagnosticClass::kCheck};

}  // namespace fabkit::hacks::codes

namespace fabkit::hacks {
/// The hacks kit's own codes (not the shared ones), for documentation and tests.
std::span<const DiagnosticCode> hacks_codes();
}  // namespace fabkit::hacks

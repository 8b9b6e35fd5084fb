#pragma once
/// The templates kit's diagnostic codes, each with its class (core/diagnostics.h). The codes
/// every kit shares (malformed input, invalid value, ...) are reachable here too:
/// templates::codes::X finds fabkit::codes::X.

#include <span>

#include "fabkit/core/diagnostics.h"

namespace fabkit::templates::codes {

using namespace fabkit::codes;

/// A part names an item the catalog does not have.
inline constexpr DiagnosticCode kUnknownItem{"unknown-item", DiagnosticClass::kInput};
/// A model names a template the database does not have.
inline constexpr DiagnosticCode kUnknownTemplate{"unknown-template", DiagnosticClass::kInput};
/// A part's size cannot be made from its item (a fixed dimension differs, or it is longer than
/// the longest stock).
inline constexpr DiagnosticCode kItemMismatch{"item-mismatch", DiagnosticClass::kInput};
/// The catalog database cannot be opened, read or migrated.
inline constexpr DiagnosticCode kCatalogError{"catalog-error", DiagnosticClass::kInput};
/// A requested size or position is outside what the template can be reshaped to; the result
/// is the nearest feasible shape and the message names the binding constraint.
inline constexpr DiagnosticCode kConstrained{"constrained", DiagnosticClass::kInfeasible};
/// A control that the template's constraints fix completely (hidden in the editor).
inline constexpr DiagnosticCode kFixedControl{"fixed-control", DiagnosticClass::kInfeasible};
/// Two linked parts could not be joined: no connection in the database fits.
inline constexpr DiagnosticCode kNoConnection{"no-connection", DiagnosticClass::kInfeasible};
/// The QP solver did not converge (the result is the last feasible shape).
inline constexpr DiagnosticCode kSolverFailed{"solver-failed", DiagnosticClass::kInfeasible};
/// A part (or group of joined parts) is not in static equilibrium: it tips or slides.
inline constexpr DiagnosticCode kUnstable{"unstable", DiagnosticClass::kFallsApart};
/// Two principal parts overlap in volume (a fabrication check).
inline constexpr DiagnosticCode kPartsOverlap{"parts-overlap", DiagnosticClass::kCheck};
/// A part of the model touches nothing (a warning).
inline constexpr DiagnosticCode kFloatingPart{"floating-part", DiagnosticClass::kCheck};
/// A lumber or sheet piece is larger than every stock size of its item.
inline constexpr DiagnosticCode kPieceTooLarge{"piece-too-large", DiagnosticClass::kInfeasible};

}  // namespace fabkit::templates::codes

namespace fabkit::templates {
/// The templates kit's own codes (not the shared ones), for documentation and tests.
std::span<const DiagnosticCode> templates_codes();
}  // namespace fabkit::templates

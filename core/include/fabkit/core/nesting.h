#pragma once
/// Nesting flat pieces onto rectangular sheets (libnest2d's no-fit-polygon placer behind plain
/// types): several sheets, spacing between pieces, a margin at the sheet's edge, a set of
/// allowed rotations, and the sheet count and utilisation of the result.

#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/polygon2d.h"

namespace fabkit {

struct NestingOptions {
  double sheet_width_mm = 600;   ///< sheet size along x
  double sheet_height_mm = 400;  ///< sheet size along y
  double spacing_mm = 3;         ///< least gap between two pieces
  double margin_mm = 5;          ///< least gap between a piece and the sheet's edge
  /// Rotations a piece may take, degrees counter-clockwise (grain direction: {0, 180}).
  std::vector<double> rotations_deg = {0, 90, 180, 270};
  /// libnest2d's placer accuracy in (0, 1]: higher tries more positions (slower, denser).
  double accuracy = 0.65;
  int max_sheets = 100;  ///< refuse to use more sheets than this
  /// Stop (diagnostic kTimeLimit, pieces left unplaced) once this time has passed.
  std::optional<std::chrono::steady_clock::time_point> deadline;

  /// An input diagnostic naming each option that makes no sense; empty when fine.
  Diagnostics validate() const;
};

/// Where one piece went: p ↦ R(rotation) · p + translation (sheet frame: origin at the
/// sheet's lower-left corner, x along its width, mm).
struct NestedPlacement {
  int sheet = -1;  ///< 0-based; -1: not placed
  double rotation_deg = 0;
  Vec2 translation = Vec2::Zero();
};

struct NestingResult {
  std::vector<NestedPlacement> placements;  ///< one per input piece, in input order
  int sheet_count = 0;
  /// Pieces' area over sheet area, per sheet and over all sheets used (0..1).
  std::vector<double> sheet_utilisation;
  double utilisation = 0;
  std::vector<int> unplaced;  ///< indices of pieces that fit on no sheet
  double milliseconds = 0;
  Diagnostics diagnostics;  ///< one error per piece that cannot fit (names it, with sizes)
};

/// Nests `pieces` (each in its own frame; `names` for messages, may be empty). Deterministic:
/// the same input gives the same layout. Never throws.
NestingResult nest(const std::vector<Polygon2d>& pieces,
                   const std::vector<std::string>& names,
                   const NestingOptions& options = {});

/// The piece as placed on its sheet.
Polygon2d placed(const Polygon2d& piece, const NestedPlacement& placement);

}  // namespace fabkit

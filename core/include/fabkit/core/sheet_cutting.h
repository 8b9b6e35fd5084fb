#pragma once
/// Two-dimensional guillotine cutting of rectangles from stock sheets (plywood, MDF, acrylic),
/// for every kit: which pieces to cut from which sheet, where, and the straight through-cuts a
/// panel saw or track saw makes, with kerf and trimmed factory edges.
///
///   std::vector<SheetPiece> pieces = {{"side", 782, 400}, {"shelf", 564, 380, true}, ...};
///   SheetSpec sheet{.length = 2440, .width = 1220, .kerf = 3, .edge_trim = 5};
///   Diagnostics diags;
///   auto plan = plan_sheets(pieces, sheet, diags);
///   if (plan) write_file_atomically("sheet_1.svg", sheet_plan_svg(*plan, 0, pieces, sheet),
///   diags);
///
/// Coordinates: mm, x along the sheet's length, y along its width, origin at the sheet's
/// corner. A piece keeps its exact size; kerf falls on the waste side of every cut, so pieces
/// are at least one kerf apart. Guillotine: every cut runs edge to edge of the panel it splits.
///
/// Solver: the guillotine free-rectangle heuristic (best short-side fit, split along the
/// shorter leftover) run over several orderings (area, long side, perimeter, and seeded random
/// ones); the plan with the fewest sheets, then the most compact last sheet, wins. The plan
/// reports the area lower bound ⌈Σ(l + kerf)(w + kerf) / ((L + kerf)(W + kerf))⌉ and whether it
/// meets it.

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"

namespace fabkit {

namespace codes {
/// A piece larger than the usable sheet in either orientation allowed.
inline constexpr DiagnosticCode kPieceLargerThanSheet{"piece-larger-than-sheet",
                                                      DiagnosticClass::kInfeasible};
}  // namespace codes

struct SheetPiece {
  std::string label;       ///< names the piece in messages, drawings and lists
  double length = 0;       ///< mm, along the sheet's length when not rotated (> 0)
  double width = 0;        ///< mm (> 0)
  bool may_rotate = true;  ///< false when the grain (or a pattern) must run along the length
};

struct SheetSpec {
  double length = 2440;  ///< mm
  double width = 1220;   ///< mm
  double kerf = 3;       ///< mm each cut removes (>= 0)
  double edge_trim = 0;  ///< mm trimmed off every factory edge (>= 0)
  double usable_length() const { return length - 2 * edge_trim; }
  double usable_width() const { return width - 2 * edge_trim; }
};

struct SheetPlanOptions {
  int orderings = 64;  ///< seeded random orderings tried after the sorted ones (>= 0)
  unsigned seed = 1;
};

/// A piece on a sheet: its lower-left corner and its size as placed.
struct SheetPlacement {
  int piece = 0;
  double x = 0, y = 0;           ///< mm from the sheet's corner
  double length = 0, width = 0;  ///< mm as placed (swapped when rotated)
  bool rotated = false;
};

/// A guillotine cut: a straight line at the centre of its kerf, edge to edge of the panel it
/// splits.
struct SheetCutLine {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< mm
};

struct SheetCut {
  std::vector<SheetPlacement> pieces;
  std::vector<SheetCutLine> cuts;
  double used_area = 0;  ///< mm² of pieces
};

struct SheetPlan {
  std::vector<SheetCut> sheets;
  int lower_bound = 0;
  bool meets_lower_bound = false;
  std::string summary;  ///< "2 sheets (lower bound 2), 71 % of the area used"
  int sheet_count() const { return static_cast<int>(sheets.size()); }
  /// Fraction of the usable area of all sheets covered by pieces.
  double utilisation(const SheetSpec& sheet) const;
};

/// Plans `pieces` on sheets of `sheet`. nullopt with diagnostics when a size is not finite and
/// positive, the trim leaves no usable sheet, or a piece fits in neither allowed orientation
/// (piece-larger-than-sheet, naming it and the sizes). Deterministic for a given seed.
std::optional<SheetPlan> plan_sheets(std::span<const SheetPiece> pieces,
                                     const SheetSpec& sheet,
                                     Diagnostics& diags,
                                     const SheetPlanOptions& options = {});

/// Independent check: every piece placed once at its size (or rotated when allowed), inside
/// the usable area, no two closer than one kerf. Internal-error diagnostics when it is not.
Diagnostics validate_sheet_plan(const SheetPlan& plan,
                                std::span<const SheetPiece> pieces,
                                const SheetSpec& sheet);

/// One sheet as an SVG at true size (width/height in mm, viewBox in mm): the sheet outline,
/// the trimmed margin, every piece (light fill, its label and size), every cut line in red at
/// the kerf centre with the kerf drawn as its stroke width. Labels are XML-escaped.
std::string sheet_plan_svg(const SheetPlan& plan,
                           int sheet_index,
                           std::span<const SheetPiece> pieces,
                           const SheetSpec& sheet);

/// `label,length_mm,width_mm,sheet,x_mm,y_mm,rotated` per piece (sheet 1-based), RFC 4180.
std::string sheet_plan_csv(const SheetPlan& plan, std::span<const SheetPiece> pieces);

}  // namespace fabkit

#pragma once
/// One-dimensional stock cutting for every kit: which pieces to cut from which stock length
/// (dowels for rods, boards for lumber cut lists), with end padding and saw/laser kerf.
///
///   std::vector<CutPiece> pieces = {{"rod 01-02", 412.5}, {"rod 02-03", 388.0}, ...};
///   Diagnostics diags;
///   auto plan = plan_cuts(pieces, StockSpec{.length = 1000, .end_padding = 10, .kerf = 0.2},
///                         diags);
///   if (plan) write_file_atomically("cuts.svg", cut_plan_svg(*plan, pieces, stock), diags);
///
/// Layout on one stock piece (all mm, measured from the stock's left end):
///
///   |<- end_padding ->|piece|kerf|piece|kerf|piece| ... remainder ... |<- end_padding ->|
///
/// A stock piece holds pieces ℓ1..ℓn when Σℓ + (n−1)·kerf ≤ length − 2·end_padding; each piece
/// keeps its exact length (the kerf falls on the waste side of every cut). Equivalently each
/// piece needs ℓ + kerf of a bin of capacity usable + kerf, which is how it is packed.
///
/// Two solvers, the fast one first:
///  1. first fit over first-fit-decreasing and many seeded random orderings (RodSteward §4.2;
///     every optimal packing is the first fit of some ordering);
///  2. unless (1) already meets the lower bound, the exact integer program of bin packing in
///     its pattern form (Gilmore–Gomory), solved with GLPK: column generation proves the
///     linear-programming lower bound, then the integer master over the generated patterns
///     searches for a plan that meets it, within a time limit.
/// The plan says whether it is proven optimal, and otherwise the gap to the best lower bound.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"

namespace fabkit {

namespace codes {
/// A piece longer than the usable stock length: no plan can cut it.
inline constexpr DiagnosticCode kPieceLongerThanStock{"piece-longer-than-stock",
                                                      DiagnosticClass::kInfeasible};
}  // namespace codes

/// One piece to cut.
struct CutPiece {
  std::string label;  ///< names the piece in messages, the SVG and the CSV ("rod 03-07")
  double length = 0;  ///< mm, exact length of the finished piece (> 0)
};

/// The stock the pieces come from (one length bought many times).
struct StockSpec {
  double length = 1000;     ///< mm, as bought (> 0)
  double end_padding = 10;  ///< mm discarded at each end for rough factory cuts (>= 0)
  double kerf = 0;          ///< mm of material each cut removes (>= 0)
  /// length − 2·end_padding (mm).
  double usable_length() const { return length - 2 * end_padding; }
};

struct CutPlanOptions {
  int orderings = 1000;  ///< random first-fit orderings tried after first-fit decreasing (>= 0)
  unsigned seed = 1;     ///< seeds the orderings: same input and seed, same plan
  bool integer_program = true;  ///< run the exact program when first fit misses the bound
  double time_limit_s = 0.8;    ///< budget of the integer program (column generation + search)
};

/// A piece placed on a stock piece.
struct PlacedPiece {
  int piece = 0;      ///< index into the pieces given to plan_cuts
  double start = 0;   ///< mm from the stock's left end to the piece's left end
  double length = 0;  ///< mm (copied from the piece)
};

/// One stock piece and what is cut from it, left to right, longest first.
struct StockCut {
  std::vector<PlacedPiece> pieces;
  double used = 0;       ///< mm of the usable length taken by pieces and the kerfs between them
  double remainder = 0;  ///< mm of usable length left over after the last piece
};

/// Which solver produced the plan.
enum class CutPlanMethod { kFirstFit, kIntegerProgram };
std::string_view to_string(CutPlanMethod m);

struct CutPlan {
  std::vector<StockCut> stock;  ///< one entry per stock piece to buy
  /// ⌈Σ(ℓ + kerf) / (usable + kerf)⌉: the bound every plan respects (with kerf 0 this is
  /// ⌈Σℓ / usable⌉).
  int sum_lower_bound = 0;
  /// The best proven lower bound (>= sum_lower_bound; the linear-programming bound of the
  /// pattern formulation when column generation finished).
  int lower_bound = 0;
  bool proven_optimal = false;  ///< stock_count() == lower_bound
  CutPlanMethod method = CutPlanMethod::kFirstFit;
  int first_fit_stock_count = 0;  ///< the best first-fit plan (for comparison)
  bool column_generation_converged = false;
  bool hit_time_limit = false;
  double first_fit_ms = 0;
  double integer_program_ms = 0;
  /// One line: "7 stock pieces, proven optimal (lower bound 7)" or "... 1 above the lower
  /// bound 6 (time limit)".
  std::string summary;

  int stock_count() const { return static_cast<int>(stock.size()); }
  /// stock_count() − lower_bound.
  int gap() const { return stock_count() - lower_bound; }
  /// mm of usable stock not in any piece (remainders and kerfs).
  double waste(const StockSpec& stock_spec) const;
};

/// Plans cuts of `pieces` from `stock`. nullopt with diagnostics when a length is not a finite
/// positive number (invalid-value), the stock leaves no usable length (invalid-value), or a
/// piece is longer than the usable length (piece-longer-than-stock, naming the piece and both
/// lengths; every such piece is reported). Deterministic for a given seed.
std::optional<CutPlan> plan_cuts(std::span<const CutPiece> pieces,
                                 const StockSpec& stock,
                                 Diagnostics& diags,
                                 const CutPlanOptions& options = {});

/// Independent check of a plan: every piece placed exactly once with its own length, pieces
/// inside the usable length, at least one kerf apart, in order. Errors (internal-error class)
/// name the stock piece and the numbers; empty when the plan is valid.
Diagnostics validate_cut_plan(const CutPlan& plan,
                              std::span<const CutPiece> pieces,
                              const StockSpec& stock);

struct CutPlanSvgOptions {
  double stock_width = 10;  ///< mm, height of each stock row (the dowel's diameter)
  double row_gap = 6;       ///< mm between rows
  double margin = 5;        ///< mm around the drawing
  double label_size = 3;    ///< mm, label text height (0: no labels)
};

/// An SVG at true size (width and height in mm, viewBox in mm) for a laser cutter or to print:
/// one row per stock piece with its outline (blue, not cut), a cut line (red, 0.1 mm) at the
/// centre of every kerf and at every piece end next to padding, and each piece's label and
/// length (black text, to engrave or ignore). Labels are XML-escaped.
std::string cut_plan_svg(const CutPlan& plan,
                         std::span<const CutPiece> pieces,
                         const StockSpec& stock,
                         const CutPlanSvgOptions& options = {});

/// A cut list as CSV (RFC 4180 quoting), one row per piece sorted by length (longest first,
/// then label): `label,length_mm,stock,position_mm` where stock is 1-based and position is
/// the piece's left end from the stock's left end.
std::string cut_plan_csv(const CutPlan& plan, std::span<const CutPiece> pieces);

}  // namespace fabkit

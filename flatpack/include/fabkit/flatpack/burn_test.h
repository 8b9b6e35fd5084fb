#pragma once
/// A burn-test sheet (paper Appendix A.1: "users may need to perform some experiments to find
/// the best interference fit value and the fabrication kerf"): one cell per (Δ, δ) pair, each a
/// finger comb, the dent strip it presses into and a slot for the board, drawn exactly as fabkit
/// draws those joints, and labelled with its Δ and δ. The maker cuts it, finds the cell whose
/// fingers press in firmly and whose slot grips a board, and writes that Δ and δ into the
/// design's material.
///
/// Sheet frame: mm, origin at the lower-left corner; cells in rows by Δ (first kerf at the
/// bottom) and columns by δ.

#include <filesystem>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/svg_sheet.h"
#include "fabkit/flatpack/design.h"

namespace fabkit::flatpack {

struct BurnTestOptions {
  Material material;                     ///< its name and thickness; its kerf and fit are ignored
  std::vector<double> kerfs_mm;          ///< Δ values to try (per side), 0 ≤ Δ ≤ 2 mm
  std::vector<double> interferences_mm;  ///< δ values to try, −1 ≤ δ ≤ 1 mm
  double finger_width_mm = 0;            ///< nominal finger width; 0: 3 × thickness
  static constexpr int kMaxValues = 20;  ///< per list (at most 400 cells)
};

/// One cell of the sheet and the widths drawn in it.
struct BurnTestCell {
  double kerf_mm = 0;
  double interference_mm = 0;
  double finger_mm = 0;  ///< drawn finger width (w_f = w_d + 4Δ + δ)
  double dent_mm = 0;    ///< drawn dent width
  double slot_mm = 0;    ///< drawn slot width (cut: thickness − δ)
  Box2d box;             ///< the cell's area on the sheet
};

struct BurnTest {
  CutSheet sheet;
  std::vector<BurnTestCell> cells;  ///< row by row: kerfs outer, interferences inner
  Diagnostics diagnostics;          ///< input errors (then sheet and cells are empty)
};

/// The sheet for every (Δ, δ) pair of `options`; deterministic, never throws.
BurnTest burn_test(const BurnTestOptions& options);

/// Writes `dir`/burn-test.svg and `dir`/burn-test.dxf (the directory is made if needed); the
/// files written, or an I/O diagnostic.
std::vector<std::filesystem::path> write_burn_test(const BurnTest& test,
                                                   const std::filesystem::path& dir,
                                                   Diagnostics& diags);

/// Parses a list of values in mm as a maker writes it on the command line: "0.1", "0.1,0.15,0.2"
/// or "start:stop:step" (inclusive, "0.05:0.25:0.05"); an input diagnostic naming `what` on
/// anything else.
std::vector<double> parse_value_list(const std::string& text,
                                     const std::string& what,
                                     Diagnostics& diags);

}  // namespace fabkit::flatpack

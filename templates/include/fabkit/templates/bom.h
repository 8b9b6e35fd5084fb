#pragma once
/// The bill of materials and fabrication plan (paper §5.3): every item with quantity, sizes,
/// unit and total cost and supplier; lumber and pipe cut from the fewest, cheapest stock lengths
/// (the core 1D cut planner), sheet goods cut from sheets by guillotine cuts (core sheet
/// cutting), both with kerf; hardware bought in packs.

#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/cut_plan.h"
#include "fabkit/core/diagnostics.h"
#include "fabkit/core/sheet_cutting.h"
#include "fabkit/templates/catalog.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates {

struct BomOptions {
  double saw_kerf_mm = 3.2;        ///< lumber and sheet cuts (a circular saw blade)
  double lumber_end_trim_mm = 10;  ///< discarded at each end of a board (rough factory ends)
  double sheet_edge_trim_mm = 5;   ///< trimmed off each factory edge of a sheet
  double pipe_kerf_mm = 2;         ///< a pipe or tube cutter
  CutPlanOptions cut_plan;
  SheetPlanOptions sheet_plan;
};

/// One line of the bill: an item, how many parts of it the design has, and what to buy.
struct BomLine {
  std::string item;
  std::string name;
  ItemCategory category = ItemCategory::kHardware;
  std::string supplier;
  std::string part_number;
  std::string unit;       ///< unit of sale ("box", "sheet", "length")
  int parts = 0;          ///< parts of this item in the design
  int units = 0;          ///< units to buy (packs, stock lengths, sheets)
  double unit_price = 0;  ///< USD per unit (for cut goods: see `buy`)
  double total = 0;       ///< USD
  std::string buy;        ///< "3 x 2438 mm at $3.88", "1 sheet 2440 x 1220 mm at $78.00"
  std::string sizes;      ///< "4 x 732 mm" (cut goods) or "" (hardware)
};

/// Lumber or pipe of one item: the cut plan on the chosen stock length.
struct LumberCuts {
  std::string item;
  std::vector<CutPiece> pieces;
  StockSpec stock;
  double stock_price = 0;
  CutPlan plan;
  double width_mm = 0;  ///< for drawings (the board's width)
};

/// Sheet goods of one item: each sheet with its stock size.
struct SheetCuts {
  std::string item;
  std::vector<SheetPiece> pieces;
  std::vector<SheetSpec> sheet_specs;  ///< per sheet of the plan (a mix of sizes is allowed)
  std::vector<double> sheet_prices;
  SheetPlan plan;  ///< sheets[i] is cut from sheet_specs[i]
};

struct BillOfMaterials {
  std::vector<BomLine> lines;  ///< by category, then item id
  double total = 0;            ///< USD: the sum of the lines
  std::vector<LumberCuts> lumber;
  std::vector<SheetCuts> sheets;
  int parts = 0;
  double milliseconds = 0;
};

/// The bill of `t` at its current q. nullopt with diagnostics when a part's item is unknown or
/// a piece is larger than every stock size of its item (piece-too-large, naming the part).
std::optional<BillOfMaterials> bill_of_materials(const Template& t,
                                                 const ItemCatalog& catalog,
                                                 Diagnostics& diags,
                                                 const BomOptions& options = {});

/// `category,item,name,parts,units,unit,unit_price_usd,total_usd,supplier,part_number,buy,sizes`
/// per line, then a TOTAL line (RFC 4180).
std::string bom_csv(const BillOfMaterials& bom);
/// The bill, cut plans and sheet layouts as JSON text (documented in docs/templates.md).
std::string bom_json(const BillOfMaterials& bom);

}  // namespace fabkit::templates

// The bill of materials: totals are the sum of the lines, counts match the parts, cut plans
// hold every piece, stock choice is the cheapest, oversize pieces are named.
#include "fabkit/templates/bom.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <map>

#include "fabkit/templates/database.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/manipulate.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::db;
using testing::has_diagnostic;

TEST(Bom, TotalsAreTheSumOfTheItemsAndCountsMatchTheParts) {
  for (const std::string& name : db().names()) {
    SCOPED_TRACE(name);
    const Template& t = *db().source_template(name);
    Diagnostics d;
    const auto bom = bill_of_materials(t, db().catalog(), d);
    ASSERT_TRUE(bom) << d.format();
    double sum = 0;
    int parts = 0;
    for (const BomLine& l : bom->lines) {
      sum += l.total;
      parts += l.parts;
      EXPECT_GT(l.units, 0) << l.item;
      const Item* it = db().catalog().find(l.item);
      ASSERT_TRUE(it);
      if (!it->cut_to_size()) {
        // Hardware: whole packs, enough of them, priced per pack.
        EXPECT_EQ(l.units, (l.parts + it->pack_quantity - 1) / it->pack_quantity);
        EXPECT_NEAR(l.total, l.units * it->price, 1e-9);
      }
    }
    EXPECT_NEAR(bom->total, sum, 1e-9);
    EXPECT_EQ(parts, t.part_count());
    EXPECT_EQ(bom->parts, t.part_count());
    for (const LumberCuts& c : bom->lumber) {
      EXPECT_TRUE(validate_cut_plan(c.plan, c.pieces, c.stock).empty()) << c.item;
    }
    for (const SheetCuts& c : bom->sheets) {
      for (std::size_t s = 0; s < c.plan.sheets.size(); ++s) {
        SheetPlan one;
        one.sheets = {c.plan.sheets[s]};
        std::vector<SheetPiece> pieces;
        for (SheetPlacement p : one.sheets[0].pieces) pieces.push_back(c.pieces[p.piece]);
        for (std::size_t i = 0; i < one.sheets[0].pieces.size(); ++i)
          one.sheets[0].pieces[i].piece = static_cast<int>(i);
        EXPECT_TRUE(validate_sheet_plan(one, pieces, c.sheet_specs[s]).empty()) << c.item;
      }
    }
    const std::string csv = bom_csv(*bom);
    EXPECT_NE(csv.find(fmt::format("TOTAL,,,{},,,,{:.2f}", bom->parts, bom->total)),
              std::string::npos);
  }
}

TEST(Bom, DiningTableLumberAndHardwareByHand) {
  const Template& t = *db().source_template("dining_table");
  Diagnostics d;
  const auto bom = bill_of_materials(t, db().catalog(), d);
  ASSERT_TRUE(bom);
  std::map<std::string, const BomLine*> by;
  for (const BomLine& l : bom->lines) by[l.item] = &l;
  // Four 732 mm legs from 4x4: 4·732 + 3 kerfs of 3.2 + 2 end trims of 10 = 2957.6 mm fit one
  // 3048 mm board ($15.48); a 2438 mm board holds only 3 (two cost $23.96), a 3658 mm one $18.98.
  ASSERT_TRUE(by.count("LUM-PINE-4x4"));
  EXPECT_EQ(by["LUM-PINE-4x4"]->units, 1);
  EXPECT_NEAR(by["LUM-PINE-4x4"]->total, 15.48, 1e-9);
  EXPECT_EQ(by["LUM-PINE-4x4"]->buy, "1 x 3048 mm at $15.48");
  EXPECT_EQ(by["LUM-PINE-4x4"]->sizes, "4 x 732 mm");
  // 8 brackets at 4 a pack; 8 x 4 bracket screws + 6 clip screws = 38, one box of 100.
  EXPECT_EQ(by["LBR-50"]->parts, 8);
  EXPECT_EQ(by["LBR-50"]->units, 2);
  EXPECT_EQ(by["SCR-3.5x16"]->parts, 38);
  EXPECT_EQ(by["SCR-3.5x16"]->units, 1);
  EXPECT_EQ(by["ZCLIP"]->parts, 6);
  // The top: one 1600 x 900 piece from a full 2440 x 1220 sheet.
  EXPECT_EQ(by["PLY-BIRCH-18"]->units, 1);
  EXPECT_NEAR(by["PLY-BIRCH-18"]->total, 78.0, 1e-9);
}

TEST(Bom, SmallSheetPiecesComeFromTheCheaperQuarterSheet) {
  const Template& t = *db().source_template("side_table");
  Diagnostics d;
  const auto bom = bill_of_materials(t, db().catalog(), d);
  ASSERT_TRUE(bom);
  for (const BomLine& l : bom->lines) {
    // The 450 x 400 top fits a 1200 x 600 panel ($34) rather than a 2400 x 600 one ($64).
    if (l.item == "PANEL-PINE-18") {
      EXPECT_NEAR(l.total, 34.0, 1e-9) << l.buy;
    }
  }
}

TEST(Bom, PieceLongerThanEveryStockIsNamed) {
  Template t = *db().source_template("dining_table");
  const Manipulator m(t);
  // A 2400 mm top is a feasible shape, but with 25 mm trimmed off each factory edge it no
  // longer comes from a 2440 mm sheet.
  const DragResult r = m.set(m.control(t.find("top"), ControlKind::kSizeX), 2400);
  ASSERT_TRUE(r.reached) << r.message;
  t.q = r.q;
  Diagnostics d;
  BomOptions o;
  o.sheet_edge_trim_mm = 25;  // 2440 − 2·25 = 2390 mm usable < 2400
  EXPECT_FALSE(bill_of_materials(t, db().catalog(), d, o));
  EXPECT_TRUE(has_diagnostic(
      d, codes::kPieceTooLarge, "part 'top' is 2400 x 900 mm; the largest sheet of PLY-BIRCH-18"));
}

}  // namespace
}  // namespace fabkit::templates

// Guillotine sheet cutting: plans are valid by an independent check, meet the area bound on
// cases where it is achievable, respect grain, kerf and trim, and name pieces that cannot fit.
#include "fabkit/core/sheet_cutting.h"

#include <gtest/gtest.h>

#include <random>

namespace fabkit {
namespace {

TEST(SheetCutting, FourQuartersFillOneSheetExactly) {
  // Four 1220 x 610 pieces on a 2440 x 1220 sheet with no kerf: one sheet, 100 % used.
  std::vector<SheetPiece> pieces(4, SheetPiece{"quarter", 1220, 610, true});
  Diagnostics d;
  const auto plan = plan_sheets(pieces, SheetSpec{2440, 1220, 0, 0}, d);
  ASSERT_TRUE(plan) << d.format();
  EXPECT_EQ(plan->sheet_count(), 1);
  EXPECT_TRUE(plan->meets_lower_bound);
  EXPECT_NEAR(plan->utilisation(SheetSpec{2440, 1220, 0, 0}), 1.0, 1e-12);
  EXPECT_TRUE(validate_sheet_plan(*plan, pieces, SheetSpec{2440, 1220, 0, 0}).empty());
  // With a 3 mm kerf the four no longer fit in one: (1223 · 613) · 4 > 2443 · 1223.
  const auto kerfed = plan_sheets(pieces, SheetSpec{2440, 1220, 3, 0}, d);
  ASSERT_TRUE(kerfed);
  EXPECT_EQ(kerfed->lower_bound, 2);
  EXPECT_EQ(kerfed->sheet_count(), 2);
}

TEST(SheetCutting, KerfAndTrimKeepPiecesApartAndInside) {
  std::vector<SheetPiece> pieces;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> len(80, 900), wid(60, 500);
  for (int i = 0; i < 40; ++i)
    pieces.push_back({std::string("p") + std::to_string(i), len(rng), wid(rng), i % 3 != 0});
  const SheetSpec sheet{2440, 1220, 3.2, 6};
  Diagnostics d;
  const auto plan = plan_sheets(pieces, sheet, d);
  ASSERT_TRUE(plan) << d.format();
  EXPECT_TRUE(validate_sheet_plan(*plan, pieces, sheet).empty())
      << validate_sheet_plan(*plan, pieces, sheet).format();
  EXPECT_GE(plan->sheet_count(), plan->lower_bound);
  EXPECT_LE(plan->sheet_count(), plan->lower_bound + 1);
  for (const SheetCut& s : plan->sheets) {
    for (const SheetPlacement& p : s.pieces) EXPECT_FALSE(p.rotated && !pieces[p.piece].may_rotate);
    // Every cut line lies inside the usable area.
    for (const SheetCutLine& c : s.cuts) {
      EXPECT_GE(std::min(c.x0, c.x1), sheet.edge_trim - 1e-9);
      EXPECT_LE(std::max(c.y0, c.y1), sheet.width - sheet.edge_trim + 1e-9);
    }
  }
}

TEST(SheetCutting, GrainForbidsTurningAPieceThatOnlyFitsTurned) {
  Diagnostics d;
  std::vector<SheetPiece> pieces = {{"tall door", 1000, 1500, false}};
  EXPECT_FALSE(plan_sheets(pieces, SheetSpec{2440, 1220, 3, 0}, d));
  ASSERT_FALSE(d.empty());
  EXPECT_EQ(d.items()[0].code, codes::kPieceLargerThanSheet);
  EXPECT_NE(d.items()[0].message.find(
                "'tall door' (1000 x 1500 mm, grain along the length) does not fit"),
            std::string::npos)
      << d.format();
  pieces[0].may_rotate = true;
  Diagnostics d2;
  const auto plan = plan_sheets(pieces, SheetSpec{2440, 1220, 3, 0}, d2);
  ASSERT_TRUE(plan);
  EXPECT_TRUE(plan->sheets[0].pieces[0].rotated);
}

TEST(SheetCutting, SvgIsAtTrueSizeAndCsvListsEveryPiece) {
  std::vector<SheetPiece> pieces = {
      {"side <L>", 782, 400, false}, {"side R", 782, 400, false}, {"top", 564, 400}};
  const SheetSpec sheet{2440, 1220, 3, 5};
  Diagnostics d;
  const auto plan = plan_sheets(pieces, sheet, d);
  ASSERT_TRUE(plan);
  const std::string svg = sheet_plan_svg(*plan, 0, pieces, sheet);
  EXPECT_NE(svg.find("width=\"2460mm\" height=\"1240mm\""), std::string::npos);
  EXPECT_NE(svg.find("side &lt;L&gt;"), std::string::npos);
  EXPECT_NE(svg.find("stroke=\"#d00\""), std::string::npos);
  const std::string csv = sheet_plan_csv(*plan, pieces);
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 4);
  EXPECT_NE(csv.find("top,564,400,1,"), std::string::npos);
}

}  // namespace
}  // namespace fabkit

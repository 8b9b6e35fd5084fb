#include "fabkit/core/nesting.h"

#include <gtest/gtest.h>

namespace fabkit {
namespace {

// Checks a nesting independently of libnest2d: with Clipper, every placed piece lies inside the
// sheet's margin and no two pieces on a sheet overlap or come closer than the spacing.
void expect_valid_layout(const std::vector<Polygon2d>& pieces,
                         const NestingResult& r,
                         const NestingOptions& o) {
  const Polygon2d usable = rectangle(
      o.margin_mm, o.margin_mm, o.sheet_width_mm - o.margin_mm, o.sheet_height_mm - o.margin_mm);
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const NestedPlacement& p = r.placements[i];
    ASSERT_GE(p.sheet, 0) << "piece " << i;
    const Polygon2d a = placed(pieces[i], p);
    EXPECT_NEAR(area(subtract({a}, {usable})), 0, 1e-3) << "piece " << i << " leaves the sheet";
    for (std::size_t j = i + 1; j < pieces.size(); ++j) {
      if (r.placements[j].sheet != p.sheet) continue;
      const Polygon2d b = placed(pieces[j], r.placements[j]);
      // Grown by just under half the spacing, two pieces may touch but never overlap.
      const double g = o.spacing_mm / 2 - 0.01;
      EXPECT_NEAR(area(intersect(offset({a}, g), offset({b}, g))), 0, 1e-3) << i << " and " << j;
    }
  }
}

TEST(Nesting, PlacesEveryPieceWithoutOverlapOnSeveralSheets) {
  std::vector<Polygon2d> pieces;
  for (int i = 0; i < 6; ++i) pieces.push_back(rectangle(0, 0, 250, 150));
  Polygon2d l;
  l.outer = {{0, 0}, {200, 0}, {200, 40}, {40, 40}, {40, 120}, {0, 120}};
  pieces.push_back(l);
  NestingOptions o;
  const NestingResult r = nest(pieces, {}, o);
  ASSERT_FALSE(r.diagnostics.has_errors()) << r.diagnostics.format();
  // 6 × 250 × 150 mm cannot go on one 600 × 400 sheet (two rows of two fit with margins).
  EXPECT_GE(r.sheet_count, 2);
  EXPECT_LE(r.sheet_count, 3);
  expect_valid_layout(pieces, r, o);
  double total = 0;
  for (const Polygon2d& p : pieces) total += p.area();
  EXPECT_NEAR(r.utilisation, total / (600.0 * 400 * r.sheet_count), 1e-9);
}

TEST(Nesting, IsDeterministic) {
  std::vector<Polygon2d> pieces;
  for (int i = 0; i < 5; ++i) pieces.push_back(rectangle(0, 0, 90 + 10 * i, 60));
  const NestingResult a = nest(pieces, {}, {});
  const NestingResult b = nest(pieces, {}, {});
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    EXPECT_EQ(a.placements[i].sheet, b.placements[i].sheet);
    EXPECT_EQ(a.placements[i].translation, b.placements[i].translation);
  }
}

TEST(Nesting, APieceTooLargeIsNamedWithItsSize) {
  const NestingResult r = nest({rectangle(0, 0, 700, 100)}, {"top"}, {});
  ASSERT_TRUE(r.diagnostics.has_errors());
  EXPECT_NE(
      r.diagnostics.format().find("top (700.0 × 100.0 mm) does not fit on a 600 × 400 mm sheet"),
      std::string::npos)
      << r.diagnostics.format();
  EXPECT_EQ(r.unplaced, std::vector<int>{0});
}

TEST(Nesting, RotationLetsALongPieceFit) {
  NestingOptions o;
  o.sheet_width_mm = 200;
  o.sheet_height_mm = 500;
  const std::vector<Polygon2d> pieces{rectangle(0, 0, 400, 50)};
  const NestingResult r = nest(pieces, {}, o);
  ASSERT_FALSE(r.diagnostics.has_errors()) << r.diagnostics.format();
  expect_valid_layout(pieces, r, o);
  o.rotations_deg = {0};
  EXPECT_TRUE(nest(pieces, {}, o).diagnostics.has_errors());
}

TEST(Nesting, BadOptionsAreNamed) {
  NestingOptions o;
  o.sheet_width_mm = -1;
  o.rotations_deg.clear();
  const Diagnostics d = o.validate();
  EXPECT_NE(d.format().find("sheet size -1"), std::string::npos);
  EXPECT_NE(d.format().find("at least one allowed rotation"), std::string::npos);
}

}  // namespace
}  // namespace fabkit

// The burn-test sheet (issue item 6): every cell's joints measured on the sheet's outlines
// against Appendix A's formulas for its Δ and δ, its label, the sheet's exact size, and the
// command-line value lists.
#include "fabkit/flatpack/burn_test.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "fabkit/core/dxf.h"
#include "fabkit/flatpack/build.h"
#include "fabkit/flatpack/joint_widths.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

std::vector<double> parse(const std::string& text, Diagnostics& d) {
  return parse_value_list(text, "--kerf", d);
}

TEST(BurnTest, ValueListsAreValuesListsOrInclusiveRanges) {
  Diagnostics d;
  const std::vector<double> range = parse("0.05:0.25:0.05", d);
  ASSERT_FALSE(d.has_errors()) << d.format();
  ASSERT_EQ(range.size(), 5u);
  for (std::size_t k = 0; k < 5; ++k)
    EXPECT_NEAR(range[k], 0.05 * static_cast<double>(k + 1), 1e-12);
  EXPECT_EQ(fmt::format("{:g}", range[2]), "0.15");  // labels read 0.15, not 0.15000000000000002
  EXPECT_EQ(parse("0.1, 0.15,0.3", d), (std::vector<double>{0.1, 0.15, 0.3}));
  EXPECT_EQ(parse("0", d), (std::vector<double>{0}));
  EXPECT_EQ(parse("0:0.1:0.05,0.3", d), (std::vector<double>{0, 0.05, 0.1, 0.3}));
  EXPECT_FALSE(d.has_errors()) << d.format();
  for (const char* bad : {"", "x", "0.1:0.2", "0.2:0.1:0.05", "0:0.1:0", "0.1,,0.2", "1e999"}) {
    Diagnostics e;
    EXPECT_TRUE(parse(bad, e).empty()) << bad;
    EXPECT_TRUE(e.has_errors()) << bad;
    EXPECT_NE(e.format().find("--kerf"), std::string::npos) << e.format();
  }
  Diagnostics many;
  parse("0:1:0.01", many);
  EXPECT_NE(many.format().find("has 101 values; at most 20 fit a sheet"), std::string::npos)
      << many.format();
}

// The stretches of material along a horizontal line through a ring.
std::vector<LineStretch> across(const Ring& ring, double y) {
  Polygon2d p;
  p.outer = ring;
  return classify_line(oriented(p), Vec2(-1e3, y), Vec2(1, 0));
}

class Cells : public ::testing::TestWithParam<double> {};

TEST_P(Cells, EveryJointIsDrawnToTheFormulaForItsKerfAndInterference) {
  const double t = GetParam();
  BurnTestOptions o;
  o.material.name = "birch";
  o.material.thickness_mm = t;
  o.kerfs_mm = {0, 0.1, 0.25};
  o.interferences_mm = {0, 0.05, 0.2};
  const BurnTest b = burn_test(o);
  ASSERT_FALSE(b.diagnostics.has_errors()) << b.diagnostics.format();
  ASSERT_EQ(b.cells.size(), 9u);
  ASSERT_EQ(b.sheet.labels.size(), 9u);
  const double w = 3 * t;
  for (std::size_t k = 0; k < b.cells.size(); ++k) {
    const BurnTestCell& c = b.cells[k];
    EXPECT_EQ(c.kerf_mm, o.kerfs_mm[k / 3]);
    EXPECT_EQ(c.interference_mm, o.interferences_mm[k % 3]);
    const double kerf = c.kerf_mm, fit = c.interference_mm;
    SCOPED_TRACE(fmt::format("t {} Δ {} δ {}", t, kerf, fit));
    // The label names the cell's values and sits in it.
    const SheetLabel& label = b.sheet.labels[k];
    EXPECT_EQ(label.text, fmt::format("Δ {:g} δ {:g}", kerf, fit));
    EXPECT_TRUE(label.position.x() > c.box.min.x() && label.position.x() < c.box.max.x() &&
                label.position.y() > c.box.min.y() && label.position.y() < c.box.max.y());
    // The cell's two outlines: the comb (lower) and the dent strip with its slot (upper).
    std::vector<const Ring*> rings;
    for (const SheetOutline& s : b.sheet.outlines) {
      const Box2d box = bounds(s.points);
      if (box.min.x() >= c.box.min.x() - 1e-9 && box.max.x() <= c.box.max.x() + 1e-9 &&
          box.min.y() >= c.box.min.y() - 1e-9 && box.max.y() <= c.box.max.y() + 1e-9)
        rings.push_back(&s.points);
    }
    ASSERT_EQ(rings.size(), 2u);
    if (bounds(*rings[0]).min.y() > bounds(*rings[1]).min.y()) std::swap(rings[0], rings[1]);
    const Box2d comb = bounds(*rings[0]), strip = bounds(*rings[1]);
    // Fingers, half a board below the comb's top: three, each w + (4Δ + δ)/2 wide.
    const auto fingers = across(*rings[0], comb.max.y() - t / 2);
    ASSERT_EQ(fingers.size(), 3u);
    const double finger = fingers[0].s1 - fingers[0].s0;
    EXPECT_NEAR(finger, w + (4 * kerf + fit) / 2, 1e-6);
    // Dents, half a board above the strip's open edge: the gaps between its material.
    const auto teeth = across(*rings[1], strip.min.y() + t / 2);
    ASSERT_EQ(teeth.size(), 4u);
    for (std::size_t g = 0; g + 1 < teeth.size(); ++g) {
      const double dent = teeth[g + 1].s0 - teeth[g].s1;
      // w_f = w_d + 4Δ + δ (Appendix A.1.1), and once cut the finger is δ wider than the dent.
      EXPECT_NEAR(finger - dent, 4 * kerf + fit, 1e-6);
      EXPECT_NEAR(cut_solid_width(finger, kerf) - cut_opening_width(dent, kerf), fit, 1e-6);
      EXPECT_NEAR(dent, c.dent_mm, 1e-6);
    }
    // The slot, half a board below the strip's top: cut, it is δ narrower than the board.
    const auto sides = across(*rings[1], strip.max.y() - t / 2);
    ASSERT_EQ(sides.size(), 2u);
    const double slot = sides[1].s0 - sides[0].s1;
    EXPECT_NEAR(slot, t - 2 * kerf - fit, 1e-6);
    EXPECT_NEAR(cut_opening_width(slot, kerf), t - fit, 1e-6);
    EXPECT_NEAR(slot, c.slot_mm, 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(Thicknesses, Cells, ::testing::Values(3.0, 6.0));

TEST(BurnTest, TheSheetIsExactlyAsLargeAsItsCellsAndOpensAtScale) {
  BurnTestOptions o;
  o.material.thickness_mm = 3;
  o.kerfs_mm = {0.1, 0.2, 0.3};
  o.interferences_mm = {0, 0.1};
  const BurnTest b = burn_test(o);
  ASSERT_FALSE(b.diagnostics.has_errors()) << b.diagnostics.format();
  // Margin 5, two columns of 7 × 9 mm strips 10 apart; three rows of 32 mm cells 10 apart.
  EXPECT_DOUBLE_EQ(b.sheet.width_mm, 5 + 63 + 10 + 63 + 5);
  EXPECT_DOUBLE_EQ(b.sheet.height_mm, 5 + 3 * 32 + 2 * 10 + 5);
  Box2d all;
  for (const SheetOutline& s : b.sheet.outlines) {
    for (const Vec2& p : s.points) all.extend(p);
  }
  EXPECT_NEAR(all.min.x(), 5, 1e-9);
  EXPECT_NEAR(all.max.x(), b.sheet.width_mm - 5, 1e-9);
  EXPECT_GE(all.min.y(), 5 - 1 - 1e-9);  // dents open 1 mm past the strip's edge
  EXPECT_LE(all.max.y(), b.sheet.height_mm - 5);
  const std::string svg = svg_sheet(b.sheet);
  EXPECT_NE(svg.find("width=\"146mm\" height=\"126mm\" viewBox=\"0 0 146 126\""), std::string::npos)
      << svg.substr(0, 400);
}

// AutoCAD 2000 DXF text is in a code page, not UTF-8: labels go out with \U+XXXX escapes.
TEST(BurnTest, DxfLabelsEscapeWhatIsNotAscii) {
  CutSheet s;
  s.labels.push_back({"Δ 0.1 δ 0.05", Vec2::Zero(), 3, 0});
  s.labels.push_back({"→ leg_a", Vec2::Zero(), 3, 0});
  s.labels.push_back({"plain", Vec2::Zero(), 3, 0});
  const CutSheet d = for_dxf(s);
  EXPECT_EQ(d.labels[0].text, "\\U+0394 0.1 \\U+03B4 0.05");
  EXPECT_EQ(d.labels[1].text, "\\U+2192 leg_a");
  EXPECT_EQ(d.labels[2].text, "plain");
  Diagnostics diags;
  const auto dxf = dxf_sheet(d, diags);
  ASSERT_TRUE(dxf) << diags.format();
  for (char c : *dxf) EXPECT_LT(static_cast<unsigned char>(c), 0x80);
}

TEST(BurnTest, ValuesThatMakeNoJointAreRefusedByName) {
  auto refused = [](BurnTestOptions o, const std::string& expected) {
    const BurnTest b = burn_test(o);
    EXPECT_TRUE(b.diagnostics.has_errors());
    EXPECT_TRUE(b.cells.empty());
    EXPECT_NE(b.diagnostics.format().find(expected), std::string::npos) << b.diagnostics.format();
  };
  BurnTestOptions o;
  o.kerfs_mm = {0.1};
  o.interferences_mm = {0.1};
  BurnTestOptions thin = o;
  thin.material.thickness_mm = 0;
  refused(thin, "board thickness 0 mm must be more than 0");
  BurnTestOptions kerf = o;
  kerf.kerfs_mm = {0.1, 2.5};
  refused(kerf, "kerf 2.5 mm is outside 0 … 2 mm (the kerf values are 0.1, 2.5)");
  BurnTestOptions none = o;
  none.interferences_mm.clear();
  refused(none, "no interference values");
  BurnTestOptions narrow = o;
  narrow.finger_width_mm = 1;
  narrow.kerfs_mm = {0.4};
  refused(narrow, "with kerf 0.4 mm and interference 0.1 mm a dent would be drawn 0.15 mm");
  BurnTestOptions many = o;
  many.kerfs_mm.assign(21, 0.1);
  refused(many, "21 kerf values; at most 20 fit a sheet");
}

}  // namespace
}  // namespace fabkit::flatpack

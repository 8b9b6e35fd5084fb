#include "fabkit/core/glyph_outline.h"

#include <gtest/gtest.h>

#include "fabkit/core/extrude.h"
#include "fabkit/core/mesh_boolean.h"

namespace fabkit {
namespace {

TextOutlineOptions sized(double em) {
  TextOutlineOptions o;
  o.em_size = em;
  return o;
}

TEST(GlyphOutline, DigitsFromDejaVuHaveTheirHoles) {
  Diagnostics d;
  const auto zero = text_outline("0", sized(10), d);
  ASSERT_TRUE(zero) << d.format();
  EXPECT_EQ(zero->rings.size(), 2u);  // outer and counter
  const auto eight = text_outline("8", sized(10), d);
  ASSERT_TRUE(eight);
  EXPECT_EQ(eight->rings.size(), 3u);
  const auto one = text_outline("1", sized(10), d);
  ASSERT_TRUE(one);
  EXPECT_EQ(one->rings.size(), 1u);
  // DejaVu digits are 0.729 em tall (cap height) and advance 0.696 em in the bold face.
  EXPECT_NEAR(zero->max.y() - zero->min.y(), 7.4, 0.3);
  EXPECT_NEAR(zero->advance, 6.96, 0.01);
  EXPECT_GT(zero->area(), 10);
  EXPECT_LT(zero->area(), (zero->max - zero->min).prod());
}

TEST(GlyphOutline, TwoDigitsSideBySideScaleWithSize) {
  Diagnostics d;
  const auto small = text_outline("07", sized(5), d);
  const auto big = text_outline("07", sized(10), d);
  ASSERT_TRUE(small && big) << d.format();
  EXPECT_EQ(big->rings.size(), 3u);
  EXPECT_NEAR(big->area(), 4 * small->area(), 0.02 * big->area());
  EXPECT_GT(big->max.x(), big->advance * 0.9);
}

TEST(GlyphOutline, ExtrudedTextIsASolid) {
  Diagnostics d;
  const auto text = text_outline("48", sized(8), d);
  ASSERT_TRUE(text);
  const TriangleMesh solid = extrude_rings(text->rings, 0, 1);
  const SolidCheck c = check_solid(solid);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_NEAR(c.volume, text->area(), 1e-6 * text->area());
}

TEST(GlyphOutline, MissingFontIsAnUnreadableFile) {
  Diagnostics d;
  EXPECT_FALSE(text_outline("1", TextOutlineOptions{"/nonexistent/font.ttf", 10, 0.02}, d));
  EXPECT_EQ(d.items().at(0).code, codes::kUnreadableFile);
  EXPECT_NE(d.format().find("/nonexistent/font.ttf"), std::string::npos);
}

}  // namespace
}  // namespace fabkit

#include <gtest/gtest.h>

#include "fabkit/flatpack/component.h"

namespace fabkit::flatpack {
namespace {

TEST(Components, EveryIssueTypeIsRegistered) {
  for (const char* name : {"Rectangle",
                           "Square",
                           "RightTriangle",
                           "IsoscelesTriangle",
                           "Trapezoid",
                           "RegularPolygon",
                           "LShape",
                           "UShape",
                           "Disc",
                           "Polygon"}) {
    EXPECT_NE(ComponentLibrary::builtin().find(name), nullptr) << name;
  }
}

TEST(Components, RectangleEdgesFollowThePaper) {
  const ComponentType* t = ComponentLibrary::builtin().find("Rectangle");
  std::string error;
  const auto s = t->generate({{"l", 30}, {"w", 60}}, {}, error);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->polygon.area(), 1800, 1e-9);
  ASSERT_EQ(s->edges.size(), 4u);
  EXPECT_EQ(s->edges[2].name, "t");  // from (l, w) to (0, w)
  EXPECT_EQ(s->polygon.outer[2], Vec2(30, 60));
  EXPECT_GT(signed_area(s->polygon.outer), 0);  // front faces +z
}

TEST(Components, UShapeRejectsANotchWiderThanThePanel) {
  const ComponentType* t = ComponentLibrary::builtin().find("UShape");
  std::string error;
  EXPECT_FALSE(t->generate({{"l", 100}, {"w", 50}, {"nl", 120}, {"nw", 10}}, {}, error));
  EXPECT_NE(error.find("notch nl = 120 mm"), std::string::npos) << error;
  const auto ok = t->generate({{"l", 100}, {"w", 50}, {"nl", 40}, {"nw", 10}}, {}, error);
  ASSERT_TRUE(ok);
  EXPECT_NEAR(ok->polygon.area(), 100 * 50 - 40 * 10, 1e-9);
}

}  // namespace
}  // namespace fabkit::flatpack

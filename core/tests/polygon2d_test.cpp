#include "fabkit/core/polygon2d.h"

#include <gtest/gtest.h>

#include <map>

namespace fabkit {
namespace {

// Every edge of a closed, consistently oriented mesh is used once in each direction.
bool closed_and_oriented(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : m.faces) {
    for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  }
  for (const auto& [e, n] : directed) {
    if (n != 1) return false;
    auto back = directed.find({e.second, e.first});
    if (back == directed.end() || back->second != 1) return false;
  }
  return !m.faces.empty();
}

TEST(Polygon2d, BooleansOfTwoSquaresHaveHandComputedAreas) {
  const Region2d a{rectangle(0, 0, 10, 10)};
  const Region2d b{rectangle(5, 5, 15, 15)};
  EXPECT_NEAR(area(unite(a, b)), 175, 1e-6);
  EXPECT_NEAR(area(intersect(a, b)), 25, 1e-6);
  EXPECT_NEAR(area(subtract(a, b)), 75, 1e-6);
  // Touching squares merge into one polygon (the coplanar merge of the flatpack kit relies on it).
  const Region2d touching = unite({rectangle(0, 0, 10, 10)}, {rectangle(10, 0, 20, 10)});
  ASSERT_EQ(touching.size(), 1u);
  EXPECT_NEAR(touching[0].area(), 200, 1e-6);
}

TEST(Polygon2d, DifferenceMakesAHoleThatIsClockwise) {
  const Region2d r = subtract({rectangle(0, 0, 10, 10)}, {rectangle(4, 4, 6, 6)});
  ASSERT_EQ(r.size(), 1u);
  ASSERT_EQ(r[0].holes.size(), 1u);
  EXPECT_GT(signed_area(r[0].outer), 0);
  EXPECT_LT(signed_area(r[0].holes[0]), 0);
  EXPECT_NEAR(r[0].area(), 96, 1e-6);
}

TEST(Polygon2d, MiterOffsetKeepsRectanglesExact) {
  const Region2d grown = offset({rectangle(0, 0, 10, 4)}, 1.5);
  ASSERT_EQ(grown.size(), 1u);
  const Box2d box = bounds(grown);
  EXPECT_NEAR(box.min.x(), -1.5, 1e-4);
  EXPECT_NEAR(box.max.y(), 5.5, 1e-4);
  EXPECT_NEAR(grown[0].area(), 13 * 7, 1e-3);
}

TEST(Polygon2d, LineAlongAnEdgeIsBoundaryAndThroughTheFaceIsInside) {
  const Polygon2d p = rectangle(0, 0, 10, 4);
  // Along the bottom edge.
  auto s = classify_line(p, Vec2(-5, 0), Vec2(1, 0));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].where, PointLocation::kBoundary);
  EXPECT_NEAR(s[0].s0, 5, 1e-9);
  EXPECT_NEAR(s[0].s1, 15, 1e-9);
  // Across the middle.
  s = classify_line(p, Vec2(3, -1), Vec2(0, 2));
  ASSERT_EQ(s.size(), 1u);
  EXPECT_EQ(s[0].where, PointLocation::kInside);
  EXPECT_NEAR(s[0].s0, 1, 1e-9);
  EXPECT_NEAR(s[0].s1, 5, 1e-9);
  // Through a hole: two stretches.
  const Region2d holed = subtract({p}, {rectangle(4, 1, 6, 3)});
  s = classify_line(holed[0], Vec2(0, 2), Vec2(1, 0));
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[0].s1, 4, 1e-4);
  EXPECT_NEAR(s[1].s0, 6, 1e-4);
  // Missing the polygon.
  EXPECT_TRUE(classify_line(p, Vec2(0, 9), Vec2(1, 0)).empty());
}

TEST(Polygon2d, LocateUsesTheTolerance) {
  const Polygon2d p = rectangle(0, 0, 10, 10);
  EXPECT_EQ(locate(p, Vec2(5, 5)), PointLocation::kInside);
  EXPECT_EQ(locate(p, Vec2(10, 5)), PointLocation::kBoundary);
  EXPECT_EQ(locate(p, Vec2(10.5, 5)), PointLocation::kOutside);
  EXPECT_EQ(locate(p, Vec2(10.5, 5), 1.0), PointLocation::kBoundary);
}

TEST(Polygon2d, ExtrusionWithAHoleIsClosedWithTheRightVolume) {
  const Region2d r = subtract({rectangle(0, 0, 10, 10)}, {rectangle(4, 4, 6, 6)});
  const TriangleMesh m = extrude(r[0], -1.5, 1.5);
  EXPECT_TRUE(closed_and_oriented(m));
  EXPECT_NEAR(m.volume(), 96 * 3, 1e-6);
  // A non-convex outline (an L) too.
  Polygon2d l;
  l.outer = {{0, 0}, {10, 0}, {10, 3}, {3, 3}, {3, 10}, {0, 10}};
  const TriangleMesh ml = extrude(l, 0, 6);
  EXPECT_TRUE(closed_and_oriented(ml));
  EXPECT_NEAR(ml.volume(), l.area() * 6, 1e-6);
}

TEST(Polygon2d, InteriorPointIsInsideANotchedShape) {
  Polygon2d u;
  u.outer = {{0, 0}, {3, 0}, {3, 7}, {7, 7}, {7, 0}, {10, 0}, {10, 10}, {0, 10}};
  const Vec2 p = interior_point(u);
  EXPECT_EQ(locate(u, p), PointLocation::kInside);
  EXPECT_GT(boundary_distance(u, p), 1.0);
}

}  // namespace
}  // namespace fabkit

#include <gtest/gtest.h>

#include <cmath>

#include "fabkit/flatpack/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

using test::check_yaml;

// Fig. 3: A.t → B.b, front-front, rotation (90, 0, 0): A folds up about B's bottom edge.
TEST(Placement, PaperFig3MatchesTheHandComputedFrame) {
  const Analysis a = check_yaml(
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 30, w: 60}\n"
      "  - {name: B, type: Rectangle, l: 30, w: 60}\n"
      "connections:\n  - {connect: [A.t, B.b], alignment: front-front, rotation: [90, 0, 0]}\n");
  ASSERT_TRUE(a.placed) << a.diagnostics.format();
  // A's top edge lies on B's bottom edge (midpoints together, directions opposite), then A turns
  // 90° about it towards its front. By hand, in B's frame: A's (x, y) ↦ (x, 0, 60 − y).
  const Mat4 rel = rigid_inverse(a.components[1].frame) * a.components[0].frame;  // A in B
  auto at = [&](double x, double y) { return Vec3((rel * Eigen::Vector4d(x, y, 0, 1)).head<3>()); };
  EXPECT_LT((at(0, 60) - Vec3(0, 0, 0)).norm(), 1e-9) << at(0, 60).transpose();
  EXPECT_LT((at(30, 60) - Vec3(30, 0, 0)).norm(), 1e-9) << at(30, 60).transpose();
  EXPECT_LT((at(0, 0) - Vec3(0, 0, 60)).norm(), 1e-9) << at(0, 0).transpose();
  EXPECT_LT((at(30, 10) - Vec3(30, 0, 50)).norm(), 1e-9) << at(30, 10).transpose();
}

TEST(Placement, FrontBackFlipsTheFaceAndOffsetsMoveAlongTheEdgeFrame) {
  const Analysis a = check_yaml(
      "fabkit: flatpack/1\ncomponents:\n  - {name: B, type: Rectangle, l: 100, w: 50}\n"
      "  - {name: A, type: Rectangle, l: 20, w: 10}\n"
      "connections:\n  - {connect: [A.b, B.t], alignment: front-back, offset: [5, -10, 2]}\n");
  ASSERT_TRUE(a.placed) << a.diagnostics.format();
  const Mat4 rel = rigid_inverse(a.components[0].frame) * a.components[1].frame;  // A in B
  // B's t edge runs from (100, 50) to (0, 50): its frame x = −x, y (into B) = −y, origin (50, 50).
  // Front-back: A's b edge runs along it in the same direction, A on the far side (y > 50),
  // flipped (normal −z); the offset (5, −10, 2) is in B's edge frame: x −5, y +10, z +2.
  EXPECT_LT((rel.block<3, 1>(0, 2) - Vec3(0, 0, -1)).norm(), 1e-12);
  auto at = [&](double x, double y) { return Vec3((rel * Eigen::Vector4d(x, y, 0, 1)).head<3>()); };
  EXPECT_LT((at(10, 0) - Vec3(45, 60, 2)).norm(), 1e-9) << at(10, 0).transpose();
  EXPECT_LT((at(0, 0) - Vec3(55, 60, 2)).norm(), 1e-9) << at(0, 0).transpose();
  EXPECT_LT((at(0, 10) - Vec3(55, 70, 2)).norm(), 1e-9) << at(0, 10).transpose();
}

TEST(Placement, ACycleThatDoesNotCloseIsReportedWithItsResidual) {
  const Analysis a = check_yaml(
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 30, w: 30}\n"
      "  - {name: B, type: Rectangle, l: 30, w: 30}\n  - {name: C, type: Rectangle, l: 30, w: 30}\n"
      "connections:\n  - {connect: [B.l, A.r]}\n  - {connect: [C.l, B.r]}\n"
      "  - {connect: [C.b, A.t], offset: [0, 0, 5], name: closing}\n");
  ASSERT_TRUE(test::has_code(a.diagnostics, codes::kCycleMismatch)) << a.diagnostics.format();
  const std::string text = a.diagnostics.format();
  EXPECT_NE(text.find("disagrees with the placement the other connections give C by"),
            std::string::npos)
      << text;
  for (const char* name : {"closing", "c1", "c2"})
    EXPECT_NE(text.find(name), std::string::npos) << text;
  EXPECT_NE(text.find("does not close"), std::string::npos) << text;
  // The residual as numbers. Breadth first from A, "closing" places C on A's top edge (x 0..30,
  // y 30..60, 5 mm up); c2, met last, would put it beside B (x 60..90, y 0..30, z 0), unturned:
  // every corner (60, −30, −5) away.
  ASSERT_EQ(a.residuals.size(), 1u);
  EXPECT_EQ(a.residuals[0].name, "c2");
  EXPECT_EQ(a.residuals[0].component, "C");
  EXPECT_EQ(a.residuals[0].connection, 1);
  EXPECT_FALSE(a.residuals[0].closes);
  EXPECT_NEAR(a.residuals[0].position_mm, std::sqrt(60.0 * 60 + 30 * 30 + 5 * 5), 1e-9);
  EXPECT_NEAR(a.residuals[0].angle_deg, 0, 1e-9);
  // c2 would put C unturned with its corner at (60, 0, 0); C is where "closing" put it, its
  // bottom edge on A's top edge: corner at (0, 30), 5 mm up.
  const Mat4& by_c2 = a.residuals[0].frame;
  EXPECT_LT((by_c2.topLeftCorner<3, 3>() - Eigen::Matrix3d::Identity()).norm(), 1e-9);
  EXPECT_LT((by_c2.topRightCorner<3, 1>() - Vec3(60, 0, 0)).norm(), 1e-9) << by_c2;
  EXPECT_LT((a.components[2].frame.topRightCorner<3, 1>() - Vec3(0, 30, 5)).norm(), 1e-9)
      << a.components[2].frame;
}

// Unconnected components sit at the origin and, being coplanar, merge into one piece; with
// separate_groups_mm each further group is laid beside the previous ones instead.
TEST(Placement, UnconnectedGroupsAreLaidSideBySideWhenAsked) {
  const std::string yaml =
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 30, w: 60}\n"
      "  - {name: B, type: Rectangle, l: 40, w: 60}\n  - {name: C, type: Rectangle, l: 20, w: 10}\n"
      "  - {name: D, type: Rectangle, l: 20, w: 10}\n"
      "connections:\n  - {connect: [D.b, C.t], rotation: [90, 0, 0]}\n";
  const Analysis at_origin = check_yaml(yaml);
  ASSERT_TRUE(at_origin.placed) << at_origin.diagnostics.format();
  EXPECT_EQ(at_origin.pieces.size(), 2u);  // A, B and C merge; D stands on C
  Diagnostics d;
  const Design design = test::parse(yaml, d);
  CheckOptions options;
  options.separate_groups_mm = 50;
  const Analysis apart = check(design, options);
  ASSERT_TRUE(apart.placed) << apart.diagnostics.format();
  ASSERT_EQ(apart.pieces.size(), 4u);
  // A spans x 0..30; B starts 50 mm after it, C (with D) 50 mm after B: x = 80 and 170.
  auto min_x = [&](int c) {
    double lo = 1e9;
    for (const Vec2& p : apart.components[static_cast<std::size_t>(c)].shape.polygon.outer)
      lo = std::min(lo,
                    (apart.components[static_cast<std::size_t>(c)].frame *
                     Eigen::Vector4d(p.x(), p.y(), 0, 1))
                        .x());
    return lo;
  };
  EXPECT_NEAR(min_x(0), 0, 1e-9);
  EXPECT_NEAR(min_x(1), 80, 1e-9);
  EXPECT_NEAR(min_x(2), 170, 1e-9);
  EXPECT_NEAR(min_x(3), 170, 1e-9);    // D moved with C
  EXPECT_EQ(apart.joints.size(), 1u);  // C–D still joined, nothing else touches
  EXPECT_NE(apart.diagnostics.format().find("beside the others"), std::string::npos);
}

}  // namespace
}  // namespace fabkit::flatpack

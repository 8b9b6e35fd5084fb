#include "fabkit/rods/layout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "test_support.h"

namespace fabkit::rods {
namespace {

using test::two_rods_at;

Parameters params(double r, double eps) {
  Parameters p;
  p.radius = r;
  p.tolerance = eps;
  return p;
}

TEST(Layout, OffsetAtRightAngleIsRadiusPlusTolerance) {
  const Layout l = compute_layout(two_rods_at(90), params(5, 0.2));
  EXPECT_NEAR(l.ends[0][0].max_cosine, 0, 1e-12);
  EXPECT_NEAR(l.ends[0][0].offset, 5.2, 1e-12);  // g = (r + ε) · √(1/1)
  EXPECT_NEAR(l.ends[1][0].offset, 5.2, 1e-12);
}

TEST(Layout, OffsetAt60DegreesIsRootThreeTimes) {
  const Layout l = compute_layout(two_rods_at(60), params(5, 0.2));
  EXPECT_NEAR(l.ends[0][0].max_cosine, 0.5, 1e-12);
  EXPECT_NEAR(l.ends[0][0].offset, 5.2 * std::sqrt(3.0), 1e-9);  // √((1 + ½) / (1 − ½))
}

TEST(Layout, OffsetAt16DegreesIsCotangentOfHalfAngle) {
  // The guitar stand's 16°: g = (r + ε) / tan 8° = 7.115 (r + ε); 6.5 mm → 46.25 mm.
  const Layout l = compute_layout(two_rods_at(16), params(6.35, 0.15));
  EXPECT_NEAR(l.ends[0][0].offset, 6.5 / std::tan(8 * kDegToRad), 1e-9);
  EXPECT_NEAR(l.ends[0][0].offset, 46.25, 0.01);
  // Hand-computed from Eq. (6) with c = cos 16° = 0.961262.
  EXPECT_NEAR(safe_offset(0.961262, 6.5), 6.5 * std::sqrt(1.961262 / 0.038738), 1e-9);
}

TEST(Layout, ObtuseAndStraightAngles) {
  EXPECT_NEAR(safe_offset(-0.5, 1), std::sqrt(1.0 / 3.0), 1e-12);  // 120°
  EXPECT_NEAR(safe_offset(-1, 1), 0, 1e-12);                       // 180°: rods butt at the node
  EXPECT_TRUE(std::isinf(safe_offset(1, 1)));
}

TEST(Layout, LargestCosineDecidesAtEachEnd) {
  // Three rods at a node: 30° and 100° from the first; the first's offset follows the 30°.
  const double a = 30 * kDegToRad, b = 100 * kDegToRad;
  const Structure s = test::make_structure({{0, 0, 0},
                                            {100, 0, 0},
                                            {100 * std::cos(a), 100 * std::sin(a), 0},
                                            {100 * std::cos(b), 100 * std::sin(b), 0}},
                                           {{1, 2}, {1, 3}, {1, 4}});
  const Layout l = compute_layout(s, params(3, 0));
  EXPECT_NEAR(l.end_at(0, 0).offset, 3 / std::tan(15 * kDegToRad), 1e-9);
  EXPECT_EQ(l.end_at(0, 0).closest_rod, 1);
  EXPECT_NEAR(l.end_at(2, 0).offset, 3 / std::tan(35 * kDegToRad), 1e-9);  // 70° to the 30° rod
}

TEST(Layout, LeafNodesTakeTheLeafOffsetAndLengthsFollowEq7) {
  Parameters p = params(5, 0.2);
  p.leaf_offset = 4;
  const Layout l = compute_layout(two_rods_at(60), p);
  EXPECT_EQ(l.ends[0][1].closest_rod, -1);
  EXPECT_EQ(l.ends[0][1].offset, 4);
  EXPECT_NEAR(l.edge_length[0], 100, 1e-12);
  EXPECT_NEAR(
      l.rod_length[0], 100 - 5.2 * std::sqrt(3.0) - 4, 1e-9);  // ℓ = ‖p_j − p_i‖ − g_ij − g_ji
}

TEST(Layout, RotationAlignsZWithTheEdgeEq1) {
  for (const Vec3& w : {Vec3(1, 0, 0),
                        Vec3(0, 0, 1),
                        Vec3(0, 0, -1),
                        Vec3(1, 2, -3).normalized(),
                        Vec3(1e-9, 0, -1).normalized()}) {
    const Mat3 r = rotation_to(w);
    EXPECT_LT((r * Vec3::UnitZ() - w).norm(), 1e-9) << w.transpose();
    EXPECT_NEAR(r.determinant(), 1, 1e-9);
    EXPECT_LT((r * r.transpose() - Mat3::Identity()).norm(), 1e-9);
  }
}

TEST(Layout, BothEndsOfARodSeeTheSameProfile) {
  // A square rod must fit both sockets: the polygon's vertex directions agree at both ends.
  const Structure s = test::make_structure({{0, 0, 0}, {80, 30, 50}}, {{1, 2}});
  const Layout l = compute_layout(s, params(5, 0));
  const RodEnd& a = l.ends[0][0];
  const RodEnd& b = l.ends[0][1];
  EXPECT_LT((a.direction + b.direction).norm(), 1e-12);
  for (int k = 0; k < 4; ++k) {
    const double t = 2 * std::numbers::pi * k / 4;
    const Vec3 va = std::cos(t) * a.frame.col(0) + std::sin(t) * a.frame.col(1);
    double best = 1e9;
    for (int m = 0; m < 4; ++m) {
      const double u = 2 * std::numbers::pi * m / 4;
      best = std::min(best,
                      (va - (std::cos(u) * b.frame.col(0) + std::sin(u) * b.frame.col(1))).norm());
    }
    EXPECT_LT(best, 1e-12) << "vertex " << k;
  }
  EXPECT_NEAR(b.frame.determinant(), 1, 1e-12);
}

}  // namespace
}  // namespace fabkit::rods

#include "fabkit/rods/layout.h"

#include <gtest/gtest.h>

#include <cmath>

#include "fabkit/core/mesh_boolean.h"
#include "fabkit/rods/joint_geometry.h"
#include "fabkit/rods/joint_solid.h"

namespace fabkit::rods {
namespace {

Structure two_rods_at(double angle_deg) {
  const double a = angle_deg * kDegToRad;
  std::vector<NodeInput> nodes = {{Vec3(0, 0, 0), {}},
                                  {Vec3(100, 0, 0), {}},
                                  {Vec3(100 * std::cos(a), 100 * std::sin(a), 0), {}}};
  std::vector<EdgeInput> edges = {{1, 2, {}}, {1, 3, {}}};
  Diagnostics d;
  auto s = build_structure(nodes, edges, 1, 0.01, d);
  EXPECT_TRUE(s) << d.format();
  return *s;
}

TEST(Layout, OffsetsMatchHandComputedCases) {
  Parameters p;
  p.radius = 5;
  p.tolerance = 0.2;
  // 90°: c = 0, g = r + ε.
  Layout l = compute_layout(two_rods_at(90), p);
  EXPECT_NEAR(l.ends[0][0].offset, 5.2, 1e-12);
  EXPECT_NEAR(l.ends[0][0].max_cosine, 0, 1e-12);
  // 60°: c = 1/2, g = (r + ε) √3.
  l = compute_layout(two_rods_at(60), p);
  EXPECT_NEAR(l.ends[0][0].offset, 5.2 * std::sqrt(3.0), 1e-9);
  // 16° (the guitar stand): g = (r + ε) / tan 8°.
  l = compute_layout(two_rods_at(16), p);
  EXPECT_NEAR(l.ends[0][0].offset, 5.2 / std::tan(8 * kDegToRad), 1e-9);
  EXPECT_NEAR(l.ends[0][0].offset, 37.0, 0.01);
  // Leaf ends get the leaf offset.
  EXPECT_EQ(l.ends[0][1].closest_rod, -1);
  EXPECT_EQ(l.ends[0][1].offset, p.leaf_offset);
  // ℓ = ‖p_j − p_i‖ − g_ij − g_ji.
  EXPECT_NEAR(l.rod_length[0], 100 - 5.2 / std::tan(8 * kDegToRad) - 0, 1e-9);
}

TEST(Layout, RotationAlignsZWithTheEdge) {
  for (const Vec3& w :
       {Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 2, -3).normalized()}) {
    const Mat3 r = rotation_to(w);
    EXPECT_TRUE((r * Vec3::UnitZ() - w).norm() < 1e-12) << w.transpose();
    EXPECT_NEAR(r.determinant(), 1, 1e-12);
    EXPECT_TRUE((r * r.transpose() - Mat3::Identity()).norm() < 1e-12);
  }
}

TEST(JointSolid, WatertightJointAt16Degrees) {
  Parameters p;
  p.radius = 3.175;
  p.sides = 0;
  const Structure s = two_rods_at(16);
  const Layout l = compute_layout(s, p);
  Diagnostics d;
  JointSolidOptions o;
  auto joint = make_joint_solid(s, p, l, 0, o, d);
  ASSERT_TRUE(joint) << d.format();
  EXPECT_TRUE(joint->solid.valid_solid()) << joint->solid.problems();
  EXPECT_GT(joint->engraved_volume, 0);
  std::printf("volume %.1f mm³, engraved %.2f mm³ text %.1f mm, %.0f ms\n",
              joint->volume,
              joint->engraved_volume,
              joint->text_height,
              joint->milliseconds);
}

}  // namespace
}  // namespace fabkit::rods

#include "fabkit/rods/joint_solid.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "fabkit/core/glyph_outline.h"
#include "fabkit/core/mesh_boolean.h"
#include "fabkit/core/mesh_query.h"
#include "fabkit/rods/joint_geometry.h"
#include "test_support.h"

namespace fabkit::rods {
namespace {

using test::expect_watertight;

JointSolidOptions no_engraving() {
  JointSolidOptions o;
  o.engrave = false;
  return o;
}

double polygon_area(double circumradius, int sides) {
  return 0.5 * sides * circumradius * circumradius * std::sin(2 * std::numbers::pi / sides);
}

TEST(JointSolid, WatertightAcrossAnglesAndProfiles) {
  for (const double deg : {5.0, 16.0, 30.0, 60.0, 90.0, 120.0, 179.0}) {
    for (const int sides : {0, 3, 4, 6}) {
      const double a = deg * kDegToRad;
      const Structure s = test::make_structure(
          {{0, 0, 0}, {100, 0, 0}, {100 * std::cos(a), 100 * std::sin(a), 30}, {0, 0, 100}},
          {{1, 2}, {1, 3}, {1, 4}});
      Parameters p;
      p.sides = sides;
      const Layout l = compute_layout(s, p);
      for (int node = 0; node < 4; ++node) {
        Diagnostics d;
        const auto joint = make_joint_solid(s, p, l, node, no_engraving(), d);
        ASSERT_TRUE(joint) << deg << "° p=" << sides << " node " << node << ": " << d.format();
        expect_watertight(joint->mesh, s.joint_name(node));
      }
    }
  }
}

TEST(JointSolid, WatertightOnRandomValences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 24; ++trial) {
    const int k = 2 + trial % 5;
    std::vector<Vec3> nodes = {Vec3::Zero()};
    std::vector<std::pair<int, int>> edges;
    for (int i = 0; i < k; ++i) {
      Vec3 d;
      do {
        d = Vec3(u(rng), u(rng), u(rng));
      } while (d.norm() > 1 || d.norm() < 0.2);
      if (trial % 3 == 0 && i < 3) d = Vec3::Unit(i) * (i == 1 ? -1 : 1);  // right angles
      nodes.push_back(d.normalized() * 150);
      edges.emplace_back(1, i + 2);
    }
    const Structure s = test::make_structure(nodes, edges);
    Parameters p;
    p.sides = trial % 4 == 0 ? 4 : (trial % 4 == 2 ? 6 : 0);
    p.tolerance = trial % 5 == 0 ? -0.1 : 0.15;  // press fits too
    const Layout l = compute_layout(s, p);
    Diagnostics d;
    const auto joint = make_joint_solid(s, p, l, 0, no_engraving(), d);
    ASSERT_TRUE(joint) << "trial " << trial << ": " << d.format();
    expect_watertight(joint->mesh, "trial " + std::to_string(trial));
  }
}

TEST(JointSolid, SingleRodJointHasTheAnalyticVolume) {
  // A leaf (g = 0): prism from −σ to h of circumradius r + σ, minus the socket from −ε, i.e.
  // A(r + σ)(h + σ) − A_socket (h + ε).
  const Structure s = test::make_structure({{0, 0, 0}, {0, 0, 200}}, {{1, 2}});
  for (const int sides : {4, 6, 0}) {
    Parameters p;
    p.sides = sides;
    p.radius = 4;
    p.wall = 2;
    p.socket = 12;
    p.tolerance = 0.2;
    const Layout l = compute_layout(s, p);
    Diagnostics d;
    const auto joint = make_joint_solid(s, p, l, 0, no_engraving(), d);
    ASSERT_TRUE(joint) << d.format();
    const int n = p.profile_sides();
    const double expected = polygon_area(p.radius + p.wall, n) * (p.socket + p.wall) -
                            polygon_area(p.socket_circumradius(), n) * (p.socket + p.tolerance);
    EXPECT_NEAR(joint->volume, expected, 1e-3 * expected) << "p = " << sides;
    // The flat end cap: nothing sticks out beyond the wall.
    EXPECT_NEAR(joint->mesh.bounds_min().z(), -p.wall, 1e-6);
  }
}

TEST(JointSolid, RodFitsItsSocketWithoutTouching) {
  // The rod (radius r, from g to g + ℓ) placed in the joint: nothing of it is inside the
  // joint's material for ε > 0, and every rod vertex keeps clear of the joint's surface.
  for (const int sides : {0, 4}) {
    const Structure s = test::two_rods_at(40);
    Parameters p;
    p.sides = sides;
    p.tolerance = 0.2;
    const Layout l = compute_layout(s, p);
    Diagnostics d;
    const auto joint = make_joint_solid(s, p, l, 0, no_engraving(), d);
    ASSERT_TRUE(joint) << d.format();
    const MeshRayQuery surface(joint->mesh);
    for (const RodEnd* end : l.ends_at(0)) {
      const TriangleMesh rod =
          profile_prism(end->frame,
                        Vec3::Zero(),
                        p.radius,
                        p.profile_sides(),
                        end->offset,
                        end->offset + l.rod_length[static_cast<std::size_t>(end->rod)]);
      const std::vector<TriangleMesh> cut = {joint->mesh};
      const auto outside = mesh_difference(rod, cut, "rod", d);
      ASSERT_TRUE(outside) << d.format();
      EXPECT_NEAR(outside->volume(), rod.volume(), 1e-6 * rod.volume())
          << "the rod overlaps the joint";
      double closest = 1e9;
      for (const Vec3& v : rod.vertices) closest = std::min(closest, surface.distance(v));
      EXPECT_GT(closest, 0.5 * p.tolerance) << "p = " << sides;
    }
  }
  // A press fit (ε < 0) does overlap: the rod is squeezed in.
  const Structure s = test::two_rods_at(40);
  Parameters p;
  p.tolerance = -0.1;
  const Layout l = compute_layout(s, p);
  Diagnostics d;
  const auto joint = make_joint_solid(s, p, l, 0, no_engraving(), d);
  ASSERT_TRUE(joint);
  const RodEnd& end = l.end_at(0, 0);
  const TriangleMesh rod = profile_prism(
      end.frame, Vec3::Zero(), p.radius, p.profile_sides(), end.offset, end.offset + 50);
  const std::vector<TriangleMesh> cut = {joint->mesh};
  EXPECT_LT(mesh_difference(rod, cut, "rod", d)->volume(), rod.volume() - 1);
}

TEST(JointSolid, EngravedIdRemovesItsTextAtTheChosenSpot) {
  const Structure s = test::make_structure({{0, 0, 0}, {150, 0, 0}, {0, 150, 0}, {0, 0, 150}},
                                           {{1, 2}, {1, 3}, {1, 4}});
  Parameters p;
  p.wall = 3;
  p.socket = 20;
  const Layout l = compute_layout(s, p);
  Diagnostics d;
  const auto plain = make_joint_solid(s, p, l, 0, no_engraving(), d);
  const auto engraved = make_joint_solid(s, p, l, 0, JointSolidOptions{}, d);
  ASSERT_TRUE(plain && engraved) << d.format();
  ASSERT_TRUE(engraved->engraving);
  expect_watertight(engraved->mesh, "engraved joint");
  EXPECT_EQ(engraved->label, "01");
  // Material is removed: about the label's inked area times the depth σ/2 (flat spot).
  const double removed = plain->volume - engraved->volume;
  EXPECT_NEAR(removed, engraved->engraved_volume, 1e-6);
  EXPECT_NEAR(removed, engraved->text_area * p.wall / 2, 0.2 * engraved->text_area * p.wall / 2);
  EXPECT_GT(engraved->text_height, 2.5);
  // ... at the chosen spot: the removed material's centre is within the flat radius of it.
  const Vec3 removed_centre =
      (plain->volume * plain->centroid - engraved->volume * engraved->centroid) / removed;
  EXPECT_LT((removed_centre - engraved->engraving->position).norm(), engraved->engraving->radius);
  // The spot is on the outside, facing away from the sockets' openings' occlusion.
  EXPECT_LT(engraved->engraving->occlusion, 0.5);
  // Same seed, same spot.
  const auto again = make_joint_solid(s, p, l, 0, JointSolidOptions{}, d);
  EXPECT_EQ((again->engraving->position - engraved->engraving->position).norm(), 0);
}

TEST(JointSolid, PrintPoseTurnsTheRodDirectionsUp) {
  const Structure s = test::make_structure({{0, 0, 0}, {150, 0, 0}, {0, 150, 0}, {0, 0, 150}},
                                           {{1, 2}, {1, 3}, {1, 4}});
  const Parameters p;
  const Layout l = compute_layout(s, p);
  Diagnostics d;
  const auto joint = make_joint_solid(s, p, l, 0, no_engraving(), d);
  ASSERT_TRUE(joint);
  const Mat3 r = joint->print_pose.topLeftCorner<3, 3>();
  const Vec3 sum = Vec3(1, 1, 1).normalized();
  EXPECT_LT((r * sum - Vec3::UnitZ()).norm(), 1e-12);
  const TriangleMesh posed = joint->mesh.transformed(joint->print_pose);
  EXPECT_NEAR(posed.bounds_min().z(), 0, 1e-9);  // on the bed
}

TEST(JointSolid, ScalingTheNetworkKeepsEveryJointIdentical) {
  // §6, Fig. 12: the 1.4 m lamp and the same lamp at 0.7 m print the same joints.
  const Design big = test::load_example("lamp_1400.yaml");
  const Design small = test::load_example("lamp_700.yaml");
  ASSERT_EQ(big.structure.nodes.size(), small.structure.nodes.size());
  const Layout lb = compute_layout(big.structure, big.parameters);
  const Layout ls = compute_layout(small.structure, small.parameters);
  for (const int node : {0, 4, 10}) {
    Diagnostics d;
    const auto a =
        make_joint_solid(big.structure, big.parameters, lb, node, JointSolidOptions{}, d);
    const auto b =
        make_joint_solid(small.structure, small.parameters, ls, node, JointSolidOptions{}, d);
    ASSERT_TRUE(a && b) << d.format();
    ASSERT_EQ(a->mesh.vertices.size(), b->mesh.vertices.size()) << "joint " << node;
    ASSERT_EQ(a->mesh.faces.size(), b->mesh.faces.size());
    double worst = 0;
    for (std::size_t v = 0; v < a->mesh.vertices.size(); ++v) {
      worst = std::max(worst, (a->mesh.vertices[v] - b->mesh.vertices[v]).norm());
    }
    EXPECT_LT(worst, 1e-9) << "joint " << node;
    EXPECT_EQ(a->mesh.faces, b->mesh.faces);
  }
  // ... while the rods are shorter.
  EXPECT_LT(ls.rod_length[0], lb.rod_length[0] * 0.6);
}

}  // namespace
}  // namespace fabkit::rods

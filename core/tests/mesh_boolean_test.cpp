#include "fabkit/core/mesh_boolean.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <vector>

namespace fabkit {
namespace {

TriangleMesh cube(double size, const Vec3& center) {
  return shapes::box(Vec3::Constant(size))
      .transformed(translation(center.x(), center.y(), center.z()));
}

TEST(MeshBoolean, UnionOfOverlappingCubesHasExactVolume) {
  // Two 10 mm cubes overlapping by 5 mm along x: 1000 + 1000 − 500.
  const std::vector<TriangleMesh> cubes = {cube(10, {0, 0, 0}), cube(10, {5, 0, 0})};
  Diagnostics d;
  const auto u = mesh_union(cubes, "two cubes", d);
  ASSERT_TRUE(u) << d.format();
  const SolidCheck c = check_solid(*u);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_NEAR(c.volume, 1500, 1e-6);
  EXPECT_EQ(c.components, 1);
}

TEST(MeshBoolean, UnionSharingCoplanarFacesStaysManifold) {
  // Touching along a whole face and overlapping faces in one plane: the cases a naive union
  // gets wrong.
  const std::vector<TriangleMesh> cubes = {
      cube(10, {0, 0, 0}), cube(10, {10, 0, 0}), cube(10, {5, 0, 0})};
  Diagnostics d;
  const auto u = mesh_union(cubes, "row", d);
  ASSERT_TRUE(u) << d.format();
  const SolidCheck c = check_solid(*u);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_NEAR(c.volume, 2000, 1e-6);
}

// For files: `min_feature_mm` removes the slivers a near miss leaves. Two cubes meeting face to
// face but overlapping by 0.1 µm in x and off by 0.1 µm in y and 0.3 µm in z (what two pieces
// computed along different paths give) unite into a solid whose every edge is at least 10 µm, which
// stays a solid with its coordinates in float32 a metre away, and is the same solid on every run.
TEST(MeshBoolean, ForFilesRemovesSliversOfANearMiss) {
  const std::vector<TriangleMesh> cubes = {cube(10, {0, 0, 0}), cube(10, {9.9999, 1e-4, 3e-4})};
  Diagnostics d;
  const auto raw = mesh_union(cubes, "raw", d);
  ASSERT_TRUE(raw) << d.format();
  auto shortest_edge = [](const TriangleMesh& m) {
    double shortest = 1e300;
    for (const auto& f : m.faces) {
      for (int k = 0; k < 3; ++k) {
        shortest = std::min(shortest,
                            (m.vertices[static_cast<std::size_t>(f[k])] -
                             m.vertices[static_cast<std::size_t>(f[(k + 1) % 3])])
                                .norm());
      }
    }
    return shortest;
  };
  EXPECT_LT(shortest_edge(*raw), 1e-3);  // the slivers are there without the option
  const BooleanOptions for_files{0.01};
  const auto clean = mesh_union(cubes, "clean", d, for_files);
  ASSERT_TRUE(clean) << d.format();
  const SolidCheck c = check_solid(*clean);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_EQ(c.components, 1);
  // 2000 mm³ less the 0.1 µm-thin overlap; removing the steps moves faces by under 1 µm.
  EXPECT_NEAR(c.volume, 2000 - 0.01, 0.05);
  EXPECT_GE(shortest_edge(*clean), 0.01);
  TriangleMesh far = clean->transformed(translation(1000.0, -700.0, 300.0));
  for (Vec3& v : far.vertices) v = v.cast<float>().cast<double>();
  EXPECT_TRUE(check_solid(far).valid_solid()) << check_solid(far).problems();
  const auto again = mesh_union(cubes, "again", d, for_files);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->vertices, clean->vertices);
  EXPECT_EQ(again->faces, clean->faces);
}

TEST(MeshBoolean, DifferenceDrillsAHole) {
  const TriangleMesh block = cube(20, {0, 0, 0});
  const std::vector<TriangleMesh> drill = {shapes::cylinder(4, 30, 32)};
  Diagnostics d;
  const auto holed = mesh_difference(block, drill, "block", d);
  ASSERT_TRUE(holed) << d.format();
  const SolidCheck c = check_solid(*holed);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  // A 32-gon of circumradius 4 has area 16 · 32/2 · sin(2π/32).
  const double hole = 0.5 * 32 * 16 * std::sin(2 * std::numbers::pi / 32) * 20;
  EXPECT_NEAR(c.volume, 8000 - hole, 1e-6);
}

TEST(MeshBoolean, CombinedAddAndSubtract) {
  const std::vector<TriangleMesh> add = {cube(10, {0, 0, 0}), cube(10, {0, 0, 10})};
  const std::vector<TriangleMesh> sub = {cube(4, {0, 0, 15}), cube(4, {0, 0, -5})};
  Diagnostics d;
  const auto r = mesh_boolean(add, sub, "tower", d);
  ASSERT_TRUE(r) << d.format();
  EXPECT_TRUE(check_solid(*r).valid_solid());
  EXPECT_NEAR(check_solid(*r).volume, 2000 - 32 - 32, 1e-6);  // half of each 4 mm cube inside
}

// A deadline already past stops before the first operation, with the time limit and how far
// it got; a deadline far off changes nothing.
TEST(MeshBoolean, StopsAtItsDeadlineBetweenOperations) {
  const std::vector<TriangleMesh> add = {cube(10, {0, 0, 0}), cube(10, {0, 0, 10})};
  const std::vector<TriangleMesh> sub = {cube(4, {0, 0, 15})};
  BooleanOptions o;
  o.deadline = std::chrono::steady_clock::now() - std::chrono::seconds(1);
  Diagnostics d;
  EXPECT_FALSE(mesh_boolean(add, sub, "tower", d, o));
  ASSERT_TRUE(d.has_errors_of(DiagnosticClass::kTimeout)) << d.format();
  EXPECT_FALSE(d.has_errors_of(DiagnosticClass::kInternal)) << d.format();
  EXPECT_NE(d.format().find("tower: stopped at the deadline after 0 of 2 boolean operations"),
            std::string::npos)
      << d.format();
  o.deadline = std::chrono::steady_clock::now() + std::chrono::hours(1);
  Diagnostics later;
  const auto r = mesh_boolean(add, sub, "tower", later, o);
  ASSERT_TRUE(r) << later.format();
  EXPECT_NEAR(check_solid(*r).volume, 2000 - 32, 1e-6);
}

TEST(MeshBoolean, RefusesOpenInputWithAMessage) {
  TriangleMesh open = cube(10, {0, 0, 0});
  open.faces.pop_back();
  const std::vector<TriangleMesh> add = {cube(10, {0, 0, 0}), open};
  Diagnostics d;
  EXPECT_FALSE(mesh_union(add, "joint 07", d));
  EXPECT_NE(
      d.format().find("joint 07: exact boolean failed: solid 2 to add is not a closed manifold"),
      std::string::npos)
      << d.format();
}

TEST(SolidCheck, FindsOpenNonManifoldAndSelfIntersectingMeshes) {
  TriangleMesh open = cube(10, {0, 0, 0});
  open.faces.pop_back();
  SolidCheck c = check_solid(open);
  EXPECT_FALSE(c.closed);
  EXPECT_EQ(c.boundary_edges, 3);
  EXPECT_FALSE(is_closed_manifold(open));

  TriangleMesh overlapping = cube(10, {0, 0, 0});
  overlapping.append(cube(10, {3, 3, 3}));
  c = check_solid(overlapping);
  EXPECT_TRUE(c.closed);
  EXPECT_TRUE(c.self_intersecting);
  EXPECT_TRUE(self_intersects(overlapping));
  EXPECT_FALSE(c.valid_solid());

  TriangleMesh inside_out = cube(10, {0, 0, 0});
  for (auto& f : inside_out.faces) std::swap(f[1], f[2]);
  c = check_solid(inside_out);
  EXPECT_FALSE(c.outward);
  EXPECT_NE(c.problems().find("inside out"), std::string::npos);

  EXPECT_TRUE(check_solid(cube(10, {0, 0, 0})).valid_solid());
}

TEST(ConvexHull, OfCubeCornersAndInteriorPoints) {
  std::vector<Vec3> points;
  for (int i = 0; i < 8; ++i) points.emplace_back(i & 1 ? 5 : -5, i & 2 ? 5 : -5, i & 4 ? 5 : -5);
  points.emplace_back(0, 0, 0);
  points.emplace_back(1, 2, 3);
  const TriangleMesh hull = convex_hull(points);
  const SolidCheck c = check_solid(hull);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_NEAR(c.volume, 1000, 1e-9);
  EXPECT_EQ(hull.vertices.size(), 8u);
  const std::vector<Vec3> flat = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  EXPECT_TRUE(convex_hull(flat).empty());
}

}  // namespace
}  // namespace fabkit

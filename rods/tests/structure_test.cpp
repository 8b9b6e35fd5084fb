#include "fabkit/rods/structure.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fabkit/rods/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::rods {
namespace {

using test::has_code;

std::optional<Structure> try_build(const std::vector<Vec3>& nodes,
                                   const std::vector<std::pair<long long, long long>>& edges,
                                   Diagnostics& d) {
  std::vector<NodeInput> n;
  for (std::size_t i = 0; i < nodes.size(); ++i)
    n.push_back(NodeInput{nodes[i], SourceLocation{"t.yaml", 10 + static_cast<int>(i), 5}});
  std::vector<EdgeInput> e;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    e.push_back(EdgeInput{
        edges[i].first, edges[i].second, SourceLocation{"t.yaml", 30 + static_cast<int>(i), 5}});
  }
  return build_structure(n, e, 1, 0.01, d);
}

TEST(Structure, MergesCoincidentNodesWithANote) {
  Diagnostics d;
  auto s = try_build(
      {{0, 0, 0}, {100, 0, 0}, {100.005, 0, 0}, {0, 100, 0}}, {{1, 2}, {3, 4}, {4, 1}}, d);
  ASSERT_TRUE(s) << d.format();
  EXPECT_EQ(s->nodes.size(), 3u);
  EXPECT_EQ(s->rods.size(), 3u);
  EXPECT_TRUE(has_code(d, codes::kNodesMerged, Severity::kNote));
  EXPECT_NE(d.format().find("node 3 is within 0.01 mm of node 2: merged into joint 2"),
            std::string::npos)
      << d.format();
  EXPECT_EQ(s->joint_name(2), "joint 04");  // IDs keep the file's numbering
}

TEST(Structure, RejectsEachKindOfBadNetworkWithFileAndLine) {
  Diagnostics d;
  EXPECT_FALSE(try_build({{0, 0, 0}, {100, 0, 0}}, {{1, 1}}, d));
  EXPECT_TRUE(has_code(d, codes::kZeroLengthEdge));
  EXPECT_NE(d.format().find("t.yaml:30:5: error: edge 1 joins node 1 to itself"), std::string::npos)
      << d.format();

  Diagnostics merged;
  EXPECT_FALSE(try_build({{0, 0, 0}, {0.001, 0, 0}, {5, 5, 5}}, {{1, 2}, {1, 3}}, merged));
  EXPECT_NE(merged.format().find("within 0.01 mm of each other (zero length)"), std::string::npos);

  Diagnostics dup;
  EXPECT_FALSE(try_build({{0, 0, 0}, {100, 0, 0}}, {{1, 2}, {2, 1}}, dup));
  EXPECT_NE(dup.format().find(
                "t.yaml:31:5: error: edge 2 joins nodes 2 and 1 again (edge 1 already does)"),
            std::string::npos)
      << dup.format();

  Diagnostics isolated;
  EXPECT_FALSE(try_build({{0, 0, 0}, {100, 0, 0}, {7, 8, 9}}, {{1, 2}}, isolated));
  EXPECT_NE(isolated.format().find("t.yaml:12:5: error: node 3 at [7, 8, 9] is not joined"),
            std::string::npos)
      << isolated.format();

  Diagnostics missing;
  EXPECT_FALSE(try_build({{0, 0, 0}, {100, 0, 0}}, {{1, 5}}, missing));
  EXPECT_NE(missing.format().find("edge 1 names node 5, but the nodes are numbered 1 to 2"),
            std::string::npos);

  Diagnostics nan;
  EXPECT_FALSE(try_build({{0, std::nan(""), 0}, {100, 0, 0}}, {{1, 2}}, nan));
  EXPECT_NE(nan.format().find("node 1 has a coordinate that is not a finite number"),
            std::string::npos);

  Diagnostics absurd;
  EXPECT_FALSE(try_build({{0, 0, 0}, {2e6, 0, 0}}, {{1, 2}}, absurd));
  EXPECT_NE(absurd.format().find("more than 1e+06 mm from the origin"), std::string::npos);

  Diagnostics overlap;
  EXPECT_FALSE(try_build({{0, 0, 0}, {100, 0, 0}, {200, 0, 0}}, {{1, 2}, {1, 3}, {2, 3}}, overlap));
  EXPECT_TRUE(has_code(overlap, codes::kOverlappingEdges));
  EXPECT_NE(overlap.format().find("leave node 1 in the same direction"), std::string::npos)
      << overlap.format();
}

TEST(Parameters, ValidateNamesTheParameterAndBounds) {
  Parameters p;
  EXPECT_TRUE(p.validate().empty());
  p.radius = -1;
  p.tolerance = 3;  // thicker than the wall
  p.sides = 2;
  const Diagnostics d = p.validate();
  EXPECT_NE(d.format().find("rod radius r is -1"), std::string::npos) << d.format();
  EXPECT_NE(d.format().find("profile sides p is 2"), std::string::npos);
  Parameters q;
  q.tolerance = 2.5;
  q.wall = 2;
  EXPECT_NE(q.validate().format().find("smaller than the wall σ = 2 mm"), std::string::npos);
  Parameters press;
  press.tolerance = -0.1;  // press fit is allowed
  EXPECT_TRUE(press.validate().empty());
}

TEST(Parameters, SectionPropertiesMatchTextbookFormulas) {
  Parameters circle;
  circle.radius = 5;
  EXPECT_NEAR(circle.section_area(), std::numbers::pi * 25, 1e-12);
  EXPECT_NEAR(circle.section_inertia(), std::numbers::pi * 625 / 4, 1e-9);
  EXPECT_NEAR(circle.section_torsion(), std::numbers::pi * 625 / 2, 1e-9);
  Parameters square;
  square.sides = 4;
  square.radius = 10 / std::sqrt(2.0);  // a 10 mm square
  EXPECT_NEAR(square.section_area(), 100, 1e-9);
  EXPECT_NEAR(square.section_inertia(), 10000.0 / 12, 1e-9);  // a⁴ / 12
  EXPECT_NEAR(square.section_torsion(), 0.1406 * 10000, 1e-6);
  // A circle's socket polygon contains the true circle of radius r + ε.
  EXPECT_NEAR(circle.socket_circumradius() * std::cos(std::numbers::pi / circle.circle_sides),
              circle.radius + circle.tolerance,
              1e-12);
}

TEST(Materials, PresetsAreFound) {
  EXPECT_TRUE(find_rod_material("oak"));
  EXPECT_FALSE(find_rod_material("balsa"));
  EXPECT_NEAR(find_joint_material("pla")->density, 1240, 1e-9);
}

}  // namespace
}  // namespace fabkit::rods

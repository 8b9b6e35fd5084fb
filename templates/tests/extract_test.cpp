// Automatic template construction: the paper's Appendix B table, patterns (Appendix A),
// hierarchy, connections and catalog constraints.
#include "fabkit/templates/extract.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/pattern.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::element_named;
using testing::has_diagnostic;
using testing::part;

// A row as a map index → coefficient, for exact comparison.
using Row = std::map<int, double>;
Row row_of(const Relation& r) {
  Row out;
  for (const LinearTerm& t : r.terms) out[t.index] += t.coefficient;
  return out;
}

// The paper's Figure 14 in 2D: a top and two legs, q^i = [p_x, p_y, Δ_x, Δ_y].
SourceDesign paper_table() {
  SourceDesign d;
  d.name = "table2d";
  d.parts = {part("Top", "", {0, 750, 0}, {1200, 40, 50}),
             part("Leg1", "", {-500, 365, 0}, {60, 730, 50}),
             part("Leg2", "", {500, 365, 0}, {60, 730, 50})};
  return d;
}

TEST(AppendixB, TwoDimensionalTableYieldsThePapersRows) {
  Diagnostics diags;
  ExtractOptions o;
  o.axes = 2;
  const auto t = make_template(paper_table(), nullptr, diags, o);
  ASSERT_TRUE(t) << diags.format();
  ASSERT_EQ(t->element_count(), 3);
  const ElementId top = element_named(*t, "Top"), leg1 = element_named(*t, "Leg1"),
                  leg2 = element_named(*t, "Leg2");
  auto px = [](ElementId e) { return center_index(e, 0); };
  auto py = [](ElementId e) { return center_index(e, 1); };
  auto dx = [](ElementId e) { return size_index(e, 0); };
  auto dy = [](ElementId e) { return size_index(e, 1); };

  std::vector<Row> equalities, orders;
  for (const Relation& r : t->relations) {
    for (const LinearTerm& term : r.terms) {
      EXPECT_LT(term.index % kParamsPerElement % 3, 2) << "a 2D row touches z";
    }
    EXPECT_DOUBLE_EQ(r.rhs, r.kind == RelationKind::kMinSize ? -1.0 : 0.0);
    if (r.equality) equalities.push_back(row_of(r));
    if (r.kind == RelationKind::kOrder) orders.push_back(row_of(r));
  }
  // Coplanarity (the paper's chain): p_y^Top − Δ_y^Top/2 = p_y^Leg1 + Δ_y^Leg1/2
  //                                                      = p_y^Leg2 + Δ_y^Leg2/2.
  const Row top_on_leg1{{py(top), 1}, {dy(top), -0.5}, {py(leg1), -1}, {dy(leg1), -0.5}};
  const Row leg1_with_leg2{{py(leg1), 1}, {dy(leg1), 0.5}, {py(leg2), -1}, {dy(leg2), -0.5}};
  // Symmetry: (p_x^Leg1 + p_x^Leg2)/2 = p_x^Top, i.e. p_x^Leg1 − p_x^Top = p_x^Top − p_x^Leg2.
  const Row symmetry{{px(leg1), 0.5}, {px(leg2), 0.5}, {px(top), -1}};
  // Also read off the figure: the legs' bottoms are coplanar, and their centres share y
  // (concentricity along y).
  const Row leg_bottoms{{py(leg1), 1}, {dy(leg1), -0.5}, {py(leg2), -1}, {dy(leg2), 0.5}};
  const Row legs_concentric{{py(leg1), 1}, {py(leg2), -1}};
  std::vector<Row> expected = {top_on_leg1, leg1_with_leg2, symmetry, leg_bottoms, legs_concentric};
  std::sort(equalities.begin(), equalities.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(equalities, expected);
  // Order ("replace the equality by an inequality"): Leg1 stays left of Leg2.
  const Row leg1_left_of_leg2{{px(leg1), 1}, {dx(leg1), 0.5}, {px(leg2), -1}, {dx(leg2), 0.5}};
  EXPECT_EQ(orders, std::vector<Row>{leg1_left_of_leg2});
  // The design satisfies every row, and all live at the root (the only common ancestor).
  EXPECT_LT(t->max_violation(), 1e-12);
  for (const Relation& r : t->relations) {
    if (r.elements.size() > 1) {
      EXPECT_EQ(r.node, t->root());
    }
  }
}

TEST(AppendixB, RowsAreStoredAtTheLowestCommonAncestor) {
  SourceDesign d = paper_table();
  d.parts[1].group = "base";
  d.parts[2].group = "base";
  Diagnostics diags;
  ExtractOptions o;
  o.axes = 2;
  const auto t = make_template(d, nullptr, diags, o);
  ASSERT_TRUE(t) << diags.format();
  const NodeId base = t->find("base");
  ASSERT_TRUE(base.valid());
  int at_base = 0, at_root = 0;
  for (const Relation& r : t->relations) {
    if (r.elements.size() < 2) continue;
    const bool involves_top =
        std::find(r.elements.begin(), r.elements.end(), element_named(*t, "Top")) !=
        r.elements.end();
    EXPECT_EQ(r.node, involves_top ? t->root() : base) << to_string(r.kind);
    (involves_top ? at_root : at_base)++;
  }
  EXPECT_EQ(at_root, 2);  // top on leg1, the symmetry
  EXPECT_EQ(at_base, 4);  // legs' tops, bottoms, centres, order
  // The base alone is a template: its own relations, nothing about the top.
  const Template base_t = t->subtree(base);
  EXPECT_EQ(base_t.element_count(), 2);
  EXPECT_EQ(base_t.relations.size(), 4u + 4u);  // + min sizes of two elements in 2D
  EXPECT_LT(base_t.max_violation(), 1e-12);
}

TEST(AppendixA, RowOfIdenticalPartsBecomesOnePatternElement) {
  SourceDesign d;
  d.name = "bench";
  d.parts.push_back(part("rail", "", {0, 0, 10}, {1000, 40, 20}));
  for (int i = 0; i < 6; ++i) {
    d.parts.push_back(
        part("slat_" + std::to_string(i + 1), "", {-400 + 160.0 * i, 0, 30}, {80, 300, 20}));
  }
  Diagnostics diags;
  const auto t = make_template(d, nullptr, diags);
  ASSERT_TRUE(t) << diags.format();
  ASSERT_EQ(t->element_count(), 2);
  const Element& slats = t->element(element_named(*t, "slat"));
  ASSERT_TRUE(slats.pattern);
  EXPECT_EQ(slats.pattern->count[0], 6);
  EXPECT_EQ(slats.pattern->axis[0], 0);
  EXPECT_DOUBLE_EQ(slats.pattern->step[0], 160);
  EXPECT_EQ(t->part_count(), 7);
}

TEST(AppendixA, TwoPartsOrAGridOfFourLegsStaySeparate) {
  SourceDesign d;
  d.name = "legs";
  for (int i = 0; i < 4; ++i) {
    d.parts.push_back(part("leg_" + std::to_string(i + 1),
                           "",
                           {i % 2 ? 500.0 : -500.0, i / 2 ? 300.0 : -300.0, 350},
                           {40, 40, 700}));
  }
  Diagnostics diags;
  const auto t = make_template(d, nullptr, diags);
  ASSERT_TRUE(t);
  EXPECT_EQ(t->element_count(), 4);
}

TEST(AppendixA, ResizedPatternRecomputesCountAndSpacingWithoutOverlap) {
  Pattern p;
  p.dims = 1;
  p.axis = {0, 1};
  p.count = {6, 1};
  p.step = {160, 0};
  p.part_size = Vec3(80, 300, 20);
  Box box;
  box.center = Vec3::Zero();
  box.size = Vec3(880, 300, 20);  // (6 − 1)·160 + 80
  auto boxes = pattern_part_boxes(p, box, false, {false, false, false});
  ASSERT_EQ(boxes.size(), 6u);
  // Stretched to 1360 mm: (1360 − 80)/160 + 1 = 9 parts at the same 160 mm spacing.
  box.size.x() = 1360;
  boxes = pattern_part_boxes(p, box, false, {false, false, false});
  ASSERT_EQ(boxes.size(), 9u);
  for (std::size_t i = 1; i < boxes.size(); ++i) {
    EXPECT_NEAR(boxes[i].center.x() - boxes[i - 1].center.x(), 160, 1e-9);
    EXPECT_FALSE(boxes[i].intersects(boxes[i - 1], 1e-9));
  }
  EXPECT_NEAR(boxes.front().min().x(), -680, 1e-9);
  EXPECT_NEAR(boxes.back().max().x(), 680, 1e-9);
  // 1000 mm: 6.75 parts at the design spacing → 7 parts, spacing (1000 − 80)/6 = 153.3 mm.
  box.size.x() = 1000;
  boxes = pattern_part_boxes(p, box, false, {false, false, false});
  ASSERT_EQ(boxes.size(), 7u);
  EXPECT_NEAR(boxes[1].center.x() - boxes[0].center.x(), 920.0 / 6, 1e-9);
  // Shrunk to 200 mm: at most floor((200 − 80)/80) + 1 = 2 parts fit without overlapping.
  box.size.x() = 200;
  boxes = pattern_part_boxes(p, box, false, {false, false, false});
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_FALSE(boxes[0].intersects(boxes[1], 1e-9));
  // Connecting patterns (screws) round up, so their spacing never grows beyond the design's:
  // 890 mm holds (890 − 80)/160 + 1 = 6.06 parts at the design spacing.
  box.size.x() = 890;
  EXPECT_EQ(pattern_part_boxes(p, box, false, {false, false, false}).size(), 6u);
  EXPECT_EQ(pattern_part_boxes(p, box, true, {false, false, false}).size(), 7u);
  // Parts resizable along the direction (planks cut to width) scale with the spacing.
  Pattern planks = p;
  planks.step = {100, 0};
  planks.part_size = Vec3(100, 300, 20);  // touching planks
  box.size.x() = 650;
  boxes = pattern_part_boxes(planks, box, false, {true, false, false});
  ASSERT_EQ(boxes.size(), 7u);  // round(6.5) = 7 (ties away from zero)
  EXPECT_NEAR(boxes[0].size.x(), 650.0 / 7, 1e-9);
  EXPECT_NEAR(boxes.back().max().x(), 325, 1e-9);
}

}  // namespace
}  // namespace fabkit::templates

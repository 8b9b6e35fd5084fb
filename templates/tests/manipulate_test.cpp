// The manipulation QP: constraints hold after every drag, fully constrained controls are
// hidden, requests outside the feasible set name the binding constraint.
#include "fabkit/templates/manipulate.h"

#include <gtest/gtest.h>

#include "fabkit/templates/database.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/extract.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::element_named;
using testing::has_diagnostic;
using testing::part;

// A plywood top on four 2x2 legs: the legs' sections and the top's thickness are fixed by
// their items; lengths and the top's width and depth are cut to size.
Template simple_table() {
  SourceDesign d;
  d.name = "table";
  d.parts = {part("top", "PLY-BIRCH-18", {0, 0, 721}, {1200, 600, 18})};
  int i = 0;
  for (double x : {-550.0, 550.0}) {
    for (double y : {-250.0, 250.0}) {
      d.parts.push_back(part("leg_" + std::to_string(++i),
                             "LUM-PINE-2x2",
                             {x, y, 356},
                             {38, 38, 712},
                             PartRole::kPrincipal,
                             "legs"));
    }
  }
  Diagnostics diags;
  auto t = make_template(d, &ItemCatalog::bundled(), diags);
  EXPECT_TRUE(t) << diags.format();
  return *t;
}

TEST(Manipulate, HidesExactlyTheFullyConstrainedControls) {
  const Template t = simple_table();
  const Manipulator m(t, {}, &ItemCatalog::bundled());
  const auto top = m.controls(t.find("top"));
  // Thickness of plywood is fixed; width, depth and every translation are free.
  std::vector<bool> hidden;
  for (const Control& c : top) hidden.push_back(c.hidden);
  // Its centre in x and y is the model's centre, which the anchors hold (paper §4.2: the
  // model's centre is fixed); its height follows the legs.
  EXPECT_EQ(hidden, (std::vector<bool>{true, true, false, false, false, true}));
  const auto leg = m.controls(t.find("legs/leg_1"));
  hidden.clear();
  for (const Control& c : leg) hidden.push_back(c.hidden);
  // A leg's section is fixed (38 x 38 mm); its centre and length may change.
  EXPECT_EQ(hidden, (std::vector<bool>{false, false, false, true, true, false}));
  // The legs' group: its width and depth are free (legs move apart), its height is the
  // legs' length; its centre is the model's.
  hidden.clear();
  for (const Control& c : m.controls(t.find("legs"))) hidden.push_back(c.hidden);
  EXPECT_EQ(hidden, (std::vector<bool>{true, true, false, false, false, false}));
  // The whole model moves freely (its anchors are released for its own translation).
  hidden.clear();
  for (const Control& c : m.controls(t.root())) hidden.push_back(c.hidden);
  EXPECT_EQ(hidden, (std::vector<bool>{false, false, false, false, false, false}));
}

TEST(Manipulate, DragKeepsEveryConstraint) {
  Template t = simple_table();
  const Manipulator m(t, {}, &ItemCatalog::bundled());
  const Control width = m.control(t.find("top"), ControlKind::kSizeX);
  const DragResult r = m.drag(width, 200);
  ASSERT_TRUE(r.diagnostics.empty()) << r.diagnostics.format();
  EXPECT_LT(r.max_violation, 1e-9);
  EXPECT_LT(t.max_violation(r.q), 1e-9);
  // α = 0.01 (paper: α < 1): one step goes most of the way.
  EXPECT_GT(r.achieved - width.value, 180);
  EXPECT_LE(r.achieved - width.value, 200 + 1e-9);
  // The legs stay mirror images about the top's centre; the model stays on the floor.
  t.q = r.q;
  const Box l1 = t.box(element_named(t, "leg_1")), l3 = t.box(element_named(t, "leg_3"));
  EXPECT_NEAR(l1.center.x() + l3.center.x(), 0, 1e-9);
  EXPECT_NEAR(l1.min().z(), 0, 1e-9);
  EXPECT_NEAR(t.box(element_named(t, "top")).min().z(), l1.max().z(), 1e-9);
}

TEST(Manipulate, SetReachesFeasibleTargetsExactly) {
  Template t = simple_table();
  const Manipulator m(t, {}, &ItemCatalog::bundled());
  const DragResult r = m.set(m.control(t.root(), ControlKind::kSizeZ), 900);
  ASSERT_TRUE(r.reached) << r.message;
  EXPECT_NEAR(r.achieved, 900, 1e-6);
  EXPECT_LT(t.max_violation(r.q), 1e-9);
  t.q = r.q;
  // Height comes from the legs (the top's thickness is fixed).
  EXPECT_NEAR(t.box(element_named(t, "leg_2")).size.z(), 882, 1e-6);
}

TEST(Manipulate, UnreachableTargetGetsNearestFeasibleShapeAndTheBindingConstraint) {
  Template t = simple_table();
  const Manipulator m(t, {}, &ItemCatalog::bundled());
  const DragResult r = m.set(m.control(t.find("legs/leg_1"), ControlKind::kSizeZ), 5000);
  EXPECT_FALSE(r.reached);
  EXPECT_NEAR(r.achieved, 3658, 1e-4) << r.diagnostics.format();
  EXPECT_LT(t.max_violation(r.q), 1e-9);
  ASSERT_TRUE(r.binding) << r.message << " used " << r.used_solver << " it " << r.solver_iterations
                         << " ach " << r.achieved;
  EXPECT_EQ(t.relation(*r.binding).kind, RelationKind::kMaxSize);
  EXPECT_TRUE(
      has_diagnostic(r.diagnostics,
                     codes::kConstrained,
                     "'leg_1' cannot be longer than 3658 mm along z, the longest stock of item "
                     "LUM-PINE-2x2"));
  // Narrower than the legs allow: the order relation between legs binds.
  const DragResult narrow = m.set(m.control(t.find("legs"), ControlKind::kSizeX), 10);
  EXPECT_FALSE(narrow.reached);
  EXPECT_NEAR(narrow.achieved, 76, 1e-4);  // two 38 mm legs side by side
  ASSERT_TRUE(narrow.binding);
  EXPECT_EQ(t.relation(*narrow.binding).kind, RelationKind::kOrder);
  EXPECT_NE(narrow.message.find("cannot be"), std::string::npos) << narrow.message;
}

TEST(Manipulate, FixedControlIsRefused) {
  Template t = simple_table();
  const Manipulator m(t, {}, &ItemCatalog::bundled());
  const Control thickness = m.control(t.find("top"), ControlKind::kSizeZ);
  ASSERT_TRUE(thickness.hidden);
  const DragResult r = m.drag(thickness, 5);
  EXPECT_TRUE(has_diagnostic(r.diagnostics, codes::kFixedControl, "size_z of 'top' is fixed"));
  EXPECT_EQ(r.q, t.q);
}

TEST(Manipulate, SolversAgree) {
  Template t = simple_table();
  ManipulateOptions ipopt;
  ipopt.solver = QpSolver::kIpopt;
  const Manipulator a(t, {}, &ItemCatalog::bundled());
  const Manipulator b(t, ipopt, &ItemCatalog::bundled());
  const DragResult ra = a.set(a.control(t.find("legs"), ControlKind::kSizeX), 10);
  const DragResult rb = b.set(b.control(t.find("legs"), ControlKind::kSizeX), 10);
  EXPECT_TRUE(ra.used_solver);
  EXPECT_TRUE(rb.used_solver);
  EXPECT_LT((ra.q - rb.q).cwiseAbs().maxCoeff(), 1e-4) << ra.message << " / " << rb.message;
}

}  // namespace
}  // namespace fabkit::templates

namespace fabkit::templates {
namespace {

TEST(Manipulate, ResizingAShelfPatternAddsShelvesAndTheirScrews) {
  // Paper Fig. 4: the bookshelf's three evenly spaced shelves are one pattern element; making
  // it taller adds shelves at the same spacing, and the screw pattern holding them follows.
  Template t = *TemplateDatabase::bundled().source_template("bookshelf");
  const Manipulator m(t, {}, &ItemCatalog::bundled());
  const NodeId shelves = t.find("shelves/shelf");
  ASSERT_TRUE(shelves.valid());
  auto count = [&](const Template& tt, const std::string& item, double min_z, double max_z) {
    int n = 0;
    for (const PlacedPart& p : tt.placed_parts()) {
      n += p.item == item && p.box.center.z() > min_z && p.box.center.z() < max_z &&
           p.role == PartRole::kPrincipal && p.box.size.x() > 700;
    }
    return n;
  };
  EXPECT_EQ(count(t, "PLY-BIRCH-18", 400, 1500), 3);
  // From 858 mm (two spacings of 420 + one shelf) to 1278 mm: room for a fourth at 420 mm.
  const DragResult r = m.set(m.control(shelves, ControlKind::kSizeZ), 1278);
  ASSERT_TRUE(r.reached) << r.message;
  EXPECT_LT(t.max_violation(r.q), 1e-9);
  t.q = r.q;
  std::vector<Box> boards;
  int screws = 0;
  for (const PlacedPart& p : t.placed_parts()) {
    if (p.element == element_named(t, "shelf")) boards.push_back(p.box);
    if (p.item == "SCR-4x50" && p.role == PartRole::kConnecting && p.box.center.z() > 400 &&
        p.box.center.z() < 1800) {
      ++screws;
    }
  }
  ASSERT_EQ(boards.size(), 4u);
  for (std::size_t i = 1; i < boards.size(); ++i) {
    EXPECT_NEAR(boards[i].center.z() - boards[i - 1].center.z(), 420, 1e-6);
    EXPECT_FALSE(boards[i].intersects(boards[i - 1], 1e-9));
  }
  // Two screws per shelf end, both sides: the screw patterns grew with the shelves.
  EXPECT_EQ(screws, 2 * 2 * 4);
}

}  // namespace
}  // namespace fabkit::templates

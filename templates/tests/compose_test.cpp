// Composition on the bundled database: snapping (paper §4.4), connecting (§4.5), and the
// paper's compositions (a table with a bottom shelf, a cabinet on wheels, a bench with a
// backrest), which stay templates that can be manipulated.
#include <gtest/gtest.h>

#include <set>

#include "fabkit/templates/connect.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/snap.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::db;
using testing::element_named;
using testing::has_diagnostic;

WorkingModel with(const std::string& first) {
  WorkingModel wm("model");
  Diagnostics d;
  auto t = db().find(first, d);
  EXPECT_TRUE(t) << d.format();
  EXPECT_TRUE(wm.add(*t, first, "base", std::nullopt, d));
  return wm;
}

Composition add(WorkingModel& wm, const std::string& spec, const std::string& as, const Vec3& at) {
  Diagnostics d;
  auto t = db().find(spec, d);
  EXPECT_TRUE(t) << d.format();
  auto c = wm.add(*t, spec, as, at, d);
  EXPECT_TRUE(c) << d.format();
  return *c;
}

void set(WorkingModel& wm, NodeId node, ControlKind k, double value) {
  const Manipulator m(wm.model());
  const DragResult r = m.set(m.control(node, k), value);
  ASSERT_TRUE(r.reached) << r.message;
  wm.model().q = r.q;
}

// The table with a bottom shelf: the bookshelf's bottom shelf dropped between the dining
// table's legs, 789 mm deep like the legs' outer faces.
struct TableWithShelf {
  WorkingModel wm = with("dining_table");
  Composition shelf;
  SnapResult snapped;
  Template after_snap;
  ConnectResult connected;
  TableWithShelf() {
    shelf = add(wm, "bookshelf/shelves/bottom_shelf", "shelf", Vec3(0, 0, 40));
    set(wm, shelf.node, ControlKind::kSizeY, 789);
    snapped = snap(wm, shelf, db());
    wm.model().q = snapped.q;
    after_snap = wm.model();
    connected = connect(wm, shelf, db());
  }
};

std::string plane(const Template& t, const PlaneRef& p) {
  return t.element(p.element).name + (p.side == Side::kMin ? ".min" : ".max") +
         std::string(axis_name(p.axis));
}

TEST(Snap, ShelfTakesTheLegsInnerFacesTheirFrontsAndBacksAndTheFloor) {
  TableWithShelf c;
  const SnapResult& s = c.snapped;
  ASSERT_TRUE(s.snapped) << s.diagnostics.format();
  // From the bookshelf: the shelf's ends and edges lay in its sides' planes, R = 4
  // independent constraints, K = 4 candidates each, N = 4^4 least-squares solves.
  EXPECT_EQ(s.source_constraints, 4);
  EXPECT_EQ(s.candidates_per_constraint, 4);
  EXPECT_EQ(s.combinations, 256);
  const Template& t = c.after_snap;
  std::set<std::string> chosen;
  for (const SnapConstraint& k : s.chosen) {
    const Element& target = t.element(k.target.element);
    const bool leg = target.name.rfind("leg_", 0) == 0;
    chosen.insert(plane(t, k.added) + (leg ? " → a leg's " : " → ") +
                  (k.target.side == Side::kMin ? "min" : "max") +
                  std::string(axis_name(k.target.axis)) +
                  (k.from_source ? " (source)" : " (aligned)"));
  }
  EXPECT_EQ(chosen,
            (std::set<std::string>{"bottom_shelf.minx → a leg's maxx (source)",
                                   "bottom_shelf.maxx → a leg's minx (source)",
                                   "bottom_shelf.miny → a leg's miny (source)",
                                   "bottom_shelf.maxy → a leg's maxy (source)",
                                   "bottom_shelf.minz → a leg's minz (aligned)"}));
  const Template& snapped = t;
  const Box b = snapped.box(element_named(snapped, "bottom_shelf"));
  EXPECT_NEAR(b.min().x(), -655.5, 1e-6);
  EXPECT_NEAR(b.max().x(), 655.5, 1e-6);
  EXPECT_NEAR(b.min().y(), -394.5, 1e-6);
  EXPECT_NEAR(b.max().y(), 394.5, 1e-6);
  EXPECT_NEAR(b.min().z(), 0, 1e-6);
  EXPECT_LT(snapped.max_violation(), 1e-9);
}

TEST(Connect, ShelfUnderATableGetsBracketsAndRisesToMakeRoomForThem) {
  TableWithShelf c;
  const ConnectResult& r = c.connected;
  ASSERT_TRUE(r.all_connected) << r.diagnostics.format();
  const Template& t = c.wm.model();
  ASSERT_EQ(r.links.size(), 4u);  // one per leg
  for (const Link& l : r.links) {
    ASSERT_TRUE(l.connection);
    const Connection& conn = t.connections[l.connection->value];
    std::multiset<std::string> items;
    for (ElementId e : conn.connecting) items.insert(t.element(e).item);
    EXPECT_EQ(items.count("LBR-40"), 1u) << t.element(l.existing).name;
    EXPECT_EQ(items.count("SCR-3.5x16"), 2u);
    EXPECT_EQ(conn.source, "coffee_table");
    EXPECT_GE(l.tried.size(), 2u);  // the K closest were evaluated
  }
  // Paper Fig. 10: the shelf snapped to the floor is raised to leave room for the 40 mm
  // L-brackets under it.
  const Box shelf = t.box(element_named(t, "bottom_shelf"));
  EXPECT_NEAR(shelf.min().z(), 40, 1e-6);
  EXPECT_NEAR(shelf.min().x(), -655.5, 1e-6);
  EXPECT_LT(t.max_violation(), 1e-9);
  EXPECT_GT(r.relations_added, 0);
  // Every bracket sits under the shelf against a leg.
  for (const PlacedPart& p : t.placed_parts()) {
    if (p.item != "LBR-40") continue;
    EXPECT_NEAR(p.box.max().z(), 40, 1e-6);
    EXPECT_NEAR(std::abs(p.box.min().x() + p.box.max().x()) / 2, 635.5, 1e-6);
  }
}

TEST(Connect, ReportsNoConnectionForAPairTheDatabaseCannotJoin) {
  // A caster standing on a tabletop: the only metal–wood joints in the database hold a caster
  // under a shelf.
  WorkingModel wm = with("dining_table");
  const Composition caster = add(wm, "rolling_cart/wheels/caster_fl", "caster", Vec3(0, 0, 800));
  const ConnectResult r = connect(wm, caster, db());
  EXPECT_FALSE(r.all_connected);
  EXPECT_TRUE(
      has_diagnostic(r.diagnostics,
                     codes::kNoConnection,
                     "no connection found between 'caster_fl' and 'top'; tried: rolling_cart: "));
  ASSERT_EQ(r.links.size(), 1u);
  EXPECT_FALSE(r.links[0].tried.empty());
  for (const ConnectionCandidate& c : r.links[0].tried) EXPECT_FALSE(c.accepted);
}

TEST(Compose, CabinetOnWheels) {
  WorkingModel wm = with("cabinet_with_door");
  const Composition wheels = add(wm, "rolling_cart/wheels", "wheels", Vec3(0, 0, -60));
  const SnapResult s = snap(wm, wheels, db());
  wm.model().q = s.q;
  const ConnectResult r = connect(wm, wheels, db());
  ASSERT_TRUE(r.all_connected) << r.diagnostics.format();
  const Template& t = wm.model();
  EXPECT_EQ(r.links.size(), 4u);
  for (const Link& l : r.links) {
    EXPECT_EQ(t.element(l.existing).name, "bottom");
    // The cart's own joint (caster under its bottom shelf), transferred.
    EXPECT_EQ(t.connections[l.connection->value].source, "rolling_cart");
  }
  for (const char* c : {"caster_fl", "caster_fr", "caster_bl", "caster_br"}) {
    EXPECT_NEAR(t.box(element_named(t, c)).max().z(), 0, 1e-6) << c;  // under the bottom
  }
  EXPECT_LT(t.max_violation(), 1e-9);
}

TEST(Compose, BenchWithABackrest) {
  WorkingModel wm = with("bench");
  const Composition back = add(wm, "bed_frame/headboard", "backrest", Vec3(0, 280, 450));
  const SnapResult s = snap(wm, back, db());
  wm.model().q = s.q;
  const ConnectResult r = connect(wm, back, db());
  ASSERT_FALSE(r.diagnostics.has_errors()) << r.diagnostics.format();
  const Template& t = wm.model();
  // Each post stands on the floor behind the bench and is joined to a back leg.
  for (const char* post : {"head_post_left", "head_post_right"}) {
    const Box b = t.box(element_named(t, post));
    EXPECT_NEAR(b.min().z(), 0, 1e-6) << post;
    EXPECT_NEAR(b.min().y(), 234.5, 1e-6) << post;
    bool joined = false;
    for (const Link& l : r.links) {
      joined = joined || (t.element(l.added).name == post && l.connection &&
                          t.element(l.existing).name.find("_back") != std::string::npos);
    }
    EXPECT_TRUE(joined) << post;
  }
  EXPECT_LT(t.max_violation(), 1e-9);
  for (const Relation& rel : t.relations) {
    if (rel.soft) continue;
    const double v = rel.equality ? std::abs(rel.residual(t.q)) : rel.residual(t.q);
    if (v > 1e-9) {
      ADD_FAILURE() << to_string(rel.kind) << " " << v << " " << t.element(rel.elements[0]).name;
    }
  }
}

TEST(Compose, ComposedModelIsStillATemplate) {
  TableWithShelf c;
  Template& t = c.wm.model();
  const Manipulator m(t);
  // Moving the legs apart carries the shelf with it (its ends stay on the legs).
  const NodeId legs = t.find("base/base/legs");
  ASSERT_TRUE(legs.valid());
  const DragResult r = m.set(m.control(legs, ControlKind::kSizeX), 1700);
  ASSERT_TRUE(r.reached) << r.message;
  EXPECT_LT(t.max_violation(r.q), 1e-9);
  t.q = r.q;
  const Box shelf = t.box(element_named(t, "bottom_shelf"));
  const Box leg = t.box(element_named(t, "leg_fr"));
  EXPECT_NEAR(shelf.max().x(), leg.min().x(), 1e-6);
  EXPECT_NEAR(shelf.size.x(), 1311 + 211, 1e-6);
}

TEST(Compose, RemovingAPartDropsItsConnectorsAndRelations) {
  TableWithShelf c;
  const int table_elements = db().source_template("dining_table")->element_count();
  EXPECT_GT(c.wm.model().element_count(), table_elements + 1);
  Diagnostics d;
  ASSERT_TRUE(c.wm.remove("shelf", d)) << d.format();
  const Template& t = c.wm.model();
  EXPECT_EQ(t.element_count(), table_elements);
  for (const PlacedPart& p : t.placed_parts()) EXPECT_NE(p.item, "LBR-40");
  EXPECT_LT(t.max_violation(), 1e-9);
  EXPECT_EQ(c.wm.compositions().size(), 1u);
  EXPECT_FALSE(c.wm.remove("shelf", d));
  EXPECT_TRUE(has_diagnostic(d, codes::kUnknownName, "no part 'shelf'"));
}

}  // namespace
}  // namespace fabkit::templates

namespace fabkit::templates {
namespace {

TEST(Compose, ComposedModelStillNamesTheBindingConstraint) {
  TableWithShelf c;
  Template& t = c.wm.model();
  const Manipulator m(t, {}, &db().catalog());
  const DragResult r =
      m.set(m.control(t.find_node_or_element("leg_fl"), ControlKind::kSizeZ), 5000);
  EXPECT_FALSE(r.reached);
  EXPECT_NEAR(r.achieved, 3658, 1e-3) << r.message;
  EXPECT_NE(r.message.find("cannot be longer than 3658 mm"), std::string::npos) << r.message;
  EXPECT_LT(t.max_violation(r.q), 1e-9);
}

}  // namespace
}  // namespace fabkit::templates

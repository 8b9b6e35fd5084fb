// Stability with friction: whole designs stand, a table missing a leg tips under a lean, a tall
// bookshelf tips under a push at the top but not under a small one.
#include "fabkit/templates/stability.h"

#include <gtest/gtest.h>

#include "fabkit/templates/database.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/working_model.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::db;
using testing::element_named;
using testing::has_diagnostic;

TEST(Stability, EveryBundledDesignStandsAtRest) {
  for (const std::string& name : db().names()) {
    const StabilityResult r = check_stability(*db().source_template(name), db().catalog());
    EXPECT_TRUE(r.stable) << name << ": " << r.diagnostics.format();
    EXPECT_GT(r.contacts, 0) << name;
  }
}

TEST(Stability, TableWithALegRemovedTipsWhenLeanedOn) {
  const Template& table = *db().source_template("dining_table");
  // A person leaning on the corner: 200 N down at the top's back-right corner.
  StabilityOptions lean;
  lean.loads = {Load{element_named(table, "top"), Vec3(780, 430, 750), Vec3(0, 0, -200)}};
  const StabilityResult intact = check_stability(table, db().catalog(), lean);
  EXPECT_TRUE(intact.stable) << intact.diagnostics.format();
  const Template three_legs = table.without(table.find("base/legs/leg_br"));
  ASSERT_EQ(three_legs.element_count() + 1 + 6, table.element_count());  // the leg, its joints
  lean.loads = {Load{element_named(three_legs, "top"), Vec3(780, 430, 750), Vec3(0, 0, -200)}};
  const StabilityResult r = check_stability(three_legs, db().catalog(), lean);
  EXPECT_FALSE(r.stable);
  EXPECT_TRUE(has_diagnostic(r.diagnostics, codes::kUnstable, "tips"));
  EXPECT_FALSE(r.element_stable[element_named(three_legs, "top").value]);
  // At rest, without the lean, three legs still carry it (its centre of mass is inside them).
  EXPECT_TRUE(check_stability(three_legs, db().catalog()).stable);
}

TEST(Stability, TallBookshelfTipsUnderASideLoadAtTheTop) {
  const Template& shelf = *db().source_template("bookshelf");
  const ElementId top = element_named(shelf, "top");
  // Tipping about the front edge: a push F at 1.8 m against the weight m·g at 0.15 m.
  double mass = 0;
  for (const Body& b : check_stability(shelf, db().catalog()).bodies) mass += b.mass_kg;
  const double tipping_force = mass * 9.81 * 0.150 / 1.800;
  StabilityOptions push;
  push.loads = {Load{top, Vec3(0, 150, 1800), Vec3(0, -0.8 * tipping_force, 0)}};
  EXPECT_TRUE(check_stability(shelf, db().catalog(), push).stable);
  push.loads = {Load{top, Vec3(0, 150, 1800), Vec3(0, -1.2 * tipping_force, 0)}};
  const StabilityResult r = check_stability(shelf, db().catalog(), push);
  EXPECT_FALSE(r.stable);
  EXPECT_TRUE(has_diagnostic(r.diagnostics, codes::kUnstable, "tips"));
}

TEST(Stability, APartWithNothingUnderItFallsAndOnlyItIsRed) {
  WorkingModel wm;
  Diagnostics d;
  const auto table = db().find("side_table", d);
  ASSERT_TRUE(table);
  ASSERT_TRUE(wm.add(*table, "side_table", "table", std::nullopt, d));
  const auto board = db().find("bookshelf/shelves/bottom_shelf", d);
  ASSERT_TRUE(wm.add(*board, "bookshelf", "board", Vec3(0, 0, 900), d));  // floating above
  const StabilityResult r = check_stability(wm.model(), db().catalog());
  EXPECT_FALSE(r.stable);
  EXPECT_FALSE(r.element_stable[element_named(wm.model(), "bottom_shelf").value]);
  EXPECT_TRUE(r.element_stable[element_named(wm.model(), "top").value]);
  EXPECT_TRUE(has_diagnostic(r.diagnostics, codes::kUnstable, "'bottom_shelf'"));
}

TEST(Stability, FrictionLimitsASidePushOnALowHeavyBox) {
  // A low cabinet pushed at its base slides rather than tips: friction 0.5 holds 0.4 m·g
  // but not 0.6 m·g.
  const Template& cab = *db().source_template("cabinet_with_door");
  double mass = 0;
  for (const Body& b : check_stability(cab, db().catalog()).bodies) mass += b.mass_kg;
  const ElementId bottom = element_named(cab, "bottom");
  StabilityOptions o;
  o.loads = {Load{bottom, Vec3(0, 0, 9), Vec3(0.4 * mass * 9.81, 0, 0)}};
  EXPECT_TRUE(check_stability(cab, db().catalog(), o).stable);
  o.loads = {Load{bottom, Vec3(0, 0, 9), Vec3(0.6 * mass * 9.81, 0, 0)}};
  const StabilityResult r = check_stability(cab, db().catalog(), o);
  EXPECT_FALSE(r.stable);
  EXPECT_TRUE(has_diagnostic(r.diagnostics, codes::kUnstable, "slides"));
}

}  // namespace
}  // namespace fabkit::templates

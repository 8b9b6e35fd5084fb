// The press-fit order and the assemblability check (issue item 8), on the paper's picnic table
// (Figs. 1 and 10): the table goes together, and its over-constrained variant is reported with
// the pieces that lock each other. The order found is replayed here against the joints, with
// the physics written out independently of the planner.
#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <sstream>

#include "fabkit/flatpack/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

std::string name_of(const Analysis& a, int piece) {
  return a.pieces[static_cast<std::size_t>(piece)].name;
}

// Replays an order without sub-assemblies: each piece must slide in along its direction into
// every piece already there. A finger-hole joint's fingers lead (the finger piece moves against
// its inward normal, the holed piece along it); a finger-finger pair closes moving within the
// quadrant towards each other; a board through a closed slot moves along the slotted board's
// normal.
void expect_order_is_physical(const Analysis& a) {
  std::set<int> placed;
  for (const AssemblyStep& step : a.assembly) {
    ASSERT_EQ(step.group, 0) << "this replay handles single pieces only";
    const Vec3& d = step.direction;
    for (const Joint& j : a.joints) {
      const bool is_a = j.piece_a == step.piece, is_b = j.piece_b == step.piece;
      if (!is_a && !is_b) continue;
      if (!placed.count(is_a ? j.piece_b : j.piece_a)) continue;
      const std::string what = name_of(a, step.piece) + " into " +
                               name_of(a, is_a ? j.piece_b : j.piece_a) + " (joint " +
                               std::to_string(j.id) + ")";
      switch (j.kind) {
        case JointKind::kFingerHole:
          EXPECT_GT(d.dot(is_a ? Vec3(-j.inward_a) : j.inward_a), 1 - 1e-6) << what;
          break;
        case JointKind::kFingerFinger: {
          const Vec3 self = is_a ? j.inward_a : j.inward_b;
          const Vec3 other = is_a ? j.inward_b : j.inward_a;
          EXPECT_GE(d.dot(-self), -1e-6) << what;
          EXPECT_GE(d.dot(other), -1e-6) << what;
          break;
        }
        case JointKind::kSlotSlot:
          EXPECT_GT(
              std::abs(d.dot((j.end - j.start).normalized())) +
                  std::abs(d.dot(a.pieces[static_cast<std::size_t>(
                                              std::abs(j.slot_open_a) == 2 ? j.piece_a : j.piece_b)]
                                     .frame.block<3, 1>(0, 2))),
              1 - 1e-6)
              << what;
          break;
      }
    }
    placed.insert(step.piece);
  }
}

TEST(Assembly, PicnicTableGoesTogether) {
  const Analysis a = check(test::example("picnic_table"));
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_TRUE(a.not_insertable.empty());
  ASSERT_EQ(a.pieces.size(), 5u);  // top, two benches, two end frames (each merged from four)
  ASSERT_EQ(a.assembly.size(), 5u);
  std::set<int> once;
  for (const AssemblyStep& s : a.assembly) once.insert(s.piece);
  EXPECT_EQ(once.size(), 5u);
  // The end frames carry the top and the benches on their fingers, so they go in last, along
  // their fingers (up into the top and the benches).
  for (std::size_t k = 3; k < 5; ++k) {
    const std::string name = name_of(a, a.assembly[k].piece);
    EXPECT_TRUE(name == "end_left" || name == "end_right") << name;
    EXPECT_NEAR(a.assembly[k].direction.z(), 1, 1e-6) << name;
  }
  expect_order_is_physical(a);
}

TEST(Assembly, StoolAndBoxOrdersArePhysical) {
  for (const char* name : {"stool", "box_with_lid", "computer_desk", "simple_table"}) {
    SCOPED_TRACE(name);
    const Analysis a = check(test::example(name));
    ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
    expect_order_is_physical(a);
  }
}

// Found by the fuzzer (a reading desk with a trapezoid side 2 mm wide at its base): a
// sub-assembly whose own pieces cannot come apart had no step to carry its direction, and the
// planner wrote past its steps. Every step now names a real piece, once.
TEST(Assembly, AUnitThatCannotComeApartIsNotTakenAsOne) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) +
                   "/fuzz/regressions/flatpack_design_fuzzer/unit_that_cannot_come_apart.yaml");
  ASSERT_TRUE(in) << "the regression input is missing";
  std::stringstream text;
  text << in.rdbuf();
  const Analysis a = test::check_yaml(text.str());
  ASSERT_TRUE(a.placed) << a.diagnostics.format();
  std::set<int> seen;
  for (const AssemblyStep& step : a.assembly) {
    ASSERT_GE(step.piece, 0);
    ASSERT_LT(step.piece, static_cast<int>(a.pieces.size()));
    EXPECT_TRUE(seen.insert(step.piece).second) << name_of(a, step.piece) << " twice";
    EXPECT_NEAR(step.direction.norm(), 1.0, 1e-9) << name_of(a, step.piece);
  }
  for (int p : a.not_insertable) EXPECT_LT(p, static_cast<int>(a.pieces.size()));
}

// Paper §4.6, Fig. 10(e, f): "the two connections between components 1 (or 3) and 5 (or 4) of
// the picnic table are incompatible, which makes the design nonassemblable".
TEST(Assembly, LockedPicnicTableNamesThePiecesThatCannotBeInserted) {
  const Design d = test::example("picnic_table_locked");
  const Analysis a = check(d);
  ASSERT_TRUE(a.placed) << a.diagnostics.format();
  EXPECT_TRUE(a.assembly.empty());
  std::set<std::string> stuck;
  for (int p : a.not_insertable) stuck.insert(name_of(a, p));
  EXPECT_EQ(stuck,
            (std::set<std::string>{
                "table.bench_front", "table.bench_back", "table.end_left", "table.end_right"}));
  ASSERT_TRUE(test::has_code(a.diagnostics, codes::kNotAssemblable)) << a.diagnostics.format();
  const std::string message = a.diagnostics.format();
  EXPECT_NE(message.find("not assemblable: table.bench_front, table.bench_back, table.end_left, "
                         "table.end_right lock each other"),
            std::string::npos)
      << message;
  EXPECT_EQ(message.find("table.top lock"), std::string::npos) << message;
  // And says why, joint by joint: the half lap lets a bench out sideways, the arm's fingers
  // only upwards.
  EXPECT_NE(message.find("note: table.bench_front: joint"), std::string::npos) << message;
  EXPECT_NE(message.find("(slot-slot with table.end_left) lets it out only along −y"),
            std::string::npos)
      << message;
  EXPECT_NE(message.find("(finger-hole with table.end_left) lets it out only along +z"),
            std::string::npos)
      << message;
  // Why: each bench meets each end frame twice, a half lap in the upright (it must slide in
  // sideways) and fingers from the arm (it must come down onto them).
  for (const char* bench : {"table.bench_front", "table.bench_back"}) {
    for (const char* end : {"table.end_left", "table.end_right"}) {
      std::multiset<JointKind> kinds;
      for (const Joint& j : a.joints) {
        const std::string p = name_of(a, j.piece_a), q = name_of(a, j.piece_b);
        if ((p == bench && q == end) || (p == end && q == bench)) kinds.insert(j.kind);
      }
      EXPECT_EQ(kinds, (std::multiset<JointKind>{JointKind::kFingerHole, JointKind::kSlotSlot}))
          << bench << " / " << end;
    }
  }
  // The same in 6 mm plywood (the sub-design cut from the same board).
  Design six = d;
  six.material.thickness_mm = 6;
  for (auto& [type, sub] : six.library) {
    auto copy = std::make_shared<Design>(*sub);
    copy->material.thickness_mm = 6;
    sub = copy;
  }
  const Analysis thick = check(six);
  std::set<std::string> stuck_thick;
  for (int p : thick.not_insertable) stuck_thick.insert(name_of(thick, p));
  EXPECT_EQ(stuck_thick, stuck) << thick.diagnostics.format();
  // Remove the second joint of each pair (benches back on the arms only) and it goes together.
  Design fixed = d;
  fixed.components[0].params.erase("seat_gap");
  const Analysis b = check(fixed);
  EXPECT_FALSE(b.diagnostics.has_errors()) << b.diagnostics.format();
  EXPECT_EQ(b.assembly.size(), 5u);
}

}  // namespace
}  // namespace fabkit::flatpack

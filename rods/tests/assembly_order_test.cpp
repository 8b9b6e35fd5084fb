#include "fabkit/rods/assembly_order.h"

#include <gtest/gtest.h>

#include "test_support.h"

namespace fabkit::rods {
namespace {

TEST(AssemblyOrder, DepthFirstJointThenItsRodsThenTheNextJoint) {
  // A square 1-2-3-4 with a tail 4-5: from joint 1, its rods, then joint 2, ...
  const Structure s =
      test::make_structure({{0, 0, 0}, {100, 0, 0}, {100, 100, 0}, {0, 100, 0}, {0, 200, 0}},
                           {{1, 2}, {2, 3}, {3, 4}, {4, 1}, {4, 5}});
  const Layout l = compute_layout(s, Parameters{});
  const auto steps = assembly_order(s, l, 0);
  std::vector<std::string> text;
  for (const AssemblyStep& step : steps) {
    text.push_back(step.kind == AssemblyStep::Kind::kJoint ? s.joint_name(step.joint)
                                                           : s.rod_name(step.rod));
  }
  const std::vector<std::string> expected = {"joint 01",
                                             "rod 01-02",
                                             "rod 04-01",
                                             "joint 02",
                                             "rod 02-03",
                                             "joint 03",
                                             "rod 03-04",
                                             "joint 04",
                                             "rod 04-05",
                                             "joint 05"};
  EXPECT_EQ(text, expected);
  EXPECT_TRUE(placed_set_stays_connected(s, steps));
  EXPECT_NEAR(steps[1].rod_length, l.rod_length[0], 1e-12);
  EXPECT_EQ(steps[1].from_joint, 0);
  EXPECT_EQ(steps[1].to_joint, 1);
}

TEST(AssemblyOrder, EveryGalleryOrderKeepsThePlacedSetConnected) {
  for (const char* name :
       {"geodesic_dome.yaml", "wolf_head_52.yaml", "lamp_1400.yaml", "bowl_square.yaml"}) {
    const Design d = test::load_example(name);
    const Layout l = compute_layout(d.structure, d.parameters);
    const auto steps = assembly_order(d.structure, l);
    EXPECT_EQ(steps.size(), d.structure.nodes.size() + d.structure.rods.size()) << name;
    EXPECT_TRUE(placed_set_stays_connected(d.structure, steps)) << name;
    // Default start: a lowest joint (on the floor).
    EXPECT_EQ(d.structure.nodes[static_cast<std::size_t>(steps.front().joint)].position.z(), 0)
        << name;
  }
}

TEST(AssemblyOrder, CheckerRejectsADisconnectedOrder) {
  const Structure s =
      test::make_structure({{0, 0, 0}, {100, 0, 0}, {200, 0, 10}}, {{1, 2}, {2, 3}});
  const Layout l = compute_layout(s, Parameters{});
  auto steps = assembly_order(s, l, 0);
  ASSERT_TRUE(placed_set_stays_connected(s, steps));
  // Place joint 3 first: nothing connects it to joint 1 when joint 1 comes next.
  std::vector<AssemblyStep> bad = {steps[4], steps[0], steps[1], steps[2], steps[3]};
  EXPECT_FALSE(placed_set_stays_connected(s, bad));
}

TEST(AssemblyOrder, SeveralPiecesAreAssembledOneAfterTheOther) {
  const Structure s =
      test::make_structure({{0, 0, 0}, {100, 0, 0}, {0, 300, 0}, {100, 300, 0}}, {{1, 2}, {3, 4}});
  const auto steps = assembly_order(s, compute_layout(s, Parameters{}), 0);
  EXPECT_EQ(steps.size(), 6u);
  EXPECT_TRUE(placed_set_stays_connected(s, steps));
}

}  // namespace
}  // namespace fabkit::rods

#include "fabkit/hacks/assembly.h"

#include <gtest/gtest.h>

#include <optional>
#include <set>
#include <string>

#include "fabkit/hacks/connection_rules.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::make_part;
using testing::rod_environment;

void expect_frame_near(const Mat4& m, const Vec3& pos, const Vec3& rot, double tol_mm = 1e-4) {
  EXPECT_NEAR((m.topRightCorner<3, 1>() - pos).norm(), 0.0, tol_mm)
      << "pos " << m.topRightCorner<3, 1>().transpose();
  const Mat3 expected = Frame(Vec3::Zero(), rot).matrix().topLeftCorner<3, 3>();
  EXPECT_LT((m.topLeftCorner<3, 3>() - expected).norm(), 1e-5)
      << "rot " << Frame::from_matrix(m).rot.transpose();
}

// The random starts are seeded by the parameters' keys: a key names the path of part types
// and primitives from the environment, so a chain's keys are all different, and a chain
// built on a rod that its file names otherwise, placed elsewhere, has the same ones.
TEST(Assembly, ParameterKeysFollowTheStructureOnly) {
  auto chain_keys = [](const Frame& rod_frame, int hooks) {
    auto env = rod_environment(4, 300);
    Assembly a;
    EXPECT_TRUE(a.add(env, rod_frame).accepted);
    std::shared_ptr<Part> above = env;
    std::string primitive = "rod";
    for (int i = 0; i < hooks; ++i) {
      auto hook = make_part("DoubleHook");
      EXPECT_TRUE(a.connect({hook, "hook1"}, {above, primitive}).accepted) << i;
      above = hook;
      primitive = "hook2";
    }
    EXPECT_EQ(a.parameter_keys().size(), static_cast<std::size_t>(a.parameter_count()));
    return a.parameter_keys();
  };
  const std::vector<std::string> keys = chain_keys(Frame(Vec3(0, 0, 900), Vec3(90, 0, 0)), 12);
  ASSERT_GE(keys.size(), 12u * 4u);
  EXPECT_EQ(std::set<std::string>(keys.begin(), keys.end()).size(), keys.size());
  EXPECT_EQ(chain_keys(Frame(Vec3(250, -40, 1200), Vec3(90, 0, 37)), 12), keys);
  // A key extends its parent's: the twelfth hook's names the eleven above it and itself.
  std::size_t hooks_named = 0;
  for (std::size_t at = 0; (at = keys.back().find("DoubleHook.hook1", at)) != std::string::npos;
       ++at) {
    ++hooks_named;
  }
  EXPECT_EQ(hooks_named, 12u) << keys.back();
}

// Reference Appendix A: the Demo (paper Fig. 10) propagated at the default parameters.
TEST(Assembly, DemoMatchesReferenceAtDefaultParameters) {
  auto env = rod_environment(10, 500);
  auto hanger = make_part("Hanger");
  auto doublehook = make_part("DoubleHook");
  auto ring = make_part("CurtainRing");
  Assembly a;
  ASSERT_TRUE(a.add(env, Frame(Vec3(0, 0, 400), Vec3(90, 0, 90))).accepted);
  ASSERT_TRUE(a.connect({hanger, "hook1"}, {env, "rod"}).accepted);
  ASSERT_TRUE(a.connect({doublehook, "hook1"}, {hanger, "rod"}).accepted);
  ASSERT_TRUE(a.connect({ring, "hook"}, {doublehook, "hook2"}).accepted);
  ASSERT_TRUE(
      a.end_with(PrimitiveRef(ring, "hook"), Frame(Vec3(0, 2.1, 142), Vec3(87, 0, 0))).empty());

  struct Expected {
    const char* name;
    double value, lo, hi;
    ParamTag tag;
  };
  // The reference's parameters, plus ψ (where around a rod the contact is) at 0 for each rod.
  const Expected params[] = {
      {"t", 0.5, 0, 1, ParamTag::kBoundedAndOpen},
      {"phi", 90, 45, 135, ParamTag::kBoundedAndOpen},
      {"psi", 0, 0, 360, ParamTag::kUnbounded},
      {"theta", 90, 0, 270, ParamTag::kBoundedAndOpen},
      {"t", 0.5, 0, 1, ParamTag::kBoundedAndClamped},
      {"phi", 90, 45, 135, ParamTag::kBoundedAndClamped},
      {"psi", 0, 0, 360, ParamTag::kUnbounded},
      {"theta", 135, 0, 270, ParamTag::kBoundedAndOpen},
      {"phi", 90, 45, 135, ParamTag::kBoundedAndOpen},
      {"theta", 135, 0, 270, ParamTag::kBoundedAndOpen},
      {"phi", 90, 45, 135, ParamTag::kBoundedAndOpen},
      {"theta", 171, 0, 342, ParamTag::kBoundedAndClamped},
  };
  ASSERT_EQ(a.parameter_count(), 12);
  for (int i = 0; i < 12; ++i) {
    const ParamInfo& p = a.parameters()[static_cast<std::size_t>(i)];
    EXPECT_EQ(p.spec.name, params[i].name) << i;
    // (ψ starts where the rod's top is: 0 up to round-off for these rods.)
    EXPECT_NEAR(
        std::remainder(a.values()[static_cast<std::size_t>(i)] - params[i].value, 360.0), 0.0, 1e-9)
        << i;
    EXPECT_DOUBLE_EQ(p.spec.lo, params[i].lo) << i;
    EXPECT_DOUBLE_EQ(p.spec.hi, params[i].hi) << i;
    EXPECT_EQ(p.spec.tag, params[i].tag) << i;
  }

  const std::vector<Mat4> frames = a.part_frames(a.values());
  ASSERT_EQ(frames.size(), 4u);
  expect_frame_near(frames[0], Vec3(0, 0, 400), Vec3(90, 0, 90));
  expect_frame_near(frames[1], Vec3(0, 58.689863, 334.410137), Vec3(315, 0, 180));
  expect_frame_near(frames[2], Vec3(8.202439, 146.58496, 246.51504), Vec3(315, 315, 90));
  expect_frame_near(frames[3], Vec3(16.404877, 171.108722, 219.735512), Vec3(90, 310.5, 270));

  // The target primitive and the reference's user objective U at these parameters.
  const Mat4 target = frames[3] * ring->primitives[0].frame.matrix();
  expect_frame_near(target, Vec3(16.404877, 172.325371, 220.774629), Vec3(36, 0, 360));
  const Vec6 diff =
      frame_difference(Frame::from_matrix(target), a.target()->frame, Vec3(360, 360, 360));
  EXPECT_NEAR(diff.squaredNorm(), 38052.23917269693, 1e-3);

  // The templated, differentiable path agrees with forward propagation.
  for (int p = 0; p < a.part_count(); ++p) {
    EXPECT_LT((a.part_frame<double>(PartId{p}, a.values().data()).matrix() -
               frames[static_cast<std::size_t>(p)])
                  .norm(),
              1e-9);
  }
}

// A connection made the other way round (the remedy a solve offers for a slip): every other
// connect as it was, that one's alignment turned, the design verified again; a connection with
// no other way round, or no connection, gives none.
TEST(Assembly, AConnectionTurnedTheOtherWayRound) {
  int turned_any = 0;
  int fixed_any = 0;
  for (const char* name : testing::kGalleryExamples) {
    // Its closure searches, once per connection turned, would be most of the test's time.
    if (std::string(name) == "reading_nook") continue;
    const Design d = testing::load_example(name);
    ASSERT_TRUE(d.feasible()) << name;
    const Assembly& a = d.assembly;
    EXPECT_FALSE(a.with_alignment_turned(ConnectionId{}).has_value()) << name;
    EXPECT_FALSE(
        a.with_alignment_turned(ConnectionId{static_cast<int>(a.connections().size())}).has_value())
        << name;
    for (std::size_t k = 0; k < a.connections().size(); ++k) {
      const Connection& c = a.connections()[k];
      const bool flippable =
          alignment_offset(
              a.node(c.first.part).part->primitive(c.first.primitive).connector_kind(),
              a.node(c.second.part).part->primitive(c.second.primitive).connector_kind())
              .flippable();
      const std::optional<Assembly> t = a.with_alignment_turned(ConnectionId{static_cast<int>(k)});
      if (!flippable) {
        EXPECT_FALSE(t.has_value()) << name << " connection " << k;
        ++fixed_any;
        continue;
      }
      if (!t) continue;  // the design does not verify that way (a cycle that no longer closes)
      ++turned_any;
      ASSERT_EQ(t->connections().size(), a.connections().size()) << name;
      for (std::size_t j = 0; j < a.connections().size(); ++j) {
        EXPECT_EQ(t->connections()[j].alignment == a.connections()[j].alignment, j != k)
            << name << " connection " << j << " with " << k << " turned";
      }
      EXPECT_EQ(t->part_count(), a.part_count()) << name;
    }
  }
  EXPECT_GT(turned_any, 10);
  EXPECT_GT(fixed_any, 0);
}

TEST(Assembly, LabelsCountInstancesOfAType) {
  auto env = rod_environment(5, 500);
  auto dh1 = make_part("DoubleHook");
  auto dh2 = make_part("DoubleHook");
  auto basket = make_part("Basket");
  Assembly a;
  a.add(env, Frame());
  ASSERT_TRUE(a.connect({dh1, "hook1"}, {env, "rod"}).accepted);
  EXPECT_EQ(a.label(PartId{1}), "DoubleHook");
  ASSERT_TRUE(a.connect({dh2, "hook1"}, {env, "rod"}).accepted);
  EXPECT_EQ(a.label(PartId{1}), "DoubleHook#1");
  EXPECT_EQ(a.label(PartId{2}, PrimitiveId{0}), "DoubleHook#2.hook1");
  EXPECT_EQ(a.label(PartId{0}, PrimitiveId{0}), "Environment.rod");
  basket->instance_name = "mybasket";
  ASSERT_TRUE(a.connect({basket, "rod1"}, {dh1, "hook2"}).accepted);
  EXPECT_EQ(a.label(PartId{3}), "mybasket");
}

TEST(Assembly, ConnectNeedsAnEnvironmentAndAKnownPart) {
  auto dh1 = make_part("DoubleHook");
  auto dh2 = make_part("DoubleHook");
  Assembly a;
  EXPECT_TRUE(testing::has_diagnostic(a.connect({dh1, "hook1"}, {dh2, "hook1"}).diagnostics,
                                      codes::kNoEnvironment,
                                      "add() one first"));
  auto env = rod_environment(5, 500);
  a.add(env, Frame());
  EXPECT_TRUE(testing::has_diagnostic(a.connect({dh1, "hook1"}, {dh2, "hook1"}).diagnostics,
                                      codes::kNotInAssembly,
                                      "neither DoubleHook nor DoubleHook is in the assembly"));
  EXPECT_TRUE(testing::has_diagnostic(a.connect({dh1, "hook7"}, {env, "rod"}).diagnostics,
                                      codes::kUnknownPrimitive,
                                      "DoubleHook has no primitive 'hook7' (it has hook1, hook2)"));
  EXPECT_EQ(a.part_count(), 1);
}

TEST(Assembly, RejectedConnectLeavesTheAssemblyUnchanged) {
  auto env = rod_environment(12.7, 2920);
  auto dh = make_part("DoubleHook");
  Assembly a;
  a.add(env, Frame());
  const ConnectReport r = a.connect({dh, "hook1"}, {env, "rod"});
  EXPECT_FALSE(r.accepted);
  EXPECT_EQ(a.part_count(), 1);
  EXPECT_TRUE(a.connections().empty());
  EXPECT_EQ(a.parameter_count(), 0);
  EXPECT_EQ(a.available_critical_dim(PartId{0}, PrimitiveId{0}), std::vector<double>{2920});
}

TEST(Assembly, ConnectDecidesTreeOrCycle) {
  auto rods = make_part("ClosetRods");
  auto eye1 = make_part("HookEyeConnector");
  auto eye2 = make_part("HookEyeConnector");
  auto basket = make_part("RoundHandleBasket");
  Assembly a;
  a.add(rods, Frame(Vec3(0, 0, 200), Vec3(0, 0, -90)));
  ConnectOptions flip;
  flip.alignment = AlignmentChoice::kFlip;
  EXPECT_FALSE(a.connect({eye1, "hole"}, {rods, "rod1"}, flip).closes_cycle);
  EXPECT_FALSE(a.connect({eye2, "hole"}, {rods, "rod2"}).closes_cycle);
  // Argument order does not matter: the new part is found either way.
  EXPECT_FALSE(a.connect({basket, "hook"}, {eye1, "hook"}).closes_cycle);
  const ConnectReport r = a.connect({eye2, "hook"}, {basket, "hook"});
  ASSERT_TRUE(r.accepted) << r.diagnostics.format();
  EXPECT_TRUE(r.closes_cycle);
  ASSERT_EQ(r.cycles.size(), 1u);
  EXPECT_EQ(r.cycles[0],
            "ClosetRods.rod2 – HookEyeConnector#2 – RoundHandleBasket – "
            "HookEyeConnector#1 – ClosetRods.rod1");
  EXPECT_EQ(a.cycle_connections().size(), 1u);
  // The accepted configuration really closes the cycle.
  const auto [f1, f2] = a.connection_frames<double>(r.connection, a.values().data());
  EXPECT_LT((f1.t - f2.t).norm(), 1e-3);
  EXPECT_LT((f1.R - f2.R).norm(), 1e-4);
  // The basket's handle now carries two connections.
  EXPECT_EQ(a.connections_of(PartId{3}, PrimitiveId{0}).size(), 2u);
}

// A group's solve recomputes only the frames its parameters move: the parts below a varied
// connection move, the others keep the frames they had, and together they are the frames of
// the whole assembly at the new parameters.
TEST(Assembly, PartialFramesAreTheFramesOfTheWholeAssembly) {
  auto rods = make_part("ClosetRods");
  auto eye1 = make_part("HookEyeConnector");
  auto eye2 = make_part("HookEyeConnector");
  auto basket = make_part("RoundHandleBasket");
  auto hook = make_part("DoubleHook");
  Assembly a;
  a.add(rods, Frame(Vec3(0, 0, 200), Vec3(0, 0, -90)));
  ConnectOptions flip;
  flip.alignment = AlignmentChoice::kFlip;
  ASSERT_TRUE(a.connect({eye1, "hole"}, {rods, "rod1"}, flip).accepted);
  ASSERT_TRUE(a.connect({eye2, "hole"}, {rods, "rod2"}).accepted);
  ASSERT_TRUE(a.connect({basket, "hook"}, {eye1, "hook"}).accepted);
  ASSERT_TRUE(a.connect({hook, "hook1"}, {eye2, "hook"}).accepted);
  const std::vector<double> base = a.values();
  // The parameters of eye hook 1's connection to its rod: eye hook 1 and the basket below it
  // move; the rods, eye hook 2 and the S-hook on it do not.
  std::vector<int> varied;
  for (int i = 0; i < a.parameter_count(); ++i) {
    if (a.parameters()[static_cast<std::size_t>(i)].connection.value == 0) varied.push_back(i);
  }
  ASSERT_FALSE(varied.empty());
  const std::vector<char> moving = a.parts_moved_by(varied);
  ASSERT_EQ(moving.size(), 5u);
  EXPECT_EQ(std::vector<char>(moving.begin(), moving.end()), (std::vector<char>{0, 1, 0, 1, 0}));
  const std::vector<Rigid<double>> fixed = a.all_part_frames<double>(base.data());
  std::vector<double> x = base;
  for (int i : varied) {
    const ParamSpec& spec = a.parameters()[static_cast<std::size_t>(i)].spec;
    x[static_cast<std::size_t>(i)] = spec.lo + 0.37 * (spec.hi - spec.lo);
  }
  const std::vector<Rigid<double>> whole = a.all_part_frames<double>(x.data());
  const std::vector<Rigid<double>> partial = a.all_part_frames<double>(x.data(), moving, fixed);
  ASSERT_EQ(partial.size(), whole.size());
  for (std::size_t i = 0; i < whole.size(); ++i) {
    EXPECT_LT((partial[i].t - whole[i].t).norm(), 1e-12) << "part " << i;
    EXPECT_LT((partial[i].R - whole[i].R).norm(), 1e-12) << "part " << i;
  }
  // The eye hook really moved (the test would pass trivially otherwise).
  EXPECT_GT((whole[1].t - fixed[1].t).norm(), 1.0);
  // A varied parameter of the S-hook's connection moves the S-hook alone.
  std::vector<int> on_hook;
  for (int i = 0; i < a.parameter_count(); ++i) {
    if (a.parameters()[static_cast<std::size_t>(i)].connection.value == 3) on_hook.push_back(i);
  }
  const std::vector<char> hook_moving = a.parts_moved_by(on_hook);
  EXPECT_EQ(std::vector<char>(hook_moving.begin(), hook_moving.end()),
            (std::vector<char>{0, 0, 0, 0, 1}));
}

TEST(Assembly, EndWithTargetsThePartsFirstPrimitive) {
  auto env = rod_environment(5, 500);
  auto bottle = make_part("SoapBottle");
  Assembly a;
  a.add(env, Frame());
  const Frame goal(Vec3(0, 0, 253), Vec3(0, 0, 180));
  EXPECT_TRUE(a.end_with(bottle, goal).empty());
  ASSERT_TRUE(a.target());
  EXPECT_EQ(a.target()->primitive.value, 0);
  EXPECT_EQ(bottle->primitives[0].name, "rod");
  EXPECT_LT((a.target()->frame.matrix() - goal.matrix()).norm(), 1e-12);
  EXPECT_TRUE(a.end_with(PrimitiveRef(bottle, "surface"), goal).empty());
  EXPECT_EQ(a.target()->primitive.value, 1);
  EXPECT_TRUE(testing::has_diagnostic(
      a.end_with(env, Frame()), codes::kTargetMissing, "is an environment"));
}

TEST(Assembly, SingleConnectionPrimitivesHoldOneThing) {
  auto table = std::make_shared<Part>(make_primitive_part({[] {
    PrimitiveShape s;
    s.width = 400;
    s.length = 400;
    return Primitive::make("surface", PrimitiveType::kSurface, s);
  }()}));
  auto clip = make_part("PlasticClip");
  auto brush1 = make_part("Toothbrush");
  auto brush2 = make_part("Toothbrush");
  Assembly a;
  a.add(table, Frame());
  ASSERT_TRUE(a.connect({clip, "hemisphere1"}, {table, "surface"}).accepted);
  ASSERT_TRUE(a.connect({brush1, "rod"}, {clip, "clip"}).accepted);
  const ConnectReport r = a.connect({brush2, "rod"}, {clip, "clip"});
  EXPECT_FALSE(r.accepted);
  EXPECT_TRUE(testing::has_diagnostic(
      r.diagnostics, codes::kSingleConnection, "PlasticClip.clip already holds Toothbrush#1.rod"));
}

}  // namespace
}  // namespace fabkit::hacks

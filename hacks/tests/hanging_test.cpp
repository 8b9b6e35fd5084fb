// The hanging pass (src/hanging.h): a long chain hung part by part from the top starts where
// statics says it rests, and the pass stays out of the way where its lumping is not exact.

#include "../src/hanging.h"

#include <gtest/gtest.h>

#include <string>

#include "fabkit/hacks/solve.h"
#include "span_design.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::load_text;

// N S-hooks from a level rod with a mug on the last one.
std::string chain_with_mug(int hooks) {
  std::string s =
      "fabkit: hacks/1\nname: chain\nenvironment:\n"
      "  - {name: bar, primitives: {rod: {type: rod, radius: 4, length: 300}}, "
      "frame: {pos: [0, 0, 3000], rot: [90, 0, 0]}}\nparts:\n";
  for (int i = 1; i <= hooks; ++i)
    s += "  - {name: s" + std::to_string(i) + ", part: DoubleHook}\n";
  s += "  - {name: mug, part: Mug}\nconnections:\n  - connect: [s1.hook1, bar.rod]\n";
  for (int i = 2; i <= hooks; ++i) {
    s += "  - connect: [s" + std::to_string(i) + ".hook1, s" + std::to_string(i - 1) + ".hook2]\n";
  }
  s += "  - connect: [mug.hook, s" + std::to_string(hooks) + ".hook2]\n";
  return s;
}

Vec3 centre_of_mass(const Assembly& a, const std::vector<Mat4>& frames, int part) {
  const Part& p = *a.node(PartId{part}).part;
  const Mat4& m = frames[static_cast<std::size_t>(part)];
  return m.topLeftCorner<3, 3>() * p.center_of_mass + m.topRightCorner<3, 1>();
}

// Hung from the top, a chain with a mug is at rest as statics has it: the mug and every hook
// plumb under the first hook's contact with the rod (each hangs from a point, the weight below
// it pulling straight down), every hook below the one above, and no higher than the rest the
// whole relaxation finds (within 0.01 mm of mean height); no free turn is left at a stop.
TEST(Hanging, AChainHungFromTheTopIsPlumbAndAtRest) {
  for (int hooks : {12, 20}) {
    SCOPED_TRACE(hooks);
    const Design d = load_text(chain_with_mug(hooks));
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    const Assembly& a = d.assembly;
    const detail::Problem p = detail::make_problem(a);
    const detail::Variables vars = detail::select_variables(a, /*physics=*/true, &p);
    ASSERT_GE(static_cast<int>(vars.index.size()), detail::kHangFrom);
    const std::optional<std::vector<double>> hung = detail::hung_from_the_top(p, vars, a.values());
    ASSERT_TRUE(hung.has_value());
    const std::vector<Mat4> frames = a.part_frames(*hung);
    const Vec3 top = centre_of_mass(a, frames, 1);
    for (int i = 2; i <= hooks + 1; ++i) {
      const Vec3 c = centre_of_mass(a, frames, i);
      EXPECT_LT((c - top).head<2>().norm(), 0.5) << "part " << i;
      EXPECT_LT(c.z(), centre_of_mass(a, frames, i - 1).z()) << "part " << i;
    }
    // The free turns (each hook's tilt about its contact's normal, which costs nothing once it
    // hangs) stay off their stops where the connects left them off: a descent that ran them
    // into a stop would leave the answer hanging on the path it took.
    for (int index : vars.index) {
      const ParamSpec& spec = a.parameters()[static_cast<std::size_t>(index)].spec;
      if (spec.tag == ParamTag::kUnbounded) continue;
      const double before = a.values()[static_cast<std::size_t>(index)];
      const double after = (*hung)[static_cast<std::size_t>(index)];
      if (before <= spec.lo + 1e-9 || before >= spec.hi - 1e-9) continue;
      EXPECT_TRUE(after > spec.lo + 1e-9 && after < spec.hi - 1e-9)
          << spec.name << " of parameter " << index << " at its stop: " << after;
    }
    const SolveResult r = solve(a);
    ASSERT_TRUE(r.stable) << r.summary();
    EXPECT_LT(detail::group_energy(p, *hung) - detail::group_energy(p, r.parameters),
              0.01 * p.total_mass);
    EXPECT_LT(detail::group_energy(p, *hung), detail::group_energy(p, a.values()));
  }
}

// 14 S-hooks hung alternately by either end (each hook's hook1 on the one above's hook1, then
// hook2 on hook2, as the mug hanger hangs its three) under a thin rod, a mug on the last. Hung
// link by link with contact ignored, its links end interlocked through each other (3.5 mm);
// relaxed from there it stayed so ("passes through"), where the relaxation from the verified
// configuration (5 mm deep) comes apart and rests. A hung start with parts inside each other
// is not taken.
TEST(Hanging, AChainItWouldInterlockRestsAsBefore) {
  std::string s =
      "fabkit: hacks/1\nname: alternating\nenvironment:\n"
      "  - {name: bar, primitives: {rod: {type: rod, length: 500, radius: 2}}, "
      "frame: {pos: [0, 0, 2000], rot: [90, 0, 90]}}\nparts:\n";
  constexpr int kHooks = 14;
  for (int i = 1; i <= kHooks; ++i)
    s += "  - {name: d" + std::to_string(i) + ", part: DoubleHook}\n";
  s += "  - {name: mug, part: Mug}\nconnections:\n  - connect: [d1.hook2, bar.rod]\n";
  for (int i = 2; i <= kHooks; ++i) {
    const bool even = i % 2 == 0;
    s += "  - connect: [d" + std::to_string(i) + (even ? ".hook2" : ".hook1") + ", d" +
         std::to_string(i - 1) + (even ? ".hook1" : ".hook2") + "]\n";
  }
  s += "  - connect: [mug.hook, d" + std::to_string(kHooks) + ".hook1]\n";
  const Design d = load_text(s);
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const SolveResult r = solve(d.assembly);
  EXPECT_TRUE(r.stable) << r.summary();
  EXPECT_LE(r.max_penetration_mm, 0.5) << r.summary();
}

// A chain spanning two wall hooks is a cycle: no part hangs from one point, and the pass does
// not apply.
TEST(Hanging, ACycleIsNotHungPartByPart) {
  const Design d = load_text(testing_designs::span_between_wall_hooks(16));
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const detail::Problem p = detail::make_problem(d.assembly);
  const detail::Variables vars = detail::select_variables(d.assembly, /*physics=*/true, &p);
  EXPECT_FALSE(detail::hung_from_the_top(p, vars, d.assembly.values()).has_value());
}

}  // namespace
}  // namespace fabkit::hacks

#pragma once
// A design shared by the physics tests and the solve benchmark: `hooks` S-hooks hung between
// two hooks of a wall, `apart` mm apart at 1 m (605.5 mm: slack from 15 hooks on; issue 9,
// item 4).

#include <fmt/format.h>

#include <string>

namespace fabkit::hacks::testing_designs {

inline std::string span_between_wall_hooks(int hooks, double apart = 605.5) {
  std::string s =
      "fabkit: hacks/1\nname: span\nenvironment:\n  - name: wall\n"
      "    frame: {pos: [0, 0, 1000], rot: [0, 0, 0]}\n    primitives:\n"
      "      hook1: {type: hook, arc_radius: 12.5, arc_angle: 120, thickness: 1.25, " +
      fmt::format("frame: {{pos: [15, {}, 0], rot: [30, 0, 90]}}}}\n", -apart / 2) +
      "      hook2: {type: hook, arc_radius: 12.5, arc_angle: 120, thickness: 1.25, " +
      fmt::format("frame: {{pos: [15, {}, 0], rot: [30, 0, 90]}}}}\nparts:\n", apart / 2);
  for (int i = 1; i <= hooks; ++i) s += fmt::format("  - {{name: s{}, part: DoubleHook}}\n", i);
  s += "connections:\n  - connect: [s1.hook1, wall.hook1]\n";
  for (int i = 2; i <= hooks; ++i) {
    s += fmt::format("  - connect: [s{}.hook1, s{}.hook2]\n", i, i - 1);
  }
  s += fmt::format("  - connect: [s{}.hook2, wall.hook2]\n", hooks);
  return s;
}

}  // namespace fabkit::hacks::testing_designs

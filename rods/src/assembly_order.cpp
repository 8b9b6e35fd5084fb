#include "fabkit/rods/assembly_order.h"

#include <fmt/format.h>

#include <functional>

namespace fabkit::rods {

std::vector<AssemblyStep> assembly_order(const Structure& s, const Layout& l, int start) {
  const int n = static_cast<int>(s.nodes.size());
  std::vector<AssemblyStep> steps;
  if (n == 0) return steps;
  if (start < 0 || start >= n) {
    start = 0;
    for (int i = 1; i < n; ++i) {
      if (s.nodes[static_cast<std::size_t>(i)].position.z() <
          s.nodes[static_cast<std::size_t>(start)].position.z() - 1e-9) {
        start = i;
      }
    }
  }
  std::vector<bool> joint_placed(s.nodes.size(), false), rod_placed(s.rods.size(), false);
  // Iterative depth-first search (deep structures must not overflow the stack): each frame is
  // a joint and how far through its rods the traversal has gone.
  auto visit = [&](int root) {
    struct Frame {
      int joint;
      std::size_t next;
    };
    std::vector<Frame> stack;
    auto place_joint = [&](int i) {
      joint_placed[static_cast<std::size_t>(i)] = true;
      AssemblyStep step;
      step.kind = AssemblyStep::Kind::kJoint;
      step.joint = i;
      step.text = "place " + s.joint_name(i);
      steps.push_back(step);
      for (const int e : l.rods_at[static_cast<std::size_t>(i)]) {
        if (rod_placed[static_cast<std::size_t>(e)]) continue;
        rod_placed[static_cast<std::size_t>(e)] = true;
        const Rod& rod = s.rods[static_cast<std::size_t>(e)];
        AssemblyStep r;
        r.kind = AssemblyStep::Kind::kRod;
        r.rod = e;
        r.from_joint = i;
        r.to_joint = rod.a == i ? rod.b : rod.a;
        r.rod_length = l.rod_length[static_cast<std::size_t>(e)];
        r.text = fmt::format("insert {} ({:.1f} mm) into {}, towards {}",
                             s.rod_name(e),
                             r.rod_length,
                             s.joint_name(i),
                             s.joint_name(r.to_joint));
        steps.push_back(r);
      }
      stack.push_back({i, 0});
    };
    place_joint(root);
    while (!stack.empty()) {
      Frame& top = stack.back();
      const auto& rods = l.rods_at[static_cast<std::size_t>(top.joint)];
      if (top.next == rods.size()) {
        stack.pop_back();
        continue;
      }
      const Rod& rod = s.rods[static_cast<std::size_t>(rods[top.next++])];
      const int j = rod.a == top.joint ? rod.b : rod.a;
      if (!joint_placed[static_cast<std::size_t>(j)]) place_joint(j);
    }
  };
  visit(start);
  for (int i = 0; i < n; ++i) {
    if (!joint_placed[static_cast<std::size_t>(i)]) visit(i);
  }
  return steps;
}

bool placed_set_stays_connected(const Structure& s, const std::vector<AssemblyStep>& steps) {
  std::vector<bool> joint(s.nodes.size(), false), rod(s.rods.size(), false);
  auto rods_at = s.rods_at_nodes();
  for (const AssemblyStep& step : steps) {
    if (step.kind == AssemblyStep::Kind::kRod) {
      const Rod& r = s.rods[static_cast<std::size_t>(step.rod)];
      if (rod[static_cast<std::size_t>(step.rod)]) return false;  // placed twice
      if (!joint[static_cast<std::size_t>(r.a)] && !joint[static_cast<std::size_t>(r.b)])
        return false;
      rod[static_cast<std::size_t>(step.rod)] = true;
    } else {
      if (joint[static_cast<std::size_t>(step.joint)]) return false;
      // A joint joins the placed set through a placed rod, unless it starts a new piece (no
      // joint of its piece placed yet).
      bool through_rod = false;
      for (const int e : rods_at[static_cast<std::size_t>(step.joint)]) {
        through_rod = through_rod || rod[static_cast<std::size_t>(e)];
      }
      if (!through_rod) {
        // Starting a piece is fine only if nothing reachable from it is placed.
        std::vector<bool> seen(s.nodes.size(), false);
        std::vector<int> stack = {step.joint};
        seen[static_cast<std::size_t>(step.joint)] = true;
        while (!stack.empty()) {
          const int i = stack.back();
          stack.pop_back();
          if (joint[static_cast<std::size_t>(i)]) return false;
          for (const int e : rods_at[static_cast<std::size_t>(i)]) {
            const Rod& r = s.rods[static_cast<std::size_t>(e)];
            const int j = r.a == i ? r.b : r.a;
            if (!seen[static_cast<std::size_t>(j)]) {
              seen[static_cast<std::size_t>(j)] = true;
              stack.push_back(j);
            }
          }
        }
      }
      joint[static_cast<std::size_t>(step.joint)] = true;
    }
  }
  for (bool j : joint) {
    if (!j) return false;
  }
  for (bool r : rod) {
    if (!r) return false;
  }
  return true;
}

}  // namespace fabkit::rods

// Tests that physics writes, not the code: answers that do not depend on what physics does not
// care about (where the world is, which way round a rod is spun, the order of the connects,
// which end of a symmetric chain is built first), and rest states statics predicts.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "fabkit/hacks/solve.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::load_text;

std::string read_example(const std::string& name) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + name + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* const kGallery[] = {"toothbrush_holder",
                                "charger_holder",
                                "soap_bottle_holder",
                                "soap_bottle_one_eyehook",
                                "mug_hanger",
                                "paper_towel_holder",
                                "diaper_caddy",
                                "basket_between_rods",
                                "bird_feeder",
                                "clip_light_xs",
                                "clip_light_s",
                                "clip_light_m",
                                "clip_light_l"};

YAML::Node frame_node(const Frame& f) {
  YAML::Node n(YAML::NodeType::Map);
  for (int i = 0; i < 3; ++i) {
    n["pos"].push_back(f.pos[i]);
    n["rot"].push_back(f.rot[i]);
  }
  return n;
}

Frame frame_of(const YAML::Node& n) {
  Frame f;
  if (!n) return f;
  for (int i = 0; i < 3; ++i) {
    if (n["pos"]) f.pos[i] = n["pos"][i].as<double>();
    if (n["rot"]) f.rot[i] = n["rot"][i].as<double>();
  }
  return f;
}

std::string emit(const YAML::Node& root) {
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << root;
  return out.c_str();
}

// The design with the whole world moved: every environment and the target's goal by `world`.
std::string moved(const std::string& yaml, const Frame& world) {
  YAML::Node root = YAML::Load(yaml);
  for (YAML::Node e : root["environment"]) e["frame"] = frame_node(world * frame_of(e["frame"]));
  root["target"]["frame"] = frame_node(world * frame_of(root["target"]["frame"]));
  return emit(root);
}

struct Outcome {
  bool stable = false;
  double energy = 0;     // Σ m·z (mass units · mm)
  double mass = 0;       // Σ m of the parts that move
  double target_mm = 0;  // target position error
  double tilt_deg = 0;
  std::vector<Vec3> positions;  // part origins, in the world
  std::string summary;
};

Outcome solve_text(const std::string& yaml) {
  const Design d = load_text(yaml);
  EXPECT_TRUE(d.feasible()) << d.diagnostics.format() << yaml;
  Outcome o;
  if (!d.feasible()) return o;
  const SolveResult r = solve(d.assembly);
  o.stable = r.stable;
  o.energy = r.energy;
  for (const PartNode& n : d.assembly.nodes()) o.mass += n.environment ? 0.0 : n.part->mass;
  o.target_mm = r.target.position_mm;
  o.tilt_deg = r.target.tilt_deg;
  for (const SolvedPart& p : r.parts) o.positions.push_back(p.frame.pos);
  o.summary = r.summary();
  return o;
}

// Moving the world by a turn about the vertical and a shift changes nothing physical: the
// verdict, the potential (less the shift's share), the target's tilt and every part's height.
// Where a rest state is one of a family (a hook free to slide on a level rod), the member
// found may differ, so horizontal places are not compared; heights do not change along
// such motions.
TEST(Physics, AnswersDoNotDependOnWhereTheWorldIs) {
  const Frame world(Vec3(1234.5, -876.5, 321.0), Vec3(0, 0, 37.0));
  for (const char* name : kGallery) {
    SCOPED_TRACE(name);
    const std::string yaml = read_example(name);
    const Outcome a = solve_text(yaml);
    const Outcome b = solve_text(moved(yaml, world));
    EXPECT_EQ(a.stable, b.stable) << a.summary << b.summary;
    // Mean height of the mass: the shift adds 321 mm.
    EXPECT_NEAR(b.energy / b.mass - 321.0, a.energy / a.mass, 0.05) << a.summary << b.summary;
    EXPECT_NEAR(a.tilt_deg, b.tilt_deg, 0.5) << a.summary << b.summary;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_NEAR(b.positions[i].z() - 321.0, a.positions[i].z(), 1.0) << "part " << i;
    }
  }
}

// A rod is round: spinning an environment's rod about its own axis changes nothing (the hook
// finds its contact anywhere around the rod, not on one line of it).
TEST(Physics, SpinningARodAboutItsAxisChangesNothing) {
  int checked = 0;
  for (const char* name : kGallery) {
    const std::string yaml = read_example(name);
    YAML::Node root = YAML::Load(yaml);
    bool spun = false;
    for (YAML::Node e : root["environment"]) {
      const YAML::Node prims = e["primitives"];
      if (!prims || prims.size() != 1) continue;
      const YAML::Node spec = prims.begin()->second;
      if (spec["type"].as<std::string>() != "rod" || spec["frame"] || spec["centerline"]) continue;
      e["frame"] = frame_node(frame_of(e["frame"]) * Frame(Vec3::Zero(), Vec3(0, 0, 123.0)));
      spun = true;
    }
    if (!spun) continue;
    SCOPED_TRACE(name);
    ++checked;
    const Outcome a = solve_text(yaml);
    const Outcome b = solve_text(emit(root));
    EXPECT_EQ(a.stable, b.stable) << a.summary << b.summary;
    EXPECT_NEAR(a.energy / a.mass, b.energy / b.mass, 0.05) << a.summary << b.summary;
    EXPECT_NEAR(a.tilt_deg, b.tilt_deg, 0.5) << a.summary << b.summary;
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_NEAR(a.positions[i].z(), b.positions[i].z(), 1.0) << "part " << i;
    }
  }
  EXPECT_GE(checked, 2);
}

// The order of the connects does not matter (as long as each part still comes in through the
// same connection): branches built in another order rest the same.
TEST(Physics, TheOrderOfConnectsDoesNotMatter) {
  std::mt19937_64 rng(3);
  for (const char* name : kGallery) {
    SCOPED_TRACE(name);
    const std::string yaml = read_example(name);
    YAML::Node root = YAML::Load(yaml);
    // Which side of each connect is in the assembly already, in the file's order.
    std::set<std::string> in;
    for (const YAML::Node e : root["environment"]) in.insert(e["name"].as<std::string>());
    struct Step {
      YAML::Node node;
      std::string a, b;
      bool cycle;
    };
    std::vector<Step> steps;
    for (const YAML::Node c : root["connections"]) {
      auto part_of = [](const std::string& ref) { return ref.substr(0, ref.find('.')); };
      const std::string a = part_of(c["connect"][0].as<std::string>());
      const std::string b = part_of(c["connect"][1].as<std::string>());
      const bool cycle = in.count(a) && in.count(b);
      steps.push_back({YAML::Clone(c), a, b, cycle});
      in.insert(a);
      in.insert(b);
    }
    for (int trial = 0; trial < 3; ++trial) {
      // A random order in which every connect still finds its old side in place.
      std::set<std::string> placed;
      for (const YAML::Node e : root["environment"]) placed.insert(e["name"].as<std::string>());
      // Indices, not nodes: assigning a YAML::Node overwrites what it refers to.
      std::vector<std::size_t> left(steps.size());
      for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
      YAML::Node order(YAML::NodeType::Sequence);
      while (!left.empty()) {
        std::vector<std::size_t> ready;
        for (std::size_t i = 0; i < left.size(); ++i) {
          const Step& st = steps[left[i]];
          const bool a_in = placed.count(st.a) > 0;
          const bool b_in = placed.count(st.b) > 0;
          if (st.cycle ? (a_in && b_in) : (a_in != b_in)) ready.push_back(i);
        }
        ASSERT_FALSE(ready.empty());
        const std::size_t pick =
            ready[std::uniform_int_distribution<std::size_t>(0, ready.size() - 1)(rng)];
        const Step& st = steps[left[pick]];
        order.push_back(YAML::Clone(st.node));
        placed.insert(st.a);
        placed.insert(st.b);
        left.erase(left.begin() + static_cast<std::ptrdiff_t>(pick));
      }
      YAML::Node shuffled = YAML::Clone(root);
      shuffled["connections"] = order;
      const Outcome a = solve_text(yaml);
      const Outcome b = solve_text(emit(shuffled));
      EXPECT_EQ(a.stable, b.stable) << a.summary << b.summary;
      EXPECT_NEAR(a.energy / a.mass, b.energy / b.mass, 0.05) << a.summary << b.summary;
    }
  }
}

// A chain of S-hooks between two rods, the right rod the left one turned half a turn about the
// vertical through the middle (so the design is the same seen from either side), built from
// the left or from the right: the same chain, the same answer.
std::string chain_between_rods(int hooks, bool from_left) {
  std::string s =
      "fabkit: hacks/1\nname: chain\nenvironment:\n"
      "  - {name: left, primitives: {rod: {type: rod, radius: 4, length: 300}}, "
      "frame: {pos: [-200, 0, 500], rot: [90, 0, 0]}}\n"
      "  - {name: right, primitives: {rod: {type: rod, radius: 4, length: 300}}, "
      "frame: {pos: [200, 0, 500], rot: [90, 0, 180]}}\nparts:\n";
  for (int i = 1; i <= hooks; ++i)
    s += "  - {name: s" + std::to_string(i) + ", part: DoubleHook}\n";
  const std::string start = from_left ? "left" : "right";
  const std::string end = from_left ? "right" : "left";
  s += "connections:\n  - connect: [s1.hook1, " + start + ".rod]\n";
  for (int i = 2; i <= hooks; ++i) {
    s += "  - connect: [s" + std::to_string(i) + ".hook1, s" + std::to_string(i - 1) + ".hook2]\n";
  }
  s += "  - {connect: [s" + std::to_string(hooks) + ".hook2, " + end + ".rod], alignment: flip}\n";
  return s;
}

TEST(Physics, ASymmetricChainRestsTheSameFromEitherEnd) {
  for (int hooks : {10, 12}) {
    SCOPED_TRACE(hooks);
    const Outcome l = solve_text(chain_between_rods(hooks, true));
    const Outcome r = solve_text(chain_between_rods(hooks, false));
    EXPECT_TRUE(l.stable) << l.summary;
    EXPECT_EQ(l.stable, r.stable) << l.summary << r.summary;
    EXPECT_NEAR(l.energy / l.mass, r.energy / r.mass, 0.1) << l.summary << r.summary;
    // The lowest point of the sagging chain is in the middle, for both.
    auto lowest_x = [](const Outcome& o) {
      if (o.positions.size() < 3) return std::nan("");
      std::size_t k = 2;
      for (std::size_t i = 2; i < o.positions.size(); ++i) {
        if (o.positions[i].z() < o.positions[k].z()) k = i;
      }
      return o.positions[k].x();
    };
    EXPECT_LT(std::abs(lowest_x(l)), 40.0) << l.summary;
    EXPECT_LT(std::abs(lowest_x(r)), 40.0) << r.summary;
  }
}

// A chain of N S-hooks hangs plumb from a level rod: every hook right under the first.
TEST(Physics, AChainOfHooksHangsPlumb) {
  for (int hooks : {1, 2, 3, 5, 8, 12, 16}) {
    SCOPED_TRACE(hooks);
    std::string s =
        "fabkit: hacks/1\nname: plumb\nenvironment:\n"
        "  - {name: bar, primitives: {rod: {type: rod, radius: 4, length: 300}}, "
        "frame: {pos: [0, 0, 2000], rot: [90, 0, 0]}}\nparts:\n";
    for (int i = 1; i <= hooks; ++i)
      s += "  - {name: s" + std::to_string(i) + ", part: DoubleHook}\n";
    s += "connections:\n  - connect: [s1.hook1, bar.rod]\n";
    for (int i = 2; i <= hooks; ++i) {
      s +=
          "  - connect: [s" + std::to_string(i) + ".hook1, s" + std::to_string(i - 1) + ".hook2]\n";
    }
    const Design d = load_text(s);
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    const SolveResult r = solve(d.assembly);
    EXPECT_TRUE(r.stable) << r.summary();
    // Each hook's centre of mass is under the first's, and each lower than the one above.
    const std::vector<Mat4> frames = d.assembly.part_frames(r.parameters);
    auto com = [&](int i) {
      const Part& p = *d.assembly.node(PartId{i}).part;
      const Mat4& m = frames[static_cast<std::size_t>(i)];
      return Vec3(m.topLeftCorner<3, 3>() * p.center_of_mass + m.topRightCorner<3, 1>());
    };
    for (int i = 2; i <= hooks; ++i) {
      EXPECT_LT((com(i) - com(1)).head<2>().norm(), 0.5) << "hook " << i << r.summary();
      EXPECT_LT(com(i).z(), com(i - 1).z()) << "hook " << i;
    }
  }
}

}  // namespace
}  // namespace fabkit::hacks

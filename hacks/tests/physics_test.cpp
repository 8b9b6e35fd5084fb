// Tests that physics writes, not the code: answers that do not depend on what physics does not
// care about (where the world is, which way round a rod is spun, the order of the connects,
// which end of a symmetric chain is built first), and rest states statics predicts.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <numbers>
#include <optional>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fabkit/hacks/solve.h"
#include "span_design.h"
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

// The gallery.
std::vector<std::string> gallery() {
  std::vector<std::string> names;
  for (const char* name : testing::kGalleryExamples) names.emplace_back(name);
  return names;
}

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

// A frame as a YAML flow mapping, every number as it prints back exactly.
std::string flow_frame(const Frame& f) {
  return fmt::format("{{pos: [{}, {}, {}], rot: [{}, {}, {}]}}",
                     f.pos.x(),
                     f.pos.y(),
                     f.pos.z(),
                     f.rot.x(),
                     f.rot.y(),
                     f.rot.z());
}

struct Outcome {
  bool stable = false;
  double energy = 0;     // Σ m·z (mass units · mm)
  double mass = 0;       // Σ m of the parts that move
  double target_mm = 0;  // target position error
  double tilt_deg = 0;
  std::vector<Vec3> positions;          // part origins, in the world
  std::map<std::string, Vec3> by_name;  // the same, by the parts' names
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
  for (const SolvedPart& p : r.parts) {
    o.positions.push_back(p.frame.pos);
    o.by_name[p.name] = p.frame.pos;
  }
  o.summary = r.summary();
  return o;
}

// An environment placed primitive by primitive (the paper's Environment({"left": Rod, "right":
// Rod}) with each rod added where it is, App. B.2) is placed like any other: the world moved and
// turned, a curtain rod in two S-hooks hung from its two rods rests where it did, moved and
// turned with it. (Its part sits at the origin, and the placement's centre and heading took
// that for where it was: the design was solved as written, not in its own placement, until
// 2026-12-06.)
TEST(Physics, AnEnvironmentPlacedPrimitiveByPrimitiveIsPlacedToo) {
  PrimitiveShape rod;
  rod.radius = 6;
  rod.length = 30;
  auto solve_in = [&](const Frame& world) {
    auto env = std::make_shared<Part>(
        make_primitive_part({Primitive::make("left", PrimitiveType::kRod, rod),
                             Primitive::make("right", PrimitiveType::kRod, rod)}));
    const auto s1 = testing::make_part("DoubleHook");
    const auto s2 = testing::make_part("DoubleHook");
    const auto bar = testing::make_part("ShowerCurtainRod");
    Assembly a;
    EXPECT_TRUE(a.add({env, "left"}, world * Frame(Vec3(-150, 0, 1200), Vec3(0, 90, 0))).accepted);
    EXPECT_TRUE(a.add({env, "right"}, world * Frame(Vec3(150, 0, 1200), Vec3(0, 90, 0))).accepted);
    EXPECT_TRUE(a.connect({s1, "hook1"}, {env, "left"}).accepted);
    EXPECT_TRUE(a.connect({bar, "rod"}, {s1, "hook2"}).accepted);
    EXPECT_TRUE(a.connect({s2, "hook1"}, {env, "right"}).accepted);
    EXPECT_TRUE(a.connect({s2, "hook2"}, {bar, "rod"}).accepted);
    return solve(a);
  };
  const SolveResult here = solve_in(Frame());
  ASSERT_TRUE(here.stable) << here.summary();
  for (const Frame& world : {Frame(Vec3(1234.5, -876.5, 321.0), Vec3(0, 0, 37.0)),
                             Frame(Vec3(-2500, 1800, -40), Vec3(0, 0, 251.5))}) {
    SCOPED_TRACE(world.to_string());
    const SolveResult there = solve_in(world);
    EXPECT_TRUE(there.stable) << there.summary();
    ASSERT_EQ(here.parts.size(), there.parts.size());
    for (std::size_t i = 0; i < here.parts.size(); ++i) {
      // The environment's part is at the origin in both; its rods are where they were added.
      if (here.parts[i].environment) continue;
      SCOPED_TRACE(here.parts[i].name);
      EXPECT_LT((there.parts[i].frame.pos - world.apply(here.parts[i].frame.pos)).norm(), 1e-6);
    }
  }
}

// Moving the world by a turn about the vertical and a shift changes nothing physical: the
// verdict, the potential (less the shift's share), the target's tilt and where every part
// rests, moved with the world, to 10⁻⁶ mm — even where a rest state is one of a family (a hook
// free to slide on a level rod), one of several (the reading nook, which rested differently or
// not at all in 5 of 12 random placements until every design was verified and solved in its
// own placement: Assembly::in_own_placement) or not a rest state at all (the diaper caddy).
TEST(Physics, AnswersDoNotDependOnWhereTheWorldIs) {
  // One motion chosen by hand and three drawn (seeded): any turn about the vertical, shifts
  // of metres.
  std::vector<Frame> worlds = {Frame(Vec3(1234.5, -876.5, 321.0), Vec3(0, 0, 37.0))};
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> turn(0.0, 360.0), across(-3000.0, 3000.0),
      up(-500.0, 500.0);
  for (int k = 0; k < 3; ++k) {
    const double x = across(rng), y = across(rng), z = up(rng), c = turn(rng);
    worlds.emplace_back(Vec3(x, y, z), Vec3(0, 0, c));
  }
  for (const std::string& name : gallery()) {
    SCOPED_TRACE(name);
    const std::string yaml = read_example(name);
    const Outcome a = solve_text(yaml);
    for (const Frame& world : worlds) {
      SCOPED_TRACE(fmt::format("world moved by [{:.1f}, {:.1f}, {:.1f}], turned {:.1f}°",
                               world.pos.x(),
                               world.pos.y(),
                               world.pos.z(),
                               world.rot.z()));
      const double lift = world.pos.z();
      const Outcome b = solve_text(moved(yaml, world));
      EXPECT_EQ(a.stable, b.stable) << a.summary << b.summary;
      // Mean height of the mass: the shift adds its height.
      EXPECT_NEAR(b.energy / b.mass - lift, a.energy / a.mass, 1e-6) << a.summary << b.summary;
      EXPECT_NEAR(a.tilt_deg, b.tilt_deg, 1e-6) << a.summary << b.summary;
      ASSERT_EQ(a.by_name.size(), b.by_name.size());
      for (const auto& [part, at] : a.by_name) {
        ASSERT_TRUE(b.by_name.count(part)) << part;
        EXPECT_LT((b.by_name.at(part) - world.apply(at)).norm(), 1e-6) << part;
      }
    }
  }
}

// Far from the world's origin too: designs moved 220 m and 420 m rest as they do near it
// (the paper towel holder, its roll against the wall, ended "did not converge" 100 m out:
// the solver's round-off grows with the coordinates; it now works near the design).
// A chain of `hooks` S-hooks (`part`) between two rods 4 mm thick at `left` and `right`, the
// world turned by `turn` degrees about the vertical, built from the left rod or from the
// right one (the same connects the other way round and in the other order).
std::string chain_between_two_rods(const std::string& part,
                                   int hooks,
                                   const Vec3& left,
                                   const Vec3& right,
                                   double turn,
                                   bool from_left) {
  std::string s = fmt::format(
      "fabkit: hacks/1\nname: chain\nenvironment:\n"
      "  - {{name: left, primitives: {{rod: {{type: rod, radius: 4, length: 300}}}}, "
      "frame: {{pos: [{}, {}, {}], rot: [90, 0, {}]}}}}\n"
      "  - {{name: right, primitives: {{rod: {{type: rod, radius: 4, length: 300}}}}, "
      "frame: {{pos: [{}, {}, {}], rot: [90, 0, {}]}}}}\nparts:\n",
      left.x(),
      left.y(),
      left.z(),
      turn,
      right.x(),
      right.y(),
      right.z(),
      turn + 180);
  for (int i = 1; i <= hooks; ++i) s += fmt::format("  - {{name: s{}, part: {}}}\n", i, part);
  s += "connections:\n";
  const std::string last =
      fmt::format("  - {{connect: [s{}.hook2, right.rod], alignment: flip}}\n", hooks);
  if (from_left) {
    s += "  - connect: [s1.hook1, left.rod]\n";
    for (int i = 2; i <= hooks; ++i) {
      s += fmt::format("  - connect: [s{}.hook1, s{}.hook2]\n", i, i - 1);
    }
    return s + last;
  }
  s += last;
  for (int i = hooks - 1; i >= 1; --i) {
    s += fmt::format("  - connect: [s{}.hook2, s{}.hook1]\n", i, i + 1);
  }
  return s + "  - connect: [s1.hook1, left.rod]\n";
}

// Four medium S-hooks slack between two rods 44 mm apart, built from the lower rod, in the
// world as written and turned 286.3 deg about the vertical and moved by (2289, 608, -74) mm.
// The moved one said "falls apart: right.rod slides off the open end of s4.hook2": most ways
// of closing this loose loop let a hook slide off, and the two other closings that were
// coming to rest against the rods stopped at their contact relaxation's iteration cap, still
// sloping by 3e-5. Such a relaxation now goes on once from where it stopped. (The two rest in
// different states: with several, which one a solve reaches is not yet invariant.)
TEST(Physics, ASlackChainHoldsWhereverTheWorldIs) {
  const Outcome here =
      solve_text(chain_between_two_rods("DoubleHookMedium",
                                        4,
                                        Vec3(-21.980959971979548, 0, 500),
                                        Vec3(21.980959971979548, 0, 453.93463957242835),
                                        0,
                                        false));
  const Outcome moved = solve_text(
      chain_between_two_rods("DoubleHookMedium",
                             4,
                             Vec3(2282.5553699485813, 629.2344372661479, 426.08249548419207),
                             Vec3(2294.8782491415964, 587.0349461133695, 380.0171350566204),
                             286.2785897805018,
                             false));
  EXPECT_TRUE(here.stable) << here.summary;
  EXPECT_TRUE(moved.stable) << moved.summary;
}

// A long chain's relaxation works on large models (a factored eigenbasis, gauge pairs folded):
// 24 S-hooks and a mug from a level rod rest the same, height for height, with the rod where
// the file puts it and moved and turned about the vertical.
TEST(Physics, ALongChainRestsTheSameWhereverItsRodIs) {
  auto hanging = [](const Vec3& rod, double turn) {
    std::string s = fmt::format(
        "fabkit: hacks/1\nname: chain\nenvironment:\n"
        "  - {{name: bar, primitives: {{rod: {{type: rod, radius: 4, length: 300}}}}, "
        "frame: {{pos: [{}, {}, {}], rot: [90, 0, {}]}}}}\nparts:\n",
        rod.x(),
        rod.y(),
        rod.z(),
        turn);
    constexpr int kHooks = 24;
    for (int i = 1; i <= kHooks; ++i) s += fmt::format("  - {{name: s{}, part: DoubleHook}}\n", i);
    s += "  - {name: mug, part: Mug}\nconnections:\n  - connect: [s1.hook1, bar.rod]\n";
    for (int i = 2; i <= kHooks; ++i) {
      s += fmt::format("  - connect: [s{}.hook1, s{}.hook2]\n", i, i - 1);
    }
    return s + fmt::format("  - connect: [mug.hook, s{}.hook2]\n", kHooks);
  };
  const Vec3 here(0, 0, 3000);
  const Outcome a = solve_text(hanging(here, 0));
  ASSERT_TRUE(a.stable) << a.summary;
  for (const auto& [rod, turn] : {std::pair(Vec3(1234.5, -876.5, 3321.0), 37.0),
                                  std::pair(Vec3(-2500.0, 1900.0, 2750.0), 211.0)}) {
    SCOPED_TRACE(fmt::format("rod at [{}, {}, {}], turned {}", rod.x(), rod.y(), rod.z(), turn));
    const Outcome b = solve_text(hanging(rod, turn));
    EXPECT_TRUE(b.stable) << b.summary;
    const double lift = rod.z() - here.z();
    EXPECT_NEAR(b.energy / b.mass - lift, a.energy / a.mass, 0.01) << a.summary << b.summary;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_NEAR(b.positions[i].z() - lift, a.positions[i].z(), 0.5) << "part " << i;
    }
  }
}

TEST(Physics, AFarAwayWorldChangesNothing) {
  for (const Frame& world : {Frame(Vec3(100000, -200000, 321.0), Vec3(0, 0, 12.5)),
                             Frame(Vec3(-300000, 300000, 321.0), Vec3(0, 0, 250.0))}) {
    for (const std::string name : {"paper_towel_holder", "mug_hanger", "toothbrush_holder"}) {
      SCOPED_TRACE(name + " " + world.to_string());
      const std::string yaml = read_example(name);
      const Outcome a = solve_text(yaml);
      const Outcome b = solve_text(moved(yaml, world));
      ASSERT_TRUE(a.stable) << a.summary;
      EXPECT_TRUE(b.stable) << b.summary;
      EXPECT_NEAR(b.energy / b.mass - 321.0, a.energy / a.mass, 0.05) << a.summary << b.summary;
      EXPECT_NEAR(a.tilt_deg, b.tilt_deg, 0.5) << a.summary << b.summary;
      ASSERT_EQ(a.positions.size(), b.positions.size());
      for (std::size_t i = 0; i < a.positions.size(); ++i) {
        EXPECT_NEAR(b.positions[i].z() - 321.0, a.positions[i].z(), 1.0) << "part " << i;
      }
    }
  }
}

// A rod is round: spinning an environment's rod about its own axis changes nothing (the hook
// finds its contact anywhere around the rod, not on one line of it).
TEST(Physics, SpinningARodAboutItsAxisChangesNothing) {
  int checked = 0;
  for (const std::string& name : gallery()) {
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
    // Every part where it was (the rod is spun back in the design's own placement).
    EXPECT_EQ(a.stable, b.stable) << a.summary << b.summary;
    EXPECT_NEAR(a.energy / a.mass, b.energy / b.mass, 1e-6) << a.summary << b.summary;
    EXPECT_NEAR(a.tilt_deg, b.tilt_deg, 1e-6) << a.summary << b.summary;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_LT((a.positions[i] - b.positions[i]).norm(), 1e-6) << "part " << i;
    }
  }
  EXPECT_GE(checked, 2);
}

// The soap bottle holders, their door rod spun about its axis by 23 angles round the turn.
// With one eye hook, its step-1 starts reach the target equally well (to 0.0001 mm) in
// several ways, and which of those step 2 relaxed was decided by that last hair: spun 92.2
// degrees, a random start came 0.0001 mm nearer than the verified one, only its candidate was
// relaxed, and the design rested 0.44 mm higher (mean height), 12 mm farther from its target.
// With two, the basket can hang anywhere along the rod under the bottle, and which places
// step 1's random starts found turned with the rod: their draws of its spin about its axis
// were measured from its zero, which the spin moves (4 of 23 spins rested up to 0.06 mm
// higher, the basket 9 mm along the rod).
TEST(Physics, ARodSpunAnyWayRestsTheSameWhereStartsTie) {
  for (const char* name : {"soap_bottle_one_eyehook", "soap_bottle_holder"}) {
    SCOPED_TRACE(name);
    const std::string yaml = read_example(name);
    const Outcome a = solve_text(yaml);
    ASSERT_TRUE(a.stable) << a.summary;
    for (int k = 1; k < 24; ++k) {
      const double spin = 15.37 * k;
      SCOPED_TRACE(fmt::format("door rod spun {:.2f} deg", spin));
      YAML::Node root = YAML::Load(yaml);
      for (YAML::Node e : root["environment"]) {
        e["frame"] = frame_node(frame_of(e["frame"]) * Frame(Vec3::Zero(), Vec3(0, 0, spin)));
      }
      const Outcome b = solve_text(emit(root));
      EXPECT_EQ(a.stable, b.stable) << b.summary;
      EXPECT_NEAR(a.energy / a.mass, b.energy / b.mass, 1e-6) << a.summary << b.summary;
      EXPECT_NEAR(a.target_mm, b.target_mm, 1e-6) << a.summary << b.summary;
      // Since the rod is spun back in the design's own placement: every part where it was.
      ASSERT_EQ(a.positions.size(), b.positions.size());
      for (std::size_t i = 0; i < a.positions.size(); ++i) {
        EXPECT_LT((a.positions[i] - b.positions[i]).norm(), 1e-6) << "part " << i;
      }
    }
  }
}

// Random starts explore: they may find a configuration nearer the target, but one that only
// rests as near as the verified and guided starts' (within kEquallyNear) must not move the
// answer. Where a family of configurations rests equally near (the toothbrush holder's clip
// may grip anywhere along a stretch of the handle), which member a random start lands on is
// an accident; the answer stays the earliest start's, and so does not depend on how many
// random starts there are.
TEST(Physics, MoreRandomStartsMoveNoAnswerAmongEquallyNearOnes) {
  int equally_near = 0;
  int held_designs = 0;
  for (const std::string& name : gallery()) {
    SCOPED_TRACE(name);
    const Design d = load_text(read_example(name));
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    SolveOptions two;
    two.target_starts = 2;  // the verified and the guided start
    const SolveResult few = solve(d.assembly, two);
    const SolveResult all = solve(d.assembly);  // and six random ones
    auto nearness = [](const SolveResult& r) {
      return r.target.position_mm + r.target.tilt_deg +
             (r.target.twist_free ? 0.0 : std::abs(r.target.twist_deg));
    };
    if (std::abs(nearness(all) - nearness(few)) > 0.01) continue;  // one is really nearer
    ++equally_near;
    EXPECT_EQ(few.stable, all.stable) << few.summary() << all.summary();
    ASSERT_EQ(few.parts.size(), all.parts.size());
    // Along neutral directions (a mug turning about its hook at no cost) a part may be
    // anywhere at the same height; with none, it is where it was.
    const bool held = few.neutral_directions.empty() && all.neutral_directions.empty();
    held_designs += held ? 1 : 0;
    for (std::size_t i = 0; i < few.parts.size(); ++i) {
      const Vec3 moved = few.parts[i].frame.pos - all.parts[i].frame.pos;
      EXPECT_LT(held ? moved.norm() : std::abs(moved.z()), 0.5) << few.parts[i].name << "\n"
                                                                << few.summary() << all.summary();
    }
  }
  // Most of the gallery is such a design, the toothbrush holder (no neutral direction) too.
  EXPECT_GE(equally_near, 8);
  EXPECT_GE(held_designs, 1);
}

// Every order of the connects in which each one finds a side already placed, the orders that
// move where a cycle closes included (a part that came in through one connection coming in
// through another): the same connections, the same answer. A broom handle hung from two eye
// hooks used to read its two tube-hook connections' alignment in opposite senses when the
// second eye hook's connect came first, and no start could reach the target.
TEST(Physics, BuildingACycleFromItsOtherEndRestsTheSame) {
  for (const std::string& name :
       {std::string("paper_towel_holder"), std::string("charger_holder")}) {
    SCOPED_TRACE(name);
    const std::string yaml = read_example(name);
    const YAML::Node root = YAML::Load(yaml);
    std::set<std::string> environment;
    for (const auto& e : root["environment"]) environment.insert(e["name"].as<std::string>());
    std::vector<YAML::Node> connects;
    for (const auto& c : root["connections"]) connects.push_back(YAML::Clone(c));
    auto part_of = [](const YAML::Node& ref) {
      const std::string s = ref.as<std::string>();
      return s.substr(0, s.find('.'));
    };
    // The connects that close a cycle when applied in `order`; nothing if one of them finds
    // neither of its sides placed.
    auto closing_in =
        [&](const std::vector<std::size_t>& order) -> std::optional<std::set<std::size_t>> {
      std::set<std::string> placed = environment;
      std::set<std::size_t> closing;
      for (std::size_t i : order) {
        const std::string p = part_of(connects[i]["connect"][0]);
        const std::string q = part_of(connects[i]["connect"][1]);
        if (!placed.count(p) && !placed.count(q)) return std::nullopt;
        if (placed.count(p) && placed.count(q)) closing.insert(i);
        placed.insert(p);
        placed.insert(q);
      }
      return closing;
    };
    const Outcome a = solve_text(yaml);
    ASSERT_TRUE(a.stable) << a.summary;
    std::vector<std::size_t> order(connects.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    const std::set<std::size_t> closing_in_file = *closing_in(order);
    int tried = 0;
    int moved_closure = 0;
    do {
      const std::optional<std::set<std::size_t>> closing = closing_in(order);
      if (!closing) continue;
      if (*closing != closing_in_file) ++moved_closure;
      YAML::Node shuffled = YAML::Clone(root);
      YAML::Node list(YAML::NodeType::Sequence);
      for (std::size_t i : order) list.push_back(YAML::Clone(connects[i]));
      shuffled["connections"] = list;
      const Outcome b = solve_text(emit(shuffled));
      ++tried;
      EXPECT_EQ(a.stable, b.stable) << a.summary << b.summary;
      EXPECT_NEAR(a.target_mm, b.target_mm, 0.01) << a.summary << b.summary;
      EXPECT_NEAR(a.energy / a.mass, b.energy / b.mass, 0.05) << a.summary << b.summary;
      // Parts are numbered in the order they come in: compared by name.
      ASSERT_EQ(a.by_name.size(), b.by_name.size());
      for (const auto& [part, at] : a.by_name) {
        ASSERT_TRUE(b.by_name.count(part)) << part;
        EXPECT_NEAR(at.z(), b.by_name.at(part).z(), 1.0) << part;
      }
    } while (std::next_permutation(order.begin(), order.end()));
    EXPECT_GE(tried, 2);
    EXPECT_GE(moved_closure, 1) << "no order moved where a cycle closes";
  }
}

// Any order of the connects in which each finds one of its sides placed — a part coming in
// through another connection, a cycle closing elsewhere — with any connect written the other
// way round is the same design: the same verdict, the same target error and every part in the
// same place. (The basket between rods rested
// 18 mm from its target, turned half a turn, in five of its eight orders.)
TEST(Physics, AnyOrderOfConnectsGivesTheSameAnswer) {
  std::mt19937_64 rng(11);
  for (const std::string& name : gallery()) {
    SCOPED_TRACE(name);
    const std::string yaml = read_example(name);
    const YAML::Node root = YAML::Load(yaml);
    std::vector<YAML::Node> connects;
    for (const auto& c : root["connections"]) connects.push_back(YAML::Clone(c));
    auto part_of = [](const YAML::Node& ref) {
      const std::string s = ref.as<std::string>();
      return s.substr(0, s.find('.'));
    };
    const Design file = load_text(yaml);
    ASSERT_TRUE(file.feasible()) << file.diagnostics.format();
    const SolveResult a = solve(file.assembly);
    std::map<std::string, Mat4> at;
    for (const SolvedPart& p : a.parts) at[p.name] = p.frame.matrix();
    const int orders = 3;
    for (int trial = 0; trial < orders; ++trial) {
      std::set<std::string> placed;
      for (const auto& e : root["environment"]) placed.insert(e["name"].as<std::string>());
      std::vector<std::size_t> left(connects.size());
      for (std::size_t i = 0; i < left.size(); ++i) left[i] = i;
      YAML::Node list(YAML::NodeType::Sequence);
      std::vector<std::size_t> order;
      while (!left.empty()) {
        std::vector<std::size_t> ready;
        for (std::size_t i = 0; i < left.size(); ++i) {
          const YAML::Node& c = connects[left[i]];
          if (placed.count(part_of(c["connect"][0])) || placed.count(part_of(c["connect"][1]))) {
            ready.push_back(i);
          }
        }
        ASSERT_FALSE(ready.empty());
        const std::size_t pick =
            ready[std::uniform_int_distribution<std::size_t>(0, ready.size() - 1)(rng)];
        const YAML::Node& c = connects[left[pick]];
        order.push_back(left[pick]);
        YAML::Node written = YAML::Clone(c);
        // Half the connects written the other way round: [a, b] and [b, a] are one connect.
        if (std::bernoulli_distribution(0.5)(rng)) {
          const YAML::Node first = YAML::Clone(written["connect"][0]);
          written["connect"][0] = YAML::Clone(written["connect"][1]);
          written["connect"][1] = first;
        }
        list.push_back(written);
        placed.insert(part_of(c["connect"][0]));
        placed.insert(part_of(c["connect"][1]));
        left.erase(left.begin() + static_cast<std::ptrdiff_t>(pick));
      }
      SCOPED_TRACE(fmt::format("order {}", fmt::join(order, " ")));
      YAML::Node shuffled = YAML::Clone(root);
      shuffled["connections"] = list;
      const Design other = load_text(emit(shuffled));
      ASSERT_TRUE(other.feasible()) << other.diagnostics.format();
      const SolveResult b = solve(other.assembly);
      EXPECT_EQ(a.stable, b.stable) << a.summary() << b.summary();
      EXPECT_NEAR(a.target.position_mm, b.target.position_mm, 1e-6) << b.summary();
      EXPECT_NEAR(a.target.rotation_deg, b.target.rotation_deg, 1e-6) << b.summary();
      ASSERT_EQ(a.parts.size(), b.parts.size());
      for (const SolvedPart& p : b.parts) {
        ASSERT_TRUE(at.count(p.name)) << p.name;
        const Mat4 m = p.frame.matrix();
        EXPECT_LT((m.topRightCorner<3, 1>() - at[p.name].topRightCorner<3, 1>()).norm(), 1e-6)
            << p.name;
        EXPECT_LT((m.topLeftCorner<3, 3>() - at[p.name].topLeftCorner<3, 3>()).norm(), 1e-9)
            << p.name;
      }
    }
  }
}

// A chain of S-hooks between two rods, the right rod the left one turned half a turn about the
// vertical through the middle (so the design is the same seen from either side), built from
// the left or from the right: the same chain, the same answer.
std::string chain_between_rods(int hooks,
                               bool from_left,
                               const Vec3& left = Vec3(-200, 0, 500),
                               const Vec3& right = Vec3(200, 0, 500)) {
  std::string s = fmt::format(
      "fabkit: hacks/1\nname: chain\nenvironment:\n"
      "  - {{name: left, primitives: {{rod: {{type: rod, radius: 4, length: 300}}}}, "
      "frame: {{pos: [{}, {}, {}], rot: [90, 0, 0]}}}}\n"
      "  - {{name: right, primitives: {{rod: {{type: rod, radius: 4, length: 300}}}}, "
      "frame: {{pos: [{}, {}, {}], rot: [90, 0, 180]}}}}\nparts:\n",
      left.x(),
      left.y(),
      left.z(),
      right.x(),
      right.y(),
      right.z());
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

// Ten small S-hooks between two rods 408 mm apart (88 % of their reach), the right rod
// 14.3 mm lower.
std::string taut_chain(bool from_left) {
  return chain_between_two_rods("DoubleHook",
                                10,
                                Vec3(-204.12948237350665, 0, 500),
                                Vec3(204.12948237350665, 0, 485.6738923753454),
                                0,
                                from_left);
}

// A cycle that closes closes whichever end it is built from and whatever the seed. Pulled out
// nearly taut, the chain passes configurations where a millionth of a parameter's range
// decides which way it straightens; the closure search's last-resort stretching start, tried
// one way only, left it open (the best of 16 starts left a gap of 4.6 mm) for 3 of 9 seeds
// from either end, a different 3 for each end. Tried four ways it closes for all but seed 3
// from the left rod and seed 9 from the right. Every design file is now verified in the
// canonical order of its connects (from both rods at once, closing in the chain's middle),
// whichever end the file builds from.
TEST(Physics, ANearlyTautChainClosesFromEitherEndWhateverTheSeed) {
  for (bool from_left : {true, false}) {
    for (std::uint64_t seed : {1, 2, 3, 7, 9}) {
      SCOPED_TRACE(fmt::format("from the {} rod, seed {}", from_left ? "left" : "right", seed));
      DesignOptions options;
      options.verify.seed = seed;
      const Design d =
          load_design_text(taut_chain(from_left), "taut.yaml", PartsLibrary::builtin(), options);
      EXPECT_TRUE(d.feasible()) << d.diagnostics.format();
      // The cycle is closed once, by the connect that completes it in the canonical order.
      int closing = 0;
      for (const DesignStep& step : d.steps) closing += step.report.closes_cycle ? 1 : 0;
      EXPECT_EQ(closing, 1);
    }
  }
  const Outcome a = solve_text(taut_chain(true));
  const Outcome b = solve_text(taut_chain(false));
  EXPECT_TRUE(a.stable) << a.summary;
  EXPECT_TRUE(b.stable) << b.summary;
  ASSERT_EQ(a.positions.size(), b.positions.size());
  for (std::size_t i = 0; i < a.positions.size(); ++i) {
    EXPECT_LT((a.positions[i] - b.positions[i]).norm(), 1e-3) << "part " << i;
  }
}

TEST(Physics, ASymmetricChainRestsTheSameFromEitherEnd) {
  for (int hooks : {10, 11}) {
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

// Rods at different heights (the right one 80 mm lower): built from either end, the chain is
// the same chain and rests in the same place — hook i from the left where hook i from the left
// of the other build is — stable, with its lowest point on the lower rod's side.
TEST(Physics, AnUnevenChainRestsTheSameFromEitherEnd) {
  for (int hooks : {10, 12}) {
    SCOPED_TRACE(hooks);
    const Vec3 left(-200, 0, 500);
    const Vec3 right(200, 0, 420);
    const Outcome l = solve_text(chain_between_rods(hooks, true, left, right));
    const Outcome r = solve_text(chain_between_rods(hooks, false, left, right));
    EXPECT_TRUE(l.stable) << l.summary;
    EXPECT_TRUE(r.stable) << r.summary;
    ASSERT_EQ(l.positions.size(), static_cast<std::size_t>(hooks + 2));
    ASSERT_EQ(r.positions.size(), l.positions.size());
    // Hook i from the left is s<i> in the build from the left and s<hooks + 1 - i> in the
    // other (parts are looked up by name: the order they are listed in is the solver's).
    Vec3 lowest = l.by_name.at("s1");
    for (int i = 1; i <= hooks; ++i) {
      const Vec3& from_left = l.by_name.at(fmt::format("s{}", i));
      const Vec3& from_right = r.by_name.at(fmt::format("s{}", hooks + 1 - i));
      EXPECT_LT((from_left - from_right).norm(), 1.0) << "hook " << i;
      if (from_left.z() < lowest.z()) lowest = from_left;
    }
    EXPECT_GT(lowest.x(), 0.0) << l.summary;
  }
}

// The order the environments are listed in is not physical either: a chain between two rods
// at different heights, its rods listed the other way round, is solved as the same model and
// rests exactly where it did.
TEST(Physics, TheOrderOfTheEnvironmentsDoesNotMatter) {
  const std::string yaml = chain_between_rods(11, true, Vec3(-200, 0, 500), Vec3(200, 0, 420));
  YAML::Node root = YAML::Load(yaml);
  YAML::Node swapped = YAML::Clone(root);
  YAML::Node envs(YAML::NodeType::Sequence);
  envs.push_back(YAML::Clone(root["environment"][1]));
  envs.push_back(YAML::Clone(root["environment"][0]));
  swapped["environment"] = envs;
  // The same model: the connections made in the same order (the middle hook, s6, comes in
  // through the same neighbour and the cycle closes at the other).
  auto made = [](const Design& d) {
    std::vector<std::string> out;
    for (const Connection& c : d.assembly.connections()) {
      out.push_back(d.assembly.label(c.first.part, c.first.primitive) + " " +
                    d.assembly.label(c.second.part, c.second.primitive));
    }
    return out;
  };
  EXPECT_EQ(made(load_text(yaml)), made(load_text(emit(swapped))));
  const Outcome a = solve_text(yaml);
  const Outcome b = solve_text(emit(swapped));
  EXPECT_TRUE(a.stable) << a.summary;
  EXPECT_EQ(a.stable, b.stable) << b.summary;
  ASSERT_EQ(a.by_name.size(), b.by_name.size());
  for (const auto& [part, at] : a.by_name) {
    ASSERT_TRUE(b.by_name.count(part)) << part;
    EXPECT_LT((at - b.by_name.at(part)).norm(), 1e-6) << part;
  }
}

// Twelve to fourteen S-hooks are longer than the 400 mm between the rods: the cycle search
// closes such a slack chain with links folded back over their neighbours (through each other,
// 4 mm deep), a rest state of the joints alone that no local step undoes. What a real chain
// does is sag: every hook below the rods, lower towards the middle, the lowest in the middle,
// nothing passing through anything — and, the design being its own mirror image, the same
// sag mirrored when the chain is built from the other end.
TEST(Physics, ASlackChainBetweenRodsSagsUnfolded) {
  for (int hooks : {12, 14}) {
    SCOPED_TRACE(hooks);
    std::vector<std::vector<Vec3>> sags;
    for (const bool from_left : {true, false}) {
      SCOPED_TRACE(from_left);
      const Design d = load_text(chain_between_rods(hooks, from_left));
      ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
      const SolveResult r = solve(d.assembly);
      EXPECT_TRUE(r.stable) << r.summary();
      EXPECT_LE(r.max_penetration_mm, 0.5) << r.summary();
      // Hook i counted from the left rod.
      std::vector<Vec3> sag;
      for (int i = 1; i <= hooks; ++i) {
        const std::string name = fmt::format("s{}", from_left ? i : hooks + 1 - i);
        for (const SolvedPart& part : r.parts) {
          if (part.name == name) sag.push_back(part.frame.pos);
        }
      }
      ASSERT_EQ(sag.size(), static_cast<std::size_t>(hooks));
      for (int i = 0; i + 1 < hooks; ++i) {
        const double z = sag[static_cast<std::size_t>(i)].z();
        const double next = sag[static_cast<std::size_t>(i + 1)].z();
        EXPECT_LT(z, 500.0) << "hook " << i + 1 << " above the rods";
        // Lower towards the middle from either rod (the two middle hooks level).
        if (i + 1 < hooks / 2) {
          EXPECT_LT(next, z) << "hooks " << i + 1 << ", " << i + 2;
        }
        if (i >= hooks / 2) {
          EXPECT_GT(next, z) << "hooks " << i + 1 << ", " << i + 2;
        }
      }
      sags.push_back(sag);
    }
    // Mirror images: hook i from the left at x is hook i from the left of the mirrored build
    // at the same place (the design is symmetric about x = 0, so the sag is too).
    for (int i = 0; i < hooks; ++i) {
      const Vec3& l = sags[0][static_cast<std::size_t>(i)];
      const Vec3& r = sags[1][static_cast<std::size_t>(i)];
      const Vec3& mirror = sags[0][static_cast<std::size_t>(hooks - 1 - i)];
      EXPECT_NEAR(l.x(), r.x(), 1.0) << "hook " << i + 1;
      EXPECT_NEAR(l.z(), r.z(), 1.0) << "hook " << i + 1;
      EXPECT_NEAR(l.x(), -mirror.x(), 1.0) << "hook " << i + 1;
      EXPECT_NEAR(l.z(), mirror.z(), 1.0) << "hook " << i + 1;
    }
  }
}

// `hooks` medium S-hooks between two rods, built from the right rod; `mirrored` reflects the
// world through the plane x = 0 (the left rod, which the chain ends on, then stands on the right)
// and `flip_alignments` turns every connection's alignment the other way (the mirror image of
// an interlock: two hooks hung through each other the other way round).
std::string medium_chain(
    int hooks, double span, double drop, bool mirrored, bool flip_alignments = false) {
  auto alignment = [&](bool flip) { return flip != flip_alignments ? ", alignment: flip" : ""; };
  const double side = mirrored ? -1.0 : 1.0;
  std::string s = fmt::format(
      "fabkit: hacks/1\nname: medium chain\nenvironment:\n"
      "  - {{name: left, primitives: {{rod: {{type: rod, radius: 2.5, length: 300}}}}, "
      "frame: {{pos: [{}, 0, 500], rot: [90, 0, 0]}}}}\n"
      "  - {{name: right, primitives: {{rod: {{type: rod, radius: 2.5, length: 300}}}}, "
      "frame: {{pos: [{}, 0, {}], rot: [90, 0, {}]}}}}\nparts:\n",
      -side * span / 2,
      side * span / 2,
      500 - drop,
      side * 180);
  for (int i = 1; i <= hooks; ++i)
    s += fmt::format("  - {{name: s{}, part: DoubleHookMedium}}\n", i);
  s += fmt::format(
      "connections:\n  - {{connect: [s{}.hook2, right.rod]{}}}\n", hooks, alignment(true));
  for (int i = hooks - 1; i >= 1; --i) {
    s += fmt::format("  - {{connect: [s{}.hook2, s{}.hook1]{}}}\n", i, i + 1, alignment(false));
  }
  s += fmt::format("  - {{connect: [s1.hook1, left.rod]{}}}\n", alignment(false));
  return s;
}

// A chain and its mirror image. The S-hooks are flat, their own mirror images, but an interlock
// is not: the mirror image of two hooks hung through each other is the pair hung through each
// other the other way round, the connection's other alignment (a hook hung on a rod likewise).
// So the mirror image of the design reflects the world and turns every alignment the other way;
// it rests as the mirror image of the chain. Reflecting the world alone keeps each interlock as
// it was: another design, which must hold too (the way its cycle first closed let a hook slide
// off the open end of the next under gravity, and that was once the verdict; the same chain
// hooked another way holds). "Falls apart" is said of a design only when no way of closing it
// that was tried holds.
TEST(Physics, AMirroredChainRestsAsTheMirrorImageOfTheChain) {
  const double span = 254.2680214492943;
  const double drop = 57.312779318487;
  const Design a = load_text(medium_chain(10, span, drop, false));
  const Design mirror = load_text(medium_chain(10, span, drop, true, /*flip_alignments=*/true));
  const Design reflected = load_text(medium_chain(10, span, drop, true));
  ASSERT_TRUE(a.feasible()) << a.diagnostics.format();
  ASSERT_TRUE(mirror.feasible()) << mirror.diagnostics.format();
  ASSERT_TRUE(reflected.feasible()) << reflected.diagnostics.format();
  const SolveResult ra = solve(a.assembly);
  const SolveResult rm = solve(mirror.assembly);
  const SolveResult rr = solve(reflected.assembly);
  EXPECT_TRUE(ra.stable) << ra.summary();
  EXPECT_TRUE(rm.stable) << rm.summary();
  EXPECT_TRUE(rr.stable) << rr.summary();
  EXPECT_LE(rm.max_penetration_mm, 0.5) << rm.summary();
  EXPECT_LE(rr.max_penetration_mm, 0.5) << rr.summary();
  for (const SolvedPart& p : ra.parts) {
    for (const SolvedPart& q : rm.parts) {
      if (q.name != p.name) continue;
      EXPECT_NEAR(p.frame.pos.x(), -q.frame.pos.x(), 1.0) << p.name;
      EXPECT_NEAR(p.frame.pos.y(), q.frame.pos.y(), 1.0) << p.name;
      EXPECT_NEAR(p.frame.pos.z(), q.frame.pos.z(), 1.0) << p.name;
    }
  }
}

// `yaml` with the connect on line `line` (1-based) turned the other way round: its
// `alignment: flip` added, or taken away (what a remedy tells the user to write).
std::string with_line_turned(const std::string& yaml, int line) {
  std::istringstream in(yaml);
  std::string out;
  std::string text;
  for (int n = 1; std::getline(in, text); ++n) {
    if (n == line) {
      EXPECT_NE(text.find("connect:"), std::string::npos) << text;
      const std::size_t flip = text.find(", alignment: flip");
      text = flip != std::string::npos ? text.erase(flip, 17)
                                       : text.substr(0, text.rfind('}')) + ", alignment: flip}";
    }
    out += text + "\n";
  }
  return out;
}

// At rest: stable, the potential flat to the equilibrium tolerance, nothing passing through.
void expect_at_rest(const SolveResult& r) {
  EXPECT_TRUE(r.stable) << r.summary();
  EXPECT_LT(r.equilibrium_residual, 1e-6) << r.summary();
  EXPECT_LE(r.max_penetration_mm, 0.5) << r.summary();
}

// A slack chain of four medium S-hooks (rods 52.1 mm apart, the right 40.3 mm lower) and its
// mirror image both rest, whatever the seed. Nearly every way of closing it rests with a hook at
// the open end of the next (it would slide off): with 24 other closings the mirror image found
// no rest that holds with seed 1 and the chain none with seed 4 ("falls apart" one way, "stable"
// the other); a group this small tries four times as many.
TEST(Physics, ASlackChainAndItsMirrorImageBothRestWhateverTheSeed) {
  const double span = 52.13388551944394;
  const double drop = 40.29840426088478;
  for (const bool mirrored : {false, true}) {
    const Design d = load_text(medium_chain(4, span, drop, mirrored, /*flip_alignments=*/mirrored));
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    for (const std::uint64_t seed : {1, 4}) {
      SCOPED_TRACE(fmt::format("mirrored {}, seed {}", mirrored, seed));
      SolveOptions options;
      options.seed = seed;
      expect_at_rest(solve(d.assembly, options));
    }
  }
}

// A chain whose second hook hangs by the tip of the third falls apart, and the solve says which
// connect, made the other way round, makes it hold (SolveResult::remedy): it names that connect
// and its line, and the design with that one alignment turned holds indeed. A hook sliding down
// a tilted rod has nothing to turn that helps: no remedy is claimed. (The chains this test
// used before hold now: four hooks 92.8 mm between the rods since contact runs no longer carry
// links through pairs they did not watch, its third hook resting against the right rod; three
// hooks 86.9 mm apart since small groups try 96 other closings, one of which rests with the
// third hook's lower hook against its closed end and a link leaning on it. This one, three
// hooks 103.4 mm apart with the right rod 41.7 mm higher, was found by a sweep of random
// chains: its second hook slides off the first's open end in every closing tried.)
TEST(Physics, AChainThatFallsApartSaysWhichConnectTurnedHolds) {
  const std::string yaml = medium_chain(3, 103.35466638480828, -41.666330758393514, false);
  const Design d = load_text(yaml);
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const SolveResult r = solve(d.assembly);
  ASSERT_FALSE(r.stable) << r.summary();
  ASSERT_FALSE(r.slips.empty()) << r.summary();
  EXPECT_NE(r.remedy.find("alignment: flip on that connect"), std::string::npos) << r.summary();
  const Connection& turned = d.assembly.connection(r.slips.front().connection);
  ASSERT_GT(turned.where.line, 0);
  EXPECT_NE(r.remedy.find(fmt::format(":{})", turned.where.line)), std::string::npos) << r.remedy;
  // That line with its alignment turned: the design holds.
  const std::string changed = with_line_turned(yaml, turned.where.line);
  const Design fixed = load_text(changed);
  ASSERT_TRUE(fixed.feasible()) << fixed.diagnostics.format();
  EXPECT_TRUE(solve(fixed.assembly).stable) << changed;
  SolveOptions no_remedy;
  no_remedy.seek_remedy = false;
  EXPECT_TRUE(solve(d.assembly, no_remedy).remedy.empty());
  const Design tilted = load_text(R"(fabkit: hacks/1
environment:
  - {name: bar, primitives: {rod: {type: rod, radius: 5, length: 200}}, frame: {pos: [0, 0, 500], rot: [70, 0, 90]}}
parts:
  - {name: shook, part: DoubleHookMedium}
  - {name: mug, part: Mug}
connections:
  - connect: [shook.hook1, bar.rod]
  - connect: [mug.hook, shook.hook2]
)");
  ASSERT_TRUE(tilted.feasible()) << tilted.diagnostics.format();
  const SolveResult t = solve(tilted.assembly);
  EXPECT_FALSE(t.stable) << t.summary();
  EXPECT_TRUE(t.remedy.empty()) << t.remedy;
}

// Two links of a chain passing through each other: the solve says which of their connects,
// made the other way round, untangles it (SolveResult::remedy), and that design holds indeed.
TEST(Physics, AChainThroughItselfSaysWhichConnectTurnedHolds) {
  const std::string yaml = R"(fabkit: hacks/1
name: medium chain
environment:
  - {name: left, primitives: {rod: {type: rod, radius: 2.5, length: 300}}, frame: {pos: [-111.09713556274362, 0, 500], rot: [90, 0, 0]}}
  - {name: right, primitives: {rod: {type: rod, radius: 2.5, length: 300}}, frame: {pos: [111.09713556274362, 0, 440.7178278398759], rot: [90, 0, 180.0]}}
parts:
  - {name: s1, part: DoubleHookMedium}
  - {name: s2, part: DoubleHookMedium}
  - {name: s3, part: DoubleHookMedium}
  - {name: s4, part: DoubleHookMedium}
  - {name: s5, part: DoubleHookMedium}
connections:
  - {connect: [s5.hook2, right.rod], alignment: flip}
  - {connect: [s4.hook2, s5.hook1]}
  - {connect: [s3.hook2, s4.hook1]}
  - {connect: [s2.hook2, s3.hook1]}
  - {connect: [s1.hook2, s2.hook1]}
  - {connect: [s1.hook1, left.rod]}
)";
  const Design d = load_text(yaml);
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const SolveResult r = solve(d.assembly);
  ASSERT_FALSE(r.stable) << r.summary();
  EXPECT_TRUE(r.slips.empty()) << r.summary();
  EXPECT_GT(r.max_penetration_mm, 0.5) << r.summary();
  ASSERT_FALSE(r.remedy.empty()) << r.summary();
  // The remedy's line, with its alignment turned: the design holds.
  const std::size_t colon = r.remedy.rfind(':');
  ASSERT_NE(colon, std::string::npos) << r.remedy;
  const std::string changed = with_line_turned(yaml, std::stoi(r.remedy.substr(colon + 1)));
  const Design fixed = load_text(changed);
  ASSERT_TRUE(fixed.feasible()) << fixed.diagnostics.format();
  const SolveResult after = solve(fixed.assembly);
  EXPECT_TRUE(after.stable) << changed << after.summary();
  EXPECT_LE(after.max_penetration_mm, 0.5) << after.summary();
}

// A mug on an S-hook from an adhesive wall hook: the wall hook stays where it was stuck (step 2
// does not turn it on the wall), whatever other ways of hanging the rest are tried, and the mug
// hangs below it. (Other closings that turned the wall hook on the wall were once relaxed and
// only half kept: the reported mug lay level with the hook, through the wall.)
TEST(Physics, WhatStep2HoldsStaysAsBuiltWhenOtherClosingsAreTried) {
  const Design d = load_text(R"(fabkit: hacks/1
name: wall mug
environment:
  - {name: wall, primitives: {surface: {type: surface, width: 600, length: 600}}, frame: {pos: [0, 0, 1000], rot: [90, 0, 0]}}
parts:
  - {name: wh, part: WallHook}
  - {name: s1, part: DoubleHookMedium}
  - {name: mug, part: Mug}
connections:
  - connect: [wh.surface, wall.surface]
  - connect: [s1.hook1, wh.hook]
  - connect: [mug.hook, s1.hook2]
)");
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const std::vector<Mat4> built = d.assembly.part_frames(d.assembly.values());
  const SolveResult r = solve(d.assembly);
  std::map<std::string, Frame> at;
  for (const SolvedPart& p : r.parts) at[p.name] = p.frame;
  const Mat4 stuck = at.at("wh").matrix();
  EXPECT_LT((stuck - built[1]).norm(), 1e-6) << r.summary();
  EXPECT_LT(at.at("mug").pos.z(), at.at("wh").pos.z() - 50.0) << r.summary();
  // A sideways wall hook lets the S-hook slide off its open end: said so, not "stable".
  EXPECT_FALSE(r.stable) << r.summary();
}

// A chain of N S-hooks hangs plumb from a level rod: every hook right under the first. From
// 16 hooks the relaxation's models are large (a factored eigenbasis, gauge pairs folded).
TEST(Physics, AChainOfHooksHangsPlumb) {
  for (int hooks : {1, 2, 3, 5, 8, 12, 16, 32}) {
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

// A 16-S-hook chain from a rod with a mug on the last hook, the mug the target (its goal, for
// the mug's hook, is the mug's own frame where it rests alone moved 20 mm: a goal step 1 gets
// within 72 mm of). Long enough to be hung link by link before its fits and relaxations
// (hanging.h). The mirror image reflects the world in the plane x = 0 and turns
// every interlock the other way (AMirroredChainRestsAsTheMirrorImageOfTheChain).
std::string long_chain_with_mug(bool mirrored, const std::string& target) {
  std::string s =
      "fabkit: hacks/1\nname: long chain\nenvironment:\n"
      "  - {name: bar, primitives: {rod: {type: rod, radius: 4, length: 300}}, "
      "frame: {pos: [0, 0, 1500], rot: [90, 0, 0]}}\nparts:\n";
  for (int i = 1; i <= 16; ++i) s += fmt::format("  - {{name: s{}, part: DoubleHook}}\n", i);
  // The target is a part too: the mug is declared as one or the other.
  s += (target.empty() ? std::string("  - {name: mug, part: Mug}\n") : target) + "connections:\n";
  const std::string flip = mirrored ? ", alignment: flip" : "";
  s += fmt::format("  - {{connect: [s1.hook1, bar.rod]{}}}\n", flip);
  for (int i = 2; i <= 16; ++i) {
    s += fmt::format("  - {{connect: [s{}.hook1, s{}.hook2]{}}}\n", i, i - 1, flip);
  }
  return s + fmt::format("  - {{connect: [mug.hook, s16.hook2]{}}}\n", flip);
}

// Hung link by link, a long chain with a target still rests the same wherever the world is,
// moved and turned with it, and its mirror image rests as its mirror image (up to free turns
// about the vertical): the pass depends on the parts and gravity, not on where the design
// stands or which way its hooks face.
TEST(Physics, ALongChainWithATargetRestsTheSameMovedOrMirrored) {
  const Design alone = load_text(long_chain_with_mug(false, ""));
  ASSERT_TRUE(alone.feasible()) << alone.diagnostics.format();
  const SolveResult rest = solve(alone.assembly);
  ASSERT_TRUE(rest.stable) << rest.summary();
  Frame goal;
  for (const SolvedPart& q : rest.parts) {
    if (q.name == "mug") goal = q.frame;
  }
  goal.pos.x() += 20;
  auto target = [&](const Frame& f) {
    return "target: {name: mug, part: Mug, primitive: hook, frame: " + flow_frame(f) + "}\n";
  };
  const std::string yaml = long_chain_with_mug(false, target(goal));
  const Outcome a = solve_text(yaml);
  EXPECT_TRUE(a.stable) << a.summary;
  const Frame world(Vec3(-812.25, 1404.5, 233.0), Vec3(0, 0, 131.0));
  const Outcome b = solve_text(moved(yaml, world));
  EXPECT_EQ(a.stable, b.stable) << b.summary;
  for (const auto& [part, at] : a.by_name) {
    EXPECT_LT((b.by_name.at(part) - world.apply(at)).norm(), 1e-6) << part;
  }
  // The mirror image, its goal taken the same way from where its own mug rests alone (20 mm
  // the other way): it rests as the mirror image.
  const Design mirror_alone = load_text(long_chain_with_mug(true, ""));
  ASSERT_TRUE(mirror_alone.feasible()) << mirror_alone.diagnostics.format();
  Frame mirrored_goal;
  for (const SolvedPart& q : solve(mirror_alone.assembly).parts) {
    if (q.name == "mug") mirrored_goal = q.frame;
  }
  EXPECT_NEAR(mirrored_goal.pos.x(), -(goal.pos.x() - 20), 0.01);
  mirrored_goal.pos.x() -= 20;
  const Outcome m = solve_text(long_chain_with_mug(true, target(mirrored_goal)));
  // Up to the turns about the vertical that cost nothing (each hook's and the mug's: a chain
  // turns freely where it hangs), which keep every height.
  EXPECT_EQ(a.stable, m.stable) << m.summary;
  EXPECT_NEAR(a.target_mm, m.target_mm, 0.01) << a.summary << m.summary;
  EXPECT_NEAR(a.energy, m.energy, 1e-6 * a.mass) << a.summary << m.summary;
  for (const auto& [part, at] : a.by_name) {
    EXPECT_NEAR(m.by_name.at(part).z(), at.z(), 0.01) << part << m.summary;
  }
}

// A chain long enough to span two wall hooks is found to span them, and hangs from both with
// its lowest link near the middle: 16 and 18 S-hooks (reaching about 680 and 760 mm) between
// hooks 605.5 mm apart, where the closure search used to leave a gap of hundreds of mm
// (issue 9, item 4), and 15 (reaching about 636 mm: 95 % taut), closed by the stretching
// start.
using testing_designs::span_between_wall_hooks;

// A span's verdict and sag: stable, every hook below the wall hooks, the lowest near the middle
// (the design is symmetric about y = 0).
void expect_sags_between_wall_hooks(const Outcome& o, int hooks) {
  EXPECT_TRUE(o.stable) << o.summary;
  ASSERT_EQ(o.positions.size(), static_cast<std::size_t>(hooks + 1));
  std::size_t lowest = 1;
  for (std::size_t i = 1; i < o.positions.size(); ++i) {
    if (o.positions[i].z() < o.positions[lowest].z()) lowest = i;
    EXPECT_LT(o.positions[i].z(), 1000.0) << "hook " << i << " above the wall hooks";
  }
  EXPECT_LT(std::abs(o.positions[lowest].y()), 60.0) << o.summary;
}

TEST(Physics, AChainLongEnoughToSpanTwoHooksSpansThem) {
  for (int hooks : {15, 16, 18}) {
    SCOPED_TRACE(hooks);
    expect_sags_between_wall_hooks(solve_text(span_between_wall_hooks(hooks)), hooks);
  }
}

// Much longer chains over the same span (24 S-hooks reach about 1 m over 605.5 mm) are closed
// by the cycle search with links folded back through their neighbours, a different fold for
// each seed of its random starts; what rests is the same sag whatever the seed (it was
// "passes through", "falls apart", "did not converge" or stable, seed by seed). The seed
// chooses among equivalent starts: physics does not depend on it.
TEST(Physics, ALongSlackSpanSagsWhateverTheSeed) {
  constexpr int kHooks = 24;
  std::vector<double> lowest;
  for (std::uint64_t seed : {1, 2, 3}) {
    SCOPED_TRACE(seed);
    DesignOptions design_options;
    design_options.verify.seed = seed;
    const Design d = load_design_text(
        span_between_wall_hooks(kHooks), "span.yaml", PartsLibrary::builtin(), design_options);
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    SolveOptions options;
    options.seed = seed;
    const SolveResult r = solve(d.assembly, options);
    Outcome o;
    o.stable = r.stable;
    o.summary = r.summary();
    for (const SolvedPart& p : r.parts) o.positions.push_back(p.frame.pos);
    expect_sags_between_wall_hooks(o, kHooks);
    EXPECT_LE(r.max_penetration_mm, 0.5) << o.summary;
    double low = o.positions[1].z();
    for (const Vec3& p : o.positions) low = std::min(low, p.z());
    lowest.push_back(low);
  }
  for (double low : lowest) EXPECT_NEAR(low, lowest.front(), 1.0);
}

// A gallery design verified and solved with `seed` for every random start.
SolveResult solved_with_seed(const std::string& name, std::uint64_t seed) {
  DesignOptions design_options;
  design_options.verify.seed = seed;
  const Design d =
      load_design_text(read_example(name), name + ".yaml", PartsLibrary::builtin(), design_options);
  EXPECT_TRUE(d.feasible()) << d.diagnostics.format();
  SolveOptions options;
  options.seed = seed;
  return solve(d.assembly, options);
}

// The reading nook rests with nothing passing through for other seeds than the default too.
// Its two chains used to end 15-45 mm inside each other with other seeds ("parts pass through
// each other"): a relaxation with contact rows that swung its links farther than the pairs it
// watched carried them through pairs it did not watch, and then could not go on from there
// (no run with those pairs' rows can start where they are inside each other), so the plain
// run's result stood. Now it runs again from its start with them watched; without that, seed 7
// passes through. (Found with seeds 2 and 5 when designs were solved where they stand; in
// their own placement seeds 2, 3 and 5 end "did not converge", 4, 6 and 8 pass through:
// docs/gallery.md.)
TEST(Physics, TheReadingNookRestsApartWithOtherSeeds) {
  const SolveResult r = solved_with_seed("reading_nook", 7);
  EXPECT_TRUE(r.stable) << r.summary();
  EXPECT_LE(r.max_penetration_mm, 0.5) << r.summary();
}

// A design whose verified configuration closes its cycles the wrong way round and whose step 1
// cannot leave it is solved again with harder starts before it is said not to hold. The paper
// towel holder with seed 5 closed with its broom rod through the wall panel (123 mm deep), its
// random starts did not close (two eye hooks taped to one rod: one start of the closure search
// each) and it ended "parts pass through each other", 414 mm deep; with four starts each, two
// close, one reaches the target and it rests as with seed 1, the roll against the panel's edge.
TEST(Physics, ThePaperTowelHolderRestsTheSameWithAnotherSeed) {
  const SolveResult first = solved_with_seed("paper_towel_holder", 1);
  const SolveResult fifth = solved_with_seed("paper_towel_holder", 5);
  ASSERT_TRUE(first.stable) << first.summary();
  EXPECT_TRUE(fifth.stable) << fifth.summary();
  EXPECT_LE(fifth.max_penetration_mm, 0.5) << fifth.summary();
  EXPECT_NEAR(fifth.target.position_mm, first.target.position_mm, 0.1) << fifth.summary();
  EXPECT_NEAR(fifth.target.tilt_deg, first.target.tilt_deg, 0.1) << fifth.summary();
  ASSERT_EQ(first.parts.size(), fifth.parts.size());
  for (std::size_t i = 0; i < first.parts.size(); ++i) {
    EXPECT_NEAR(fifth.parts[i].frame.pos.z(), first.parts[i].frame.pos.z(), 0.5)
        << first.parts[i].name;
  }
}

// Slack spans of other lengths and widths come to rest too. Their relaxations used to end at
// the iteration limit still sloping (1e-6 to 6e-5: "did not converge"): joints let go of
// their stops and caught back at them step after step kept the steps short. Every one of
// these sags at rest, symmetric, with nothing passing through.
TEST(Physics, SlackSpansOfAnyLengthComeToRest) {
  struct Span {
    int hooks;
    double apart;
  };
  for (const Span& s : {Span{25, 605.5},
                        Span{30, 605.5},
                        Span{36, 605.5},
                        Span{25, 480},
                        Span{26, 480},
                        Span{28, 480},
                        Span{20, 300}}) {
    SCOPED_TRACE(fmt::format("{} hooks, {} mm apart", s.hooks, s.apart));
    const Design d = load_text(span_between_wall_hooks(s.hooks, s.apart));
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    const SolveResult r = solve(d.assembly);
    EXPECT_EQ(to_string(r.termination), "NO_TARGET") << r.summary();
    EXPECT_LE(r.equilibrium_residual, 1e-6) << r.summary();
    EXPECT_LE(r.max_penetration_mm, 0.5) << r.summary();
    Outcome o;
    o.stable = r.stable;
    o.summary = r.summary();
    for (const SolvedPart& p : r.parts) o.positions.push_back(p.frame.pos);
    expect_sags_between_wall_hooks(o, s.hooks);
  }
}

// ---- A hanger and the loads in its notches, by statics ---------------------------------------

// A wire hanger (its y-z plane) on a level rod, with S-hooks hung in its shoulder notches.
// `left` and `right` are the loads in hook3 (y < 0) and hook2 (y > 0): "" for none, "s" for an
// S-hook, "mug" for an S-hook carrying a mug.
std::string hanger_with_loads(const std::string& left, const std::string& right) {
  std::string s =
      "fabkit: hacks/1\nname: hanger\nenvironment:\n"
      "  - {name: bar, primitives: {rod: {type: rod, radius: 5, length: 300}}, "
      "frame: {pos: [0, 0, 1500], rot: [0, 90, 0]}}\nparts:\n  - {name: hanger, part: Hanger}\n";
  std::string connects = "connections:\n  - connect: [hanger.hook1, bar.rod]\n";
  auto load = [&](const std::string& what, const std::string& side, const std::string& notch) {
    if (what.empty()) return;
    s += "  - {name: s" + side + ", part: DoubleHook}\n";
    connects += "  - connect: [s" + side + ".hook1, hanger." + notch + "]\n";
    if (what == "mug") {
      s += "  - {name: mug" + side + ", part: Mug}\n";
      connects += "  - connect: [mug" + side + ".hook, s" + side + ".hook2]\n";
    }
  };
  load(left, "l", "hook3");
  load(right, "r", "hook2");
  return s + connects;
}

// Statics of a hanger: the rod can push on the top hook only along the normal through the
// hook's arc centre O, so at rest everything hanging from the rod has its centre of mass
// straight below O. A load hung in a notch hangs from the notch's lowest point (its wire arc's,
// over the part of the arc it can reach), straight above the load's own centre of mass, so it
// acts on the hanger as its weight there. With a the hanger's own centre of mass and b that
// point in the hanger's coordinates (from O), the hanger turns until m_h·a + m_load·b points
// down: it tilts by the angle between a and that sum — from the part's geometry and masses
// alone, compared with the solved pose.
TEST(Physics, LoadsInAHangersNotchTiltItByTheAngleStaticsGives) {
  const std::shared_ptr<Part> hanger_part = testing::make_part("Hanger");
  const Part& hanger = *hanger_part;
  auto primitive = [&](const std::string& name) -> const Primitive& {
    const PrimitiveId id = hanger.find_primitive(name);
    EXPECT_TRUE(id.valid()) << name;
    return hanger.primitive(id.valid() ? id : PrimitiveId{0});
  };
  // A hook's arc turns about its frame's x axis around the frame's origin, from θ = 0 to its
  // arc angle, at (0, −r sin θ, −r cos θ) in the hook's frame.
  const Vec3 top = primitive("hook1").frame.pos;
  // The notch's lowest reachable point when the hanger's rotation is `rot` (hanger coords).
  auto lowest_point = [&](const std::string& notch, const Mat3& rot) {
    const Primitive& p = primitive(notch);
    const Mat4 f = p.frame.matrix();
    Vec3 best = Vec3::Zero();
    double lowest = std::numeric_limits<double>::infinity();
    for (int i = 0; i <= 3200; ++i) {
      const double th = p.shape.arc_angle * i / 3200.0 * std::numbers::pi / 180.0;
      const Vec3 local =
          f.topLeftCorner<3, 3>() *
              Vec3(0, -p.shape.arc_radius * std::sin(th), -p.shape.arc_radius * std::cos(th)) +
          f.topRightCorner<3, 1>();
      const double z = (rot * local).z();
      if (z < lowest) {
        lowest = z;
        best = local;
      }
    }
    return best;
  };
  // Whether an S-hook may jam in its notch: only where loads pull the hanger two ways (two
  // mugs, or an S-hook across from a mug). A lone load's S-hook may come to rest at its turn's
  // limit (phi's range) without the stop carrying anything, and is checked by statics all the
  // same: where a relaxation ends, exactly at the stop or a thousandth of a degree off it,
  // says nothing about the weights.
  struct Case {
    std::string left, right;
    bool may_jam = false;
  };
  int checked_free = 0;
  for (const Case& c : {Case{"", ""},
                        Case{"s", ""},
                        Case{"mug", ""},
                        Case{"", "mug"},
                        Case{"mug", "mug", true},
                        Case{"s", "mug", true}}) {
    SCOPED_TRACE("left " + c.left + ", right " + c.right);
    const Design d = load_text(hanger_with_loads(c.left, c.right));
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    const SolveResult r = solve(d.assembly);
    EXPECT_TRUE(r.stable) << r.summary();
    const Assembly& a = d.assembly;
    const std::vector<Mat4> frames = a.part_frames(r.parameters);
    std::map<std::string, int> id;
    for (int i = 0; i < a.part_count(); ++i) id[a.label(PartId{i})] = i;
    auto world_com = [&](int i) {
      const Part& p = *a.node(PartId{i}).part;
      const Mat4& m = frames[static_cast<std::size_t>(i)];
      return Vec3(m.topLeftCorner<3, 3>() * p.center_of_mass + m.topRightCorner<3, 1>());
    };
    const Mat4& h = frames[static_cast<std::size_t>(id["hanger"])];
    const Mat3 rot = h.topLeftCorner<3, 3>();
    auto to_world = [&](const Vec3& local) { return Vec3(rot * local + h.topRightCorner<3, 1>()); };
    // The hanger's plane stays vertical: its normal is level.
    EXPECT_LT(std::abs((rot * Vec3::UnitX()).z()), 1e-3) << r.summary();
    // Each load: its mass, and its centre of mass straight below the notch's lowest point.
    const Vec3 a_local = hanger.center_of_mass - top;
    Vec3 w = hanger.mass * a_local;
    bool jammed = false;
    for (const auto& [side, notch] : {std::pair<std::string, std::string>{"l", "hook3"},
                                      std::pair<std::string, std::string>{"r", "hook2"}}) {
      if (!id.count("s" + side)) continue;
      double m = 0;
      Vec3 moment = Vec3::Zero();
      for (const std::string& name : {"s" + side, "mug" + side}) {
        if (!id.count(name)) continue;
        m += a.node(PartId{id[name]}).part->mass;
        moment += a.node(PartId{id[name]}).part->mass * world_com(id[name]);
      }
      // An S-hook turns in the notch only as far as its wire lets the two wires cross
      // (phi's range); at that limit it is jammed, not hanging free, and the wires carry a
      // torque: then neither its place nor the tilt follow from the weights alone.
      for (int i = 0; i < a.parameter_count(); ++i) {
        const ParamInfo& info = a.parameters()[static_cast<std::size_t>(i)];
        if (a.label(info.part, info.primitive) != "s" + side + ".hook1") continue;
        const double v = r.parameters[static_cast<std::size_t>(i)];
        if (c.may_jam && info.spec.name == "phi" &&
            (v < info.spec.lo + 1e-6 || v > info.spec.hi - 1e-6)) {
          jammed = true;
        }
      }
      const Vec3 hangs_from = lowest_point(notch, rot);
      if (!jammed) {
        EXPECT_LT((moment / m - to_world(hangs_from)).head<2>().norm(), 0.5) << side << "\n"
                                                                             << r.summary();
      }
      w += m * (hangs_from - top);
    }
    // The tilt statics gives, and the solved one: from straight down to the hanger's own
    // centre of mass, seen from O about the hanger's x axis (its plane's normal).
    const double predicted =
        std::atan2(a_local.cross(w).x(), a_local.dot(w)) * 180.0 / std::numbers::pi;
    const Vec3 down_local = rot.transpose() * Vec3(0, 0, -1);
    const double solved = std::atan2(a_local.cross(down_local).x(), a_local.dot(down_local)) *
                          180.0 / std::numbers::pi;
    if (!jammed) {
      EXPECT_NEAR(solved, predicted, 0.5) << r.summary();
    }
    // Everything hanging from the rod: its centre of mass is straight below O.
    Vec3 moment = Vec3::Zero();
    double total = 0;
    for (int i = 0; i < a.part_count(); ++i) {
      if (a.node(PartId{i}).environment) continue;
      const double m = a.node(PartId{i}).part->mass;
      moment += m * world_com(i);
      total += m;
    }
    EXPECT_LT((moment / total - to_world(top)).head<2>().norm(), 0.5) << r.summary();
    if (c.left == c.right) {
      EXPECT_NEAR(solved, 0.0, 0.5) << "no loads, or equal ones, keep it level";
    }
    if (c.right == "mug" && c.left != "mug") {
      EXPECT_GT(std::abs(solved), 5.0) << "a mug tilts it";
    }
    checked_free += jammed ? 0 : 1;
  }
  EXPECT_GE(checked_free, 4);  // two mugs, or an S-hook across from a mug, jam the S-hooks
}

// ---- Mirror images ----------------------------------------------------------------------------

// Reflection through the world's y-z plane (x → −x), applied to a frame: the mirror image of
// whatever is placed at it, reflected through its own y-z plane.
Frame mirrored(const Frame& f) {
  const Mat4 m = Eigen::Vector4d(-1, 1, 1, 1).asDiagonal();
  return Frame::from_matrix(m * f.matrix() * m);
}

std::string mirrored_design(const std::string& yaml) {
  YAML::Node root = YAML::Load(yaml);
  for (YAML::Node e : root["environment"]) e["frame"] = frame_node(mirrored(frame_of(e["frame"])));
  if (root["target"])
    root["target"]["frame"] = frame_node(mirrored(frame_of(root["target"]["frame"])));
  return emit(root);
}

// A design and its mirror image rest as mirror images of each other: the same verdict and
// potential, every part at the same height and at the mirrored side. S-hooks are flat, so
// the mirrored design is built of the same parts. (Its interlocks keep their alignments here:
// the exact mirror image turns each the other way, AMirroredChainRestsAsTheMirrorImageOfTheChain;
// a chain of flat hooks hanging in its own plane rests with its parts at the same places
// either way.)
TEST(Physics, AMirroredDesignRestsAsTheMirrorImage) {
  // Chains between two rods, built from either end: mirrored, the chain starts from the rod on
  // the other side; and between rods at different heights, whose mirror image the closure
  // search used to leave open (a 1.7 mm gap after 16 starts; issue 9, item 4).
  for (const std::string& yaml :
       {chain_between_rods(10, true),
        chain_between_rods(11, false),
        chain_between_rods(11, true, Vec3(-200, 0, 500), Vec3(150, 0, 620))}) {
    const Outcome a = solve_text(yaml);
    const Outcome b = solve_text(mirrored_design(yaml));
    EXPECT_TRUE(a.stable) << a.summary;
    EXPECT_EQ(a.stable, b.stable) << a.summary << b.summary;
    EXPECT_NEAR(a.energy / a.mass, b.energy / b.mass, 0.05) << a.summary << b.summary;
    ASSERT_EQ(a.positions.size(), b.positions.size());
    for (std::size_t i = 0; i < a.positions.size(); ++i) {
      EXPECT_NEAR(a.positions[i].z(), b.positions[i].z(), 1.0) << "part " << i;
      EXPECT_NEAR(a.positions[i].x(), -b.positions[i].x(), 1.0) << "part " << i;
    }
  }
}

// A shower curtain rod through two S-hooks hung from the rods `first` and `second` of
// `environments` (YAML list items).
std::string bar_on_two_hooks(const std::string& environments,
                             const std::string& first,
                             const std::string& second) {
  return "fabkit: hacks/1\nname: bar on two hooks\nenvironment:\n" + environments +
         "parts:\n  - {name: s1, part: DoubleHook}\n  - {name: s2, part: DoubleHook}\n"
         "  - {name: bar, part: ShowerCurtainRod}\nconnections:\n"
         "  - connect: [s1.hook1, " +
         first +
         ".rod]\n  - connect: [bar.rod, s1.hook2]\n"
         "  - connect: [s2.hook1, " +
         second + ".rod]\n  - connect: [s2.hook2, bar.rod]\n";
}

// Statics of a curtain rod resting in two S-hooks: each hook carries part of the weight
// straight below where it hangs, so the rod's axis is level and its centre of mass between the
// hooks. The rod may slide through the hooks at no cost (a neutral direction, which gets no
// step) as long as its centre of mass stays between them: with the hooks' swings α₁, α₂, their
// spacing d and the slide s from the middle, the potential near the level pose is
// c·(α₁² + α₂²) + (m·g·L/2d)·(α₂² − α₁²)·s, a minimum while |s| < 2c·d/(m·g·L) — the centre of
// mass between the hooks (c = m·g·L/4 for hooks of length L carrying the rod).
void expect_rests_level_between_hooks(const Design& d, const SolveResult& r) {
  EXPECT_TRUE(r.stable) << r.summary();
  EXPECT_LT(r.equilibrium_residual, 1e-6) << r.summary();
  EXPECT_FALSE(r.neutral_directions.empty()) << r.summary();
  EXPECT_LE(r.max_penetration_mm, 0.5) << r.summary();
  std::map<std::string, Mat4> at;
  for (const SolvedPart& p : r.parts) at[p.name] = p.frame.matrix();
  const Part& bar = *d.assembly.node(PartId{d.assembly.part_count() - 1}).part;
  ASSERT_EQ(d.assembly.label(PartId{d.assembly.part_count() - 1}), "bar");
  const Mat4 rod = at["bar"] * bar.primitive(bar.find_primitive("rod")).frame.matrix();
  // The rod's axis is its frame's z axis (a rod primitive runs along z).
  const Vec3 axis = rod.block<3, 1>(0, 2);
  EXPECT_LT(std::abs(axis.z()), std::sin(0.1 * std::numbers::pi / 180)) << r.summary();
  const Vec3 com = (at["bar"] * bar.center_of_mass.homogeneous()).head<3>();
  const auto [left, right] = std::minmax(at["s1"](0, 3), at["s2"](0, 3));
  EXPECT_GT(com.x(), left) << r.summary();
  EXPECT_LT(com.x(), right) << r.summary();
}

// Two S-hooks hung 300 mm apart, each from its own short rod.
TEST(Physics, ABarInTwoHooksApartRestsLevel) {
  const Design d = load_text(
      bar_on_two_hooks("  - {name: left, primitives: {rod: {type: rod, radius: 6, length: 30}}, "
                       "frame: {pos: [-150, 0, 1200], rot: [0, 90, 0]}}\n"
                       "  - {name: right, primitives: {rod: {type: rod, radius: 6, length: 30}}, "
                       "frame: {pos: [150, 0, 1200], rot: [0, 90, 0]}}\n",
                       "left",
                       "right"));
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  expect_rests_level_between_hooks(d, solve(d.assembly));
}

// `text` verified and solved with `seed` (both draw from it), then `check`ed.
void solve_with_seed(const std::string& text,
                     std::uint64_t seed,
                     const std::function<void(const Design&, const SolveResult&)>& check) {
  DesignOptions options;
  options.verify.seed = seed;
  const Design d = load_design_text(text, "bar.yaml", PartsLibrary::builtin(), options);
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  SolveOptions solve_options;
  solve_options.seed = seed;
  check(d, solve(d.assembly, solve_options));
}

// The curtain rod through two S-hooks on one rail `length` mm long, verified and solved with
// `seed`, then `check`ed.
void solve_bar_on_one_rail(int length,
                           std::uint64_t seed,
                           const std::function<void(const Design&, const SolveResult&)>& check) {
  SCOPED_TRACE(fmt::format("rail {} mm, seed {}", length, seed));
  const std::string text = bar_on_two_hooks(
      fmt::format("  - {{name: rail, primitives: {{rod: {{type: rod, radius: 6, length: {}}}}}, "
                  "frame: {{pos: [0, 0, 1200], rot: [0, 90, 0]}}}}\n",
                  length),
      "rail",
      "rail");
  solve_with_seed(text, seed, check);
}

// Both S-hooks on one rail, where the verification hangs them side by side (2.4 mm apart): a
// rod resting on two points that close is a seesaw on one, and from there it tips and slides
// out of them. The hooks may slide along the rail at no cost, and the solve, finding that way
// of hanging it does not hold, spreads them along the rail (twins on one primitive, other
// closings: docs/hacks.md), where the rod rests level. Issue 9 found this bar "sliding 172 mm
// along a direction gravity does not act on" and declared falling apart. Whatever the seed.
TEST(Physics, ABarThroughTwoHooksOnOneRailRestsLevel) {
  for (const std::uint64_t seed : {1, 2}) {
    solve_bar_on_one_rail(900, seed, [](const Design& d, const SolveResult& r) {
      expect_rests_level_between_hooks(d, r);
      // Spread apart: a seesaw no more.
      std::map<std::string, Mat4> at;
      for (const SolvedPart& p : r.parts) at[p.name] = p.frame.matrix();
      EXPECT_GT(std::abs(at["s1"](0, 3) - at["s2"](0, 3)), 100) << r.summary();
    });
  }
}

// Rails shorter than the bar (351 mm between its end caps), where the hooks spread along the
// rail stand closer together than the closing left them on the bar: hooks leaning towards each
// other let the bar slide through them onto its end, and from there out of one (150, 250 and
// 400 mm rails: "falls apart" or "did not converge" with seed 1 before the bar was centred
// between them). Statics as above, whatever the seed.
TEST(Physics, ABarThroughTwoHooksOnRailsShorterThanItRestsLevel) {
  for (const int length : {150, 250, 400}) {
    for (const std::uint64_t seed : {1, 2}) {
      solve_bar_on_one_rail(length, seed, expect_rests_level_between_hooks);
    }
  }
}

// The curtain rod through two S-hooks on a 400 mm rail, with the rod as the target at the level
// rest the solve finds without one: every candidate of step 1 had the hooks side by side (a
// seesaw) and fell apart, the rod 168 mm away and tilted 83° ("falls apart", seeds 1 and 2).
// A group whose candidates all fall apart is tried as a free group is: it rests level, on its
// target. With the goal moved along the rail (40 mm one way, 60 mm the other) it rests level
// on its goal: sliding there costs nothing (it rested where the spread put it, 40 and 60 mm
// from the goal, until the rest found was pulled towards the target).
TEST(Physics, ABarThroughTwoHooksAsTheTargetRestsLevel) {
  const std::string free_text = bar_on_two_hooks(
      "  - {name: rail, primitives: {rod: {type: rod, radius: 6, length: 400}}, "
      "frame: {pos: [0, 0, 1200], rot: [0, 90, 0]}}\n",
      "rail",
      "rail");
  const Design free = load_text(free_text);
  ASSERT_TRUE(free.feasible()) << free.diagnostics.format();
  const SolveResult rest = solve(free.assembly);
  ASSERT_TRUE(rest.stable) << rest.summary();
  Mat4 rod = Mat4::Identity();
  for (const SolvedPart& p : rest.parts) {
    if (p.name != "bar") continue;
    const Part& bar = *free.assembly.node(PartId{free.assembly.part_count() - 1}).part;
    rod = p.frame.matrix() * bar.primitive(bar.find_primitive("rod")).frame.matrix();
  }
  for (const double along : {0.0, 40.0, -60.0}) {
    Frame goal = Frame::from_matrix(rod);
    goal.pos.x() += along;
    std::string text = free_text;
    text.replace(text.find("  - {name: bar, part: ShowerCurtainRod}\n"),
                 std::string("  - {name: bar, part: ShowerCurtainRod}\n").size(),
                 "");
    text.replace(text.find("connections:"),
                 std::string("connections:").size(),
                 "target: {name: bar, part: ShowerCurtainRod, primitive: rod, frame: " +
                     flow_frame(goal) + "}\nconnections:");
    for (const std::uint64_t seed : {1, 2}) {
      if (along < 0 && seed > 1) continue;  // one seed is enough the other way
      SCOPED_TRACE(fmt::format("goal {} mm along the rail, seed {}", along, seed));
      solve_with_seed(text, seed, [&](const Design& d, const SolveResult& r) {
        expect_at_rest(r);
        EXPECT_LT(r.target.tilt_deg, 0.1) << r.summary();
        // Level, on the goal.
        EXPECT_LT(r.target.position_mm, 0.5) << r.summary();
        // Step 1's reported pose is the one that rest was relaxed from, the hooks spread along
        // the rail near where they rest — not a candidate of step 1 (the hooks side by side).
        const std::vector<Mat4> before = d.assembly.part_frames(r.step1_parameters);
        for (int i = 0; i < d.assembly.part_count(); ++i) {
          const std::string name = d.assembly.label(PartId{i});
          if (name != "s1" && name != "s2") continue;
          for (const SolvedPart& p : r.parts) {
            if (p.name != name) continue;
            const double moved =
                (before[static_cast<std::size_t>(i)].topRightCorner<3, 1>() - p.frame.pos).norm();
            EXPECT_LT(moved, 20.0) << name << "\n" << r.summary();
          }
        }
      });
    }
  }
}

// Two S-hooks on two short rods 133 mm apart (each 30 mm long), where the closing left them
// holding the bar side by side: they lean together and the bar slid out of them
// ("falls apart", also with the rods 110 mm apart). Centred between them it rests level.
TEST(Physics, ABarInTwoHooksOnShortRodsCloseTogetherRestsLevel) {
  for (const int apart : {110, 133}) {
    SCOPED_TRACE(apart);
    const Design d = load_text(bar_on_two_hooks(
        fmt::format("  - {{name: left, primitives: {{rod: {{type: rod, radius: 6, length: 30}}}}, "
                    "frame: {{pos: [{}, 0, 1200], rot: [0, 90, 0]}}}}\n"
                    "  - {{name: right, primitives: {{rod: {{type: rod, radius: 6, length: 30}}}}, "
                    "frame: {{pos: [{}, 0, 1200], rot: [0, 90, 0]}}}}\n",
                    -apart / 2.0,
                    apart / 2.0),
        "left",
        "right"));
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    expect_rests_level_between_hooks(d, solve(d.assembly));
  }
}

// The two hooks are twins (the same part hung the same way from the same rail): their random
// draws are handed out by where they are, not by their names or the order of the connects, so
// the rod and the hooks rest in the same places when the hooks swap names.
TEST(Physics, TwinHooksSwappedByNameRestTheSame) {
  const std::string rail =
      "  - {name: rail, primitives: {rod: {type: rod, radius: 6, length: 900}}, "
      "frame: {pos: [0, 0, 1200], rot: [0, 90, 0]}}\n";
  std::string swapped = bar_on_two_hooks(rail, "rail", "rail");
  for (auto [from, to] : {std::pair{"s1", "s@"}, std::pair{"s2", "s1"}, std::pair{"s@", "s2"}}) {
    for (std::size_t at = swapped.find(from); at != std::string::npos; at = swapped.find(from)) {
      swapped.replace(at, 2, to);
    }
  }
  const Outcome a = solve_text(bar_on_two_hooks(rail, "rail", "rail"));
  const Outcome b = solve_text(swapped);
  ASSERT_TRUE(a.stable) << a.summary;
  ASSERT_TRUE(b.stable) << b.summary;
  EXPECT_LT((a.by_name.at("bar") - b.by_name.at("bar")).norm(), 1e-6) << a.summary << b.summary;
  // The two hooks are interchangeable: the same two places, whichever name each has there.
  const Vec3 a1 = a.by_name.at("s1"), a2 = a.by_name.at("s2");
  const Vec3 b1 = b.by_name.at("s1"), b2 = b.by_name.at("s2");
  EXPECT_LT(std::min(std::max((a1 - b1).norm(), (a2 - b2).norm()),
                     std::max((a1 - b2).norm(), (a2 - b1).norm())),
            1e-6)
      << a.summary << b.summary;
  EXPECT_GT((a1 - a2).norm(), 100) << a.summary;
}

// A hook hung on a rail that runs inside a sleeve as long as the rail: the hook's wire lies on
// the rail's surface (2.5 mm from its axis) for every value of its connection, inside the
// sleeve's 20 mm, so every closure passes the hook through the sleeve — the design is
// infeasible (non-penetration is one of its constraints). fabkit says so, names the two parts
// and the depth, and still reports the pose; with the sleeve 100 mm above the rail the same
// hook hangs free and holds.
std::string hook_on_a_sleeved_rail(double sleeve_z) {
  return fmt::format(R"(fabkit: hacks/1
name: sleeved rail
environment:
  - {{name: rail, primitives: {{rod: {{type: rod, radius: 2.5, length: 300}}}}, frame: {{pos: [0, 0, 500], rot: [90, 0, 0]}}}}
  - {{name: sleeve, primitives: {{rod: {{type: rod, radius: 20, length: 300}}}}, frame: {{pos: [0, 0, {}], rot: [90, 0, 0]}}}}
parts:
  - {{name: hook, part: DoubleHookMedium}}
connections:
  - connect: [hook.hook1, rail.rod]
)",
                     sleeve_z);
}

TEST(Physics, AHookThatCanOnlyHangThroughASleeveIsInfeasible) {
  const Design sleeved = load_text(hook_on_a_sleeved_rail(500));
  ASSERT_TRUE(sleeved.feasible()) << sleeved.diagnostics.format();
  const SolveResult r = solve(sleeved.assembly);
  EXPECT_FALSE(r.stable) << r.summary();
  EXPECT_FALSE(r.feasible) << r.summary();
  EXPECT_EQ(r.termination, Termination::kInfeasible) << r.summary();
  // Deeper than the wire's distance to the sleeve's surface less a wire (about 15 mm).
  EXPECT_GT(r.max_penetration_mm, 10) << r.summary();
  EXPECT_NE(r.message.find("sleeve and hook pass through each other"), std::string::npos)
      << r.message;
  EXPECT_NE(r.message.find("a search, not a proof"), std::string::npos) << r.message;
  EXPECT_EQ(r.parts.size(), 3u);  // the pose is still reported

  const Design apart = load_text(hook_on_a_sleeved_rail(600));
  ASSERT_TRUE(apart.feasible()) << apart.diagnostics.format();
  const SolveResult free = solve(apart.assembly);
  EXPECT_TRUE(free.stable) << free.summary();
  EXPECT_TRUE(free.feasible) << free.summary();
  EXPECT_LE(free.max_penetration_mm, 0.5) << free.summary();
}

}  // namespace
}  // namespace fabkit::hacks

// Solving (issue 3): the paper's gallery reproduced, equilibrium invariants, failing designs,
// golden results and determinism.
#include "fabkit/hacks/solve.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../src/contacts.h"
#include "../src/solve_internal.h"
#include "fabkit/core/export_formats.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/hacks/solution_export.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::load_example;
using testing::load_text;

struct Solved {
  Design design;
  SolveResult result;
};

Solved solve_example(const std::string& name) {
  Solved s{load_example(name), {}};
  EXPECT_TRUE(s.design.feasible()) << s.design.diagnostics.format();
  s.result = solve(s.design.assembly);
  return s;
}

// Angle of a part's z axis from the vertical, degrees.
double tilt_deg(const SolveResult& r, const std::string& part) {
  for (const SolvedPart& p : r.parts) {
    if (p.name != part) continue;
    const Vec3 z = p.frame.matrix().topLeftCorner<3, 3>() * Vec3::UnitZ();
    return std::acos(std::clamp(z.z(), -1.0, 1.0)) * kRadToDeg;
  }
  ADD_FAILURE() << "no part " << part;
  return 0;
}

using testing::kGalleryExamples;

class GalleryTest : public ::testing::TestWithParam<const char*> {};

// Gallery designs whose paper pose passes parts through each other and for which the
// contact-constrained relaxation does not yet find a rest state (docs/gallery.md): the diaper
// caddy's target is inside the seat back. It must not be reported stable. (The reading nook,
// whose rings passed through each other when solved in its file's order of connects, rests
// clear of them in the canonical order every design is now solved in.)
bool not_yet_at_rest_with_contacts(const std::string& name) {
  return name == "diaper_caddy";
}

// Every design the paper built solves and closes every connection; a stable one is at an
// equilibrium and passes through nothing.
TEST_P(GalleryTest, SolvesStableAtEquilibrium) {
  const Solved s = solve_example(GetParam());
  const SolveResult& r = s.result;
  // Where every rest found passes parts through each other, the design is infeasible as
  // found (non-penetration is one of its constraints), and the pose is still reported.
  EXPECT_EQ(r.feasible, !not_yet_at_rest_with_contacts(GetParam())) << r.summary();
  EXPECT_EQ(r.termination == Termination::kInfeasible, !r.feasible) << r.summary();
  EXPECT_TRUE(r.slips.empty());
  EXPECT_LT(r.max_gap_mm, 1e-6) << r.summary();
  EXPECT_LT(r.max_gap_deg, 1e-6) << r.summary();
  if (r.stable) {
    EXPECT_LE(r.max_penetration_mm, 0.5) << r.summary();
    for (const PartContact& c : r.contacts) EXPECT_GE(c.distance_mm, -0.5) << r.summary();
  }
  if (not_yet_at_rest_with_contacts(GetParam())) {
    EXPECT_FALSE(r.stable) << r.summary();
  } else {
    EXPECT_TRUE(r.stable) << r.summary();
    EXPECT_LT(r.equilibrium_residual, 1e-6) << r.summary();
  }
  EXPECT_EQ(r.parts.size(), static_cast<std::size_t>(s.design.assembly.part_count()));
  // Bounded parameters stay in bounds; periodic ones are wrapped.
  for (int i = 0; i < s.design.assembly.parameter_count(); ++i) {
    const ParamSpec& p = s.design.assembly.parameters()[static_cast<std::size_t>(i)].spec;
    const double v = r.parameters[static_cast<std::size_t>(i)];
    if (p.tag == ParamTag::kUnbounded) {
      EXPECT_GE(v, 0);
      EXPECT_LT(v, 360);
    } else {
      EXPECT_GE(v, p.lo - 1e-9);
      EXPECT_LE(v, p.hi + 1e-9);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Paper,
                         GalleryTest,
                         ::testing::ValuesIn(kGalleryExamples),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param);
                         });

// The three designs the issue names end within 5 mm and 5° of their end_with frames.
TEST(Solve, ReachesTargetsAfterRelaxation) {
  for (const char* name : {"toothbrush_holder", "charger_holder", "bird_feeder"}) {
    SCOPED_TRACE(name);
    const SolveResult r = solve_example(name).result;
    EXPECT_LT(r.target.position_mm, 5.0) << r.summary();
    EXPECT_LT(r.target.rotation_deg, 5.0) << r.summary();
  }
}

// Paper Fig. 9: one eye hook lets the basket swing far; two hold it much nearer level. (The
// hooks slide on the basket's side rods without friction, so with two the basket still turns
// about the line through them until its centre of mass is below it, the hooks at the rods'
// ends: the photo's level basket is held by friction, which the model has only for resting
// surfaces; docs/hacks.md.)
TEST(Solve, Figure9OneEyehookTiltsTwoKeepLevel) {
  const SolveResult one = solve_example("soap_bottle_one_eyehook").result;
  const SolveResult two = solve_example("soap_bottle_holder").result;
  EXPECT_TRUE(one.stable);
  EXPECT_TRUE(two.stable);
  EXPECT_GT(tilt_deg(one, "basket"), 30.0);
  EXPECT_LT(tilt_deg(two, "basket"), 15.0);
  EXPECT_GT(tilt_deg(one, "basket"), tilt_deg(two, "basket") + 20.0);
}

// For a part hanging from one free pivot (a tree connection whose parameters are free), the
// centre of mass of everything it carries lies vertically below each axis the pivot lets it
// turn about: turning a little about the axis does not raise or lower it. Measured from part
// frames alone: lever = |d(com height)/dq| / |dω/dq|, the horizontal distance (mm) between
// the centre of mass and the turning axis.
TEST(Solve, HangingSubtreesBalanceUnderTheirPivot) {
  int checked = 0;
  for (const char* name : {"mug_hanger", "demo", "clip_light_xs", "clip_light_l"}) {
    SCOPED_TRACE(name);
    const Solved s = solve_example(name);
    const Assembly& a = s.design.assembly;
    const std::vector<double>& x = s.result.parameters;
    // Centre of mass of everything hanging below connection c, for parameters y.
    auto subtree_com = [&](std::size_t c, const std::vector<double>& y) {
      const std::vector<Mat4> frames = a.part_frames(y);
      double mass = 0;
      Vec3 moment = Vec3::Zero();
      for (int p = 0; p < a.part_count(); ++p) {
        PartId q{p};
        bool below = false;
        while (a.parent(q).valid()) {
          if (a.parent(q).value == static_cast<int>(c)) {
            below = true;
            break;
          }
          q = a.connection(a.parent(q)).first.part;
        }
        if (!below) continue;
        const Part& part = *a.node(PartId{p}).part;
        const Mat4& f = frames[static_cast<std::size_t>(p)];
        moment +=
            part.mass * (f.topLeftCorner<3, 3>() * part.center_of_mass + f.topRightCorner<3, 1>());
        mass += part.mass;
      }
      return Vec3(moment / mass);
    };
    for (std::size_t c = 0; c < a.connections().size(); ++c) {
      const Connection& conn = a.connections()[c];
      if (conn.closes_cycle) continue;
      const std::size_t child = conn.second.part.index();
      const Vec3 com = subtree_com(c, x);
      const Mat3 r0 = a.part_frames(x)[child].topLeftCorner<3, 3>();
      for (const Connector* k : {&conn.first, &conn.second}) {
        for (std::size_t i = 0; i < k->params.size(); ++i) {
          const ParamSpec& p = k->params[i];
          const std::size_t index = static_cast<std::size_t>(k->offset) + i;
          // A free turning parameter, off its bounds.
          if (p.fixed_under_physics || p.constant) continue;
          if (p.tag != ParamTag::kUnbounded && (x[index] < p.lo + 1e-6 || x[index] > p.hi - 1e-6)) {
            continue;
          }
          std::vector<double> y = x;
          const double h = 1e-6;
          y[index] += h;
          const Mat3 dr = a.part_frames(y)[child].topLeftCorner<3, 3>() * r0.transpose();
          const double turn =
              Vec3(dr(2, 1) - dr(1, 2), dr(0, 2) - dr(2, 0), dr(1, 0) - dr(0, 1)).norm() / 2;
          if (turn < 1e-3 * h) continue;  // a sliding parameter
          const double lever = std::abs(subtree_com(c, y).z() - com.z()) / turn;
          EXPECT_LT(lever, 1.0) << a.label(conn.second.part) << " hangs " << lever
                                << " mm off the axis of " << a.label(k->part, k->primitive) << " "
                                << p.name;
          ++checked;
        }
      }
    }
  }
  EXPECT_GE(checked, 10);
}

constexpr const char* kTiltedRod = R"(fabkit: hacks/1
name: hook on a tilted rod
environment:
  - name: bar
    primitives:
      rod: {type: rod, radius: 5, length: 200}
    frame: {pos: [0, 0, 500], rot: [70, 0, 90]}   # axis (0.94, 0, 0.34): 20° up along x
parts:
  - {name: shook, part: DoubleHookMedium}
target: {name: mug, part: Mug, primitive: hook, frame: {pos: [0, 0, 400], rot: [0, 0, 0]}}
connections:
  - connect: [shook.hook1, bar.rod]
  - connect: [mug.hook, shook.hook2]
)";

// A hook on a rod tilted 20° slides down and off the rod's open low end.
TEST(Solve, HookSlidesOffATiltedOpenRod) {
  const Design d = load_text(kTiltedRod);
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const SolveResult r = solve(d.assembly);
  EXPECT_TRUE(r.feasible);
  EXPECT_FALSE(r.stable) << r.summary();
  ASSERT_EQ(r.slips.size(), 1u) << r.summary();
  EXPECT_NE(r.slips[0].message.find("shook.hook1 slides off the open end of bar.rod"),
            std::string::npos)
      << r.slips[0].message;
  // The same rod closed at its ends holds the hook at the low end: stable.
  std::string closed = kTiltedRod;
  closed.replace(
      closed.find("length: 200}"), 12, "length: 200, is_open: false, open_for_connect: true}");
  const SolveResult held = solve(load_text(closed).assembly);
  EXPECT_TRUE(held.stable) << held.summary();
}

// A hook free to slide on a level rod is neutral: relaxation must not drive it to an end
// (the reference's Newton step runs it to t = 1 and reports a fall).
TEST(Solve, NeutralSlidingStaysPut) {
  std::string level = kTiltedRod;
  level.replace(level.find("rot: [70, 0, 90]"), 16, "rot: [90, 0, 90]");
  const Design d = load_text(level);
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const SolveResult r = solve(d.assembly);
  EXPECT_TRUE(r.stable) << r.summary();
  // The rod's t (parameter 0) stays about where step 1 left it (within 2 mm of the 200 mm rod),
  // away from both ends.
  const double t1 = r.step1_parameters[0];
  const double t2 = r.parameters[0];
  EXPECT_NEAR(t2, t1, 0.01);
  EXPECT_GT(t2, 0.01);
  EXPECT_LT(t2, 0.99);
}

// A ring hung on an open hook whose opening points down slides off the hook's end.
TEST(Solve, RingSlidesOffAHookOpeningDown) {
  // A 180° hook arc starts at its bottom and sweeps up one side to its tip. Turned over by
  // 200° about its axis, the arc ends 20° before the lowest point of its circle: the opening
  // faces down and nothing holds the ring.
  const Design d = load_text(R"(fabkit: hacks/1
name: ring on a downward hook
environment:
  - name: wall
    primitives:
      hook: {type: hook, arc_radius: 25, arc_angle: 180, thickness: 2.5}
    frame: {pos: [0, 0, 1000], rot: [200, 0, 90]}
parts: []
target: {name: ring, part: RingXS, frame: {pos: [0, 0, 950], rot: [0, 90, 0]}}
connections:
  - connect: [ring.ring, wall.hook]
)");
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const SolveResult r = solve(d.assembly);
  EXPECT_FALSE(r.stable) << r.summary();
  ASSERT_FALSE(r.slips.empty());
  EXPECT_NE(r.slips[0].message.find("ring.ring slides off the open end of wall.hook"),
            std::string::npos)
      << r.slips[0].message;
  // Hung the right way up, the same ring settles at the bottom of the hook.
  const Design up = load_text(R"(fabkit: hacks/1
name: ring on an upward hook
environment:
  - name: wall
    primitives:
      hook: {type: hook, arc_radius: 25, arc_angle: 180, thickness: 2.5}
    frame: {pos: [0, 0, 1000], rot: [0, 0, 90]}
parts: []
target: {name: ring, part: RingXS, frame: {pos: [0, 0, 950], rot: [0, 90, 0]}}
connections:
  - connect: [ring.ring, wall.hook]
)");
  const SolveResult ok = solve(up.assembly);
  EXPECT_TRUE(ok.stable) << ok.summary();
}

// ---- golden results -----------------------------------------------------------------------

std::filesystem::path golden_path(const std::string& name) {
  return std::filesystem::path(FABKIT_SOURCE_DIR) / "hacks" / "tests" / "golden" /
         (name + ".result.json");
}

// Per-field tolerances of the golden comparison. Where the potential is flat (a hook free to
// slide on a level rod) the relaxed pose depends on round-off along the way: positions and
// angles get 0.5 mm / 0.5°, which catches real changes but not those. Connector parameters are
// compared in their own units (t as a fraction of the primitive's length, angles in degrees);
// gaps and residuals only have to stay at equilibrium quality (1e-6), whatever the golden says
// (or, for a design the gallery test lists as not yet at rest, no worse than the golden).
struct GoldenTolerance {
  double mm = 0.5;
  double deg = 0.5;
  double fraction = 0.005;
  double quality = 1e-6;
};

bool is_angle_parameter(const std::string& name) {
  return name != "t" && name != "t1" && name != "t2";
}

// |a - b| with both read as angles (degrees), so 0 and 360 are the same.
double angle_distance(double a, double b) {
  const double d = std::fmod(std::abs(a - b), 360.0);
  return std::min(d, 360.0 - d);
}

void expect_json_near(const nlohmann::json& a,
                      const nlohmann::json& b,
                      const GoldenTolerance& tol,
                      const std::string& where,
                      const std::string& field = "",
                      const nlohmann::json* owner = nullptr) {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>();
    const double y = b.get<double>();
    if (field == "max_connection_gap_mm" || field == "max_connection_gap_deg" ||
        field == "equilibrium_residual") {
      // At equilibrium quality, or (a design not yet at rest) no worse than the golden.
      EXPECT_LE(x, std::max(tol.quality, 2 * y)) << where << " (golden " << y << ")";
    } else if (field == "rot" || field == "rot_error_deg") {
      EXPECT_LE(angle_distance(x, y), tol.deg) << where << ": " << x << " vs " << y;
    } else if (field == "value" && owner && owner->contains("name")) {
      const std::string name = owner->at("name").get<std::string>();
      if (is_angle_parameter(name)) {
        EXPECT_LE(angle_distance(x, y), tol.deg)
            << where << " (" << name << "): " << x << " vs " << y;
      } else {
        EXPECT_NEAR(x, y, tol.fraction) << where << " (" << name << ")";
      }
    } else if (field == "min" || field == "max") {
      EXPECT_NEAR(x, y, 1e-9) << where;
    } else {
      EXPECT_NEAR(x, y, tol.mm) << where;
    }
    return;
  }
  ASSERT_EQ(a.type(), b.type()) << where;
  if (a.is_object()) {
    ASSERT_EQ(a.size(), b.size()) << where;
    for (auto it = a.begin(); it != a.end(); ++it) {
      if (it.key() == "timings_ms" || it.key() == "notes") continue;  // clocks and prose
      ASSERT_TRUE(b.contains(it.key())) << where << "." << it.key();
      if (it.key() == "neutral_directions") {
        // Where several motions are free, any basis of them is as right as another (which
        // one an eigensolver returns follows round-off): only how many there are is physics.
        EXPECT_EQ(it.value().size(), b.at(it.key()).size()) << where << ".neutral_directions";
        continue;
      }
      expect_json_near(it.value(), b.at(it.key()), tol, where + "." + it.key(), it.key(), &a);
    }
  } else if (a.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << where;
    for (std::size_t i = 0; i < a.size(); ++i) {
      // Elements of a numeric array (pos, rot) keep the array's field name.
      expect_json_near(a[i], b[i], tol, where + "[" + std::to_string(i) + "]", field, owner);
    }
  } else {
    EXPECT_EQ(a, b) << where;
  }
}

class GoldenTest : public ::testing::TestWithParam<const char*> {};

TEST_P(GoldenTest, ResultMatchesGolden) {
  const Solved s = solve_example(GetParam());
  const std::string text = result_json(s.design.assembly, s.result, s.design.name);
  const std::filesystem::path path = golden_path(GetParam());
  if (std::getenv("FABKIT_UPDATE_GOLDEN")) {
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path) << text;
    GTEST_SKIP() << "wrote " << path;
  }
  std::ifstream in(path);
  ASSERT_TRUE(in) << "missing golden file " << path << " (run with FABKIT_UPDATE_GOLDEN=1)";
  const nlohmann::json expected = nlohmann::json::parse(in);
  expect_json_near(nlohmann::json::parse(text), expected, GoldenTolerance{}, GetParam());
}

INSTANTIATE_TEST_SUITE_P(Paper,
                         GoldenTest,
                         ::testing::ValuesIn(kGalleryExamples),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param);
                         });

// The solvers' twist-based Jacobian equals automatic differentiation through every frame.
TEST(Solve, AnalyticJacobianMatchesAutomaticDifferentiation) {
  for (const char* name : kGalleryExamples) {
    SCOPED_TRACE(name);
    const Design d = load_example(name);
    ASSERT_TRUE(d.feasible());
    // At the verified configuration and at a perturbed one.
    std::vector<double> x = d.assembly.values();
    EXPECT_LT(detail::jacobian_mismatch(d.assembly, x, false), 1e-9);
    EXPECT_LT(detail::jacobian_mismatch(d.assembly, x, true), 1e-9);
    for (std::size_t i = 0; i < x.size(); ++i)
      x[i] += 0.01 * std::sin(3.0 * static_cast<double>(i));
    EXPECT_LT(detail::jacobian_mismatch(d.assembly, x, false), 1e-9);
    EXPECT_LT(detail::jacobian_mismatch(d.assembly, x, true), 1e-9);
  }
}

// Same input, same output (seeded restarts, no clocks in the result).
TEST(Solve, Deterministic) {
  for (const char* name : {"bird_feeder", "toothbrush_holder"}) {
    const Solved a = solve_example(name);
    const Solved b = solve_example(name);
    EXPECT_EQ(a.result.parameters, b.result.parameters);
    nlohmann::json ja = nlohmann::json::parse(result_json(a.design.assembly, a.result, name));
    nlohmann::json jb = nlohmann::json::parse(result_json(b.design.assembly, b.result, name));
    ja.erase("timings_ms");
    jb.erase("timings_ms");
    EXPECT_EQ(ja, jb);
  }
}

// Groups that hang separately relax at once on several threads, and step 1's starts fit at
// once; how many threads is not part of the answer (each group writes only its own outcome,
// and the starts join the candidates in their own order).
TEST(Solve, TheAnswerDoesNotDependOnTheThreadCount) {
  std::string environment =
      "environment:\n  - {name: rods, part: TowelRackRods, frame: {pos: [0, 0, 200], rot: [0, "
      "0, -90]}}\n";
  std::string parts =
      "parts:\n  - {name: eyehook1, part: HookEyeConnector}\n  - {name: "
      "eyehook2, part: HookEyeConnector}\n";
  std::string connections =
      "connections:\n  - {connect: [eyehook1.hole, rods.rod1], alignment: flip}\n  - connect: "
      "[eyehook2.hole, rods.rod2]\n  - connect: [eyehook1.hook, basket.hook]\n  - connect: "
      "[eyehook2.hook, basket.hook]\n";
  for (int c = 0; c < 3; ++c) {
    const int y = 2000 + 200 * c;
    environment += fmt::format(
        "  - {{name: left{0}, primitives: {{rod: {{type: rod, radius: 4, length: 100}}}}, "
        "frame: {{pos: [-40, {1}, 500], rot: [90, 0, 0]}}}}\n"
        "  - {{name: right{0}, primitives: {{rod: {{type: rod, radius: 4, length: 100}}}}, "
        "frame: {{pos: [40, {1}, 500], rot: [90, 0, 180]}}}}\n",
        c,
        y);
    for (int i = 1; i <= 3; ++i)
      parts += fmt::format("  - {{name: s{}_{}, part: DoubleHook}}\n", c, i);
    connections += fmt::format(
        "  - connect: [s{0}_1.hook1, left{0}.rod]\n  - connect: [s{0}_2.hook1, s{0}_1.hook2]\n"
        "  - connect: [s{0}_3.hook1, s{0}_2.hook2]\n"
        "  - {{connect: [s{0}_3.hook2, right{0}.rod], alignment: flip}}\n",
        c);
  }
  const std::string text = "fabkit: hacks/1\nname: groups\n" + environment + parts +
                           "target:\n  name: basket\n  part: RoundHandleBasket\n  frame: {pos: "
                           "[0, 0, 100], rot: [-75, 0, 90]}\n" +
                           connections;
  std::vector<std::pair<std::string, Design>> designs;
  designs.emplace_back("groups", load_design_text(text, "groups.yaml", PartsLibrary::builtin()));
  // Starts that do not reach the target (all eight are fitted), one that does, one whose six
  // candidates are as near the target (relaxed at once), one that comes to rest against an
  // environment with contact rows while its unfolding runs beside them (and is dropped), and
  // one that passes through its environment whatever is tried.
  for (const char* name : {"clip_light_m",
                           "soap_bottle_holder",
                           "basket_between_rods",
                           "mug_hanger",
                           "paper_towel_holder",
                           "diaper_caddy"})
    designs.emplace_back(name, load_example(name));
  {
    // Ten medium S-hooks between two rods that do not hold where the verified configuration
    // rests: other closings are relaxed, two at a time whatever the thread count.
    std::string t =
        "fabkit: hacks/1\nname: medium chain\nenvironment:\n"
        "  - {name: left, primitives: {rod: {type: rod, radius: 2.5, length: 300}}, frame: {pos: "
        "[127.13401072464715, 0, 500], rot: [90, 0, 0]}}\n"
        "  - {name: right, primitives: {rod: {type: rod, radius: 2.5, length: 300}}, frame: {pos: "
        "[-127.13401072464715, 0, 442.687220681513], rot: [90, 0, -180]}}\nparts:\n";
    for (int i = 1; i <= 10; ++i)
      t += fmt::format("  - {{name: s{}, part: DoubleHookMedium}}\n", i);
    t += "connections:\n  - {connect: [s10.hook2, right.rod], alignment: flip}\n";
    for (int i = 9; i >= 1; --i)
      t += fmt::format("  - connect: [s{}.hook2, s{}.hook1]\n", i, i + 1);
    t += "  - connect: [s1.hook1, left.rod]\n";
    designs.emplace_back("mirrored medium chain",
                         load_design_text(t, "medium.yaml", PartsLibrary::builtin()));
  }
  // A 12-hook chain with its mug as the target (48 variables: step 1's guided start runs
  // beside the verified one): a goal beside where the mug hangs, which nothing reaches, and
  // one above it, which the verified start reaches (the guided start is called off).
  auto chain = [](const std::string& goal) {
    std::string t =
        "fabkit: hacks/1\nname: chain\nenvironment:\n  - {name: bar, primitives: {rod: {type: "
        "rod, radius: 4, length: 300}}, frame: {pos: [0, 0, 6000], rot: [90, 0, 0]}}\nparts:\n";
    for (int i = 1; i <= 12; ++i) t += fmt::format("  - {{name: s{}, part: DoubleHook}}\n", i);
    t += goal.empty() ? "  - {name: mug, part: Mug}\n"
                      : "target: {name: mug, part: Mug, primitive: hook, frame: " + goal + "}\n";
    t += "connections:\n  - connect: [s1.hook1, bar.rod]\n";
    for (int i = 2; i <= 12; ++i)
      t += fmt::format("  - connect: [s{}.hook1, s{}.hook2]\n", i, i - 1);
    return t + "  - connect: [mug.hook, s12.hook2]\n";
  };
  {
    const Design hanging = load_design_text(chain(""), "chain.yaml", PartsLibrary::builtin());
    ASSERT_TRUE(hanging.feasible()) << hanging.diagnostics.format();
    const SolveResult rest = solve(hanging.assembly);
    PartId mug;
    for (int i = 0; i < hanging.assembly.part_count(); ++i) {
      if (hanging.assembly.label(PartId{i}) == "mug") mug = PartId{i};
    }
    ASSERT_TRUE(mug.valid());
    const Part& part = *hanging.assembly.node(mug).part;
    const Frame hook =
        Frame::from_matrix(hanging.assembly.part_frames(rest.parameters)[mug.index()] *
                           part.primitive(part.find_primitive("hook")).frame.matrix());
    for (const Vec3& by : {Vec3(20, 0, 0), Vec3(0, 0, 60)}) {
      const Vec3 at = hook.pos + by;
      designs.emplace_back(
          fmt::format("chain, goal moved by ({}, {}, {})", by.x(), by.y(), by.z()),
          load_design_text(chain(fmt::format("{{pos: [{}, {}, {}], rot: [{}, {}, {}]}}",
                                             at.x(),
                                             at.y(),
                                             at.z(),
                                             hook.rot.x(),
                                             hook.rot.y(),
                                             hook.rot.z())),
                           "chain.yaml",
                           PartsLibrary::builtin()));
    }
  }
  for (const auto& [name, d] : designs) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    SolveOptions one;
    one.threads = 1;
    SolveOptions many;
    many.threads = 4;
    const SolveResult a = solve(d.assembly, one);
    const SolveResult b = solve(d.assembly, many);
    EXPECT_EQ(a.parameters, b.parameters);
    EXPECT_EQ(a.step1_parameters, b.step1_parameters);
    EXPECT_EQ(a.step1_starts, b.step1_starts);
    nlohmann::json ja = nlohmann::json::parse(result_json(d.assembly, a, name));
    nlohmann::json jb = nlohmann::json::parse(result_json(d.assembly, b, name));
    ja.erase("timings_ms");
    jb.erase("timings_ms");
    EXPECT_EQ(ja, jb);
  }
}

// result.json carries the documented keys.
TEST(Solve, ResultJsonKeys) {
  const Solved s = solve_example("bird_feeder");
  const nlohmann::json j =
      nlohmann::json::parse(result_json(s.design.assembly, s.result, "bird feeder"));
  EXPECT_TRUE(j.at("stable").get<bool>());
  EXPECT_TRUE(j.at("target").contains("pos_error_mm"));
  EXPECT_TRUE(j.at("target").contains("rot_error_deg"));
  EXPECT_TRUE(j.at("target").at("step1").contains("pos_error_mm"));
  ASSERT_EQ(j.at("parts").size(), 7u);
  EXPECT_EQ(j.at("parts")[0].at("name"), "wall");
  EXPECT_EQ(j.at("parts")[0].at("frame").at("pos").size(), 3u);
  EXPECT_EQ(j.at("parts")[0].at("frame").at("rot").size(), 3u);
  EXPECT_TRUE(j.at("slipping").is_array());
  EXPECT_TRUE(j.at("timings_ms").contains("step1"));
  EXPECT_TRUE(j.at("timings_ms").contains("step2"));
}

// The verdict is decided once, in this order, for the report, result.json, Python and the
// editor: a pose with parts inside each other is never called anything milder (however else
// it fails), and a solve stopped at its time limit is not judged by its unfinished pose.
TEST(Solve, TheVerdictIsDecidedInOneOrder) {
  SolveResult r;
  r.feasible = true;
  r.termination = Termination::kNotConverged;
  EXPECT_EQ(r.verdict(), Verdict::kNotAtRest);
  r.slips.push_back({ConnectionId{0}, 0, "s2.hook1 slides off the open end of s1.hook2"});
  EXPECT_EQ(r.verdict(), Verdict::kFallsApart);
  r.max_penetration_mm =
      detail::kPenetrationToleranceMm;  // at the tolerance: touching, not through
  EXPECT_EQ(r.verdict(), Verdict::kFallsApart);
  r.max_penetration_mm = detail::kPenetrationToleranceMm + 0.01;
  EXPECT_EQ(r.verdict(), Verdict::kPartsPassThrough);
  r.feasible = false;
  EXPECT_EQ(r.verdict(), Verdict::kPartsPassThrough);
  r.termination = Termination::kTimeout;
  EXPECT_EQ(r.verdict(), Verdict::kInfeasible);
  r.feasible = true;
  EXPECT_EQ(r.verdict(), Verdict::kStopped);
  r.max_penetration_mm = 0;
  r.slips.clear();
  r.termination = Termination::kInfeasible;
  r.feasible = false;
  EXPECT_EQ(r.verdict(), Verdict::kInfeasible);
  r.feasible = true;
  r.stable = true;
  r.termination = Termination::kConverged;
  EXPECT_EQ(r.verdict(), Verdict::kStable);
}

// Designs that hold, fall apart and pass through themselves get that verdict in the report's
// verdict line and in result.json.
TEST(Solve, ReportAndResultJsonGiveTheSameVerdict) {
  struct Case {
    std::string path;
    Verdict verdict;
    std::string line;  // the report's words
  };
  const std::string root = std::string(FABKIT_SOURCE_DIR) + "/examples/";
  const Case cases[] = {
      {root + "hacks/demo.yaml", Verdict::kStable, "STABLE"},
      {root + "failing/hook_on_tilted_rod.yaml", Verdict::kFallsApart, "FALLS APART"},
      {root + "hacks/diaper_caddy.yaml",
       Verdict::kPartsPassThrough,
       "PARTS PASS THROUGH EACH OTHER"},
  };
  for (const Case& c : cases) {
    const Design d = load_design(c.path, PartsLibrary::builtin());
    ASSERT_TRUE(d.feasible()) << c.path << d.diagnostics.format();
    const SolveResult r = solve(d.assembly);
    EXPECT_EQ(r.verdict(), c.verdict) << c.path << "\n" << r.summary();
    EXPECT_NE(r.summary().find(fmt::format("verdict                     {}", c.line)),
              std::string::npos)
        << c.path << "\n"
        << r.summary();
    const nlohmann::json j = nlohmann::json::parse(result_json(d.assembly, r, d.name));
    EXPECT_EQ(j.at("verdict").get<std::string>(), to_string(c.verdict)) << c.path;
  }
}

// The target's twist is free when some costless motion turns it about the vertical: a
// question about the space of neutral directions, not about the basis of it the eigensolver
// returned.
TEST(Solve, AFreeTwistIsFoundInAnyBasisOfTheNeutralDirections) {
  using detail::vertical_in_span;
  const Eigen::Vector3d x = Eigen::Vector3d::UnitX(), y = Eigen::Vector3d::UnitY(),
                        z = Eigen::Vector3d::UnitZ();
  auto turns = [](std::initializer_list<Eigen::Vector3d> columns) {
    Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(columns.size()));
    Eigen::Index k = 0;
    for (const Eigen::Vector3d& c : columns) m.col(k++) = c;
    return m;
  };
  EXPECT_TRUE(vertical_in_span(turns({0.02 * z})));
  EXPECT_TRUE(vertical_in_span(turns({Eigen::Vector3d::Zero(), 0.3 * z})));  // and a slide
  // A twist and a level turn, both free, as their sum and difference: neither is vertical.
  EXPECT_TRUE(vertical_in_span(turns({z + x, z - x})));
  EXPECT_TRUE(vertical_in_span(turns({z + 0.3 * y, 2 * (z - 0.3 * y), x})));
  EXPECT_FALSE(vertical_in_span(turns({x, y})));      // tilts only
  EXPECT_FALSE(vertical_in_span(turns({z + x})));     // a tilted axis: the twist costs
  EXPECT_FALSE(vertical_in_span(turns({1e-7 * z})));  // round-off
  EXPECT_FALSE(vertical_in_span(Eigen::Matrix3Xd(3, 0)));
}

// The exports open again and leave nothing half-written.
TEST(Solve, ExportsWriteEveryFile) {
  const Solved s = solve_example("demo");
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "fabkit_export_test";
  std::filesystem::remove_all(dir);
  Diagnostics d;
  ASSERT_TRUE(export_solution(s.design.assembly, s.result, dir, d)) << d.format();
  EXPECT_TRUE(d.empty()) << d.format();  // every part of the demo is one solid
  for (const char* f :
       {"result.json", "scene.glb", "preview.svg", "assembly.stl", "assembly.obj"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / f)) << f;
  }
  Diagnostics rd;
  const auto stl = read_mesh(dir / "assembly.stl", rd);
  const auto obj = read_mesh(dir / "assembly.obj", rd);
  ASSERT_TRUE(stl && obj) << rd.format();
  PartSolidCache solids;
  Diagnostics sd;
  EXPECT_EQ(stl->faces.size(),
            merged_mesh(solid_scene(s.design.assembly, s.result, solids, sd)).faces.size());
  EXPECT_EQ(obj->faces.size(), stl->faces.size());
  // A file in the way of the output directory: a clear error, no stray files.
  const std::filesystem::path blocked = dir / "result.json" / "sub";
  Diagnostics bd;
  EXPECT_FALSE(export_solution(s.design.assembly, s.result, blocked, bd));
  EXPECT_TRUE(bd.has_errors());
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    EXPECT_NE(e.path().extension(), ".tmp") << e.path();
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fabkit::hacks

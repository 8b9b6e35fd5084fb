#include <gtest/gtest.h>

#include <set>

#include "fabkit/flatpack/build.h"
#include "fabkit/flatpack/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

using test::check_yaml;
using test::has_code;

const char* kHead = "fabkit: flatpack/1\nparameters:\n  l1: 30\n  l2: {value: 60, type: length}\n";

TEST(Constraints, LinearExpressionsAndOwnConstraintsSolve) {
  const Analysis a =
      check_yaml(std::string(kHead) +
                 "components:\n  - {name: A, type: Rectangle}\n  - {name: B, type: Square}\n"
                 "constraints:\n  - A.l = l1\n  - A.w = 2*l2 + 10\n  - B.l + A.l = 100\n");
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_NEAR(a.values.at("A.w"), 130, 1e-9);
  EXPECT_NEAR(a.values.at("B.l"), 70, 1e-9);
  EXPECT_NEAR(a.values.at("B.w"), 70, 1e-9);  // the square's own w = l
}

TEST(Constraints, NonlinearOwnConstraintGivesTheHypotenuse) {
  const Analysis a = check_yaml(std::string(kHead) +
                                "components:\n  - {name: T, type: RightTriangle, w: 30, c: 50}\n");
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_NEAR(a.values.at("T.h"), 40, 1e-6);
}

TEST(Constraints, UnderConstrainedNamesTheFreeQuantities) {
  const Analysis a = check_yaml(
      std::string(kHead) +
      "components:\n  - {name: A, type: Rectangle, l: l1}\n  - {name: B, type: Rectangle, l: 5}\n"
      "constraints:\n  - A.w + B.w = 100\n");
  ASSERT_TRUE(has_code(a.diagnostics, codes::kUnderConstrained)) << a.diagnostics.format();
  EXPECT_NE(a.diagnostics.format().find("nothing determines A.w (in 'A.w + B.w = 100'), B.w"),
            std::string::npos)
      << a.diagnostics.format();
}

TEST(Constraints, OverConstrainedNamesTheConflictingConstraints) {
  const Analysis a = check_yaml(std::string(kHead) +
                                "components:\n  - {name: A, type: Rectangle, w: 5}\n"
                                "constraints:\n  - A.l = l1\n  - A.l = 35\n");
  ASSERT_TRUE(has_code(a.diagnostics, codes::kOverConstrained)) << a.diagnostics.format();
  EXPECT_NE(a.diagnostics.format().find("A.l = 35"), std::string::npos) << a.diagnostics.format();
  // Two-unknown conflicts are found by the linear solve.
  const Analysis b = check_yaml(std::string(kHead) +
                                "components:\n  - {name: A, type: Rectangle}\n"
                                "constraints:\n  - A.l + A.w = 10\n  - 2*A.l + 2*A.w = 30\n");
  ASSERT_TRUE(has_code(b.diagnostics, codes::kOverConstrained)) << b.diagnostics.format();
  EXPECT_NE(b.diagnostics.format().find("contradict each other"), std::string::npos)
      << b.diagnostics.format();
}

TEST(Constraints, UnknownNamesGetDidYouMean) {
  const Analysis a =
      check_yaml(std::string(kHead) + "components:\n  - {name: A, type: Rectangle, l: l3, w: 4}\n");
  EXPECT_NE(a.diagnostics.format().find(
                "'l3' in 'l3' is neither a parameter nor a component dimension; did you mean"),
            std::string::npos)
      << a.diagnostics.format();
  const Analysis b =
      check_yaml(std::string(kHead) + "components:\n  - {name: A, type: Rectangel}\n");
  EXPECT_NE(b.diagnostics.format().find("did you mean 'Rectangle'"), std::string::npos)
      << b.diagnostics.format();
}

TEST(Constraints, ANonWholeCountIsRefused) {
  const Analysis a = check_yaml(
      std::string(kHead) + "components:\n  - {name: P, type: RegularPolygon, n: 4.5, s: 10}\n");
  EXPECT_NE(a.diagnostics.format().find("P.n = 4.5 must be a whole number"), std::string::npos)
      << a.diagnostics.format();
}

// Paper §5.1: the simple table of Fig. 11(g) "has 4 structure-preserved design parameters,
// including the length, width, height of the table, and the width of table leg. However, an
// unconstrained table can have up to 22 parameters".
TEST(MetaParameters, SimpleTableIsDrivenByFourOfItsTwentyTwoNumbers) {
  const Design d = test::example("simple_table");
  const Analysis a = check(d);
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_EQ(a.meta_parameters,
            (std::vector<std::string>{"length", "width", "height", "leg_width"}));
  // Five rectangles (10 dimensions) and four connections (3 offsets each): 22 numbers.
  EXPECT_EQ(a.components.size(), 5u);
  EXPECT_EQ(a.dimension_count, 10);
  EXPECT_EQ(a.dimension_count + 3 * static_cast<int>(d.connections.size()), 22);
  using Set = std::set<std::string>;
  auto drives = [&](const std::string& m) {
    const auto& v = a.meta_drives.at(m);
    return Set(v.begin(), v.end());
  };
  EXPECT_EQ(drives("length"), Set{"top.l"});
  EXPECT_EQ(drives("width"), Set{"top.w"});
  EXPECT_EQ(drives("height"), (Set{"leg_fl.w", "leg_bl.w", "leg_fr.w", "leg_br.w"}));
  EXPECT_EQ(drives("leg_width"), (Set{"leg_fl.l", "leg_bl.l", "leg_fr.l", "leg_br.l"}));
  // Together they drive every dimension.
  Set all;
  for (const auto& [m, dims] : a.meta_drives) all.insert(dims.begin(), dims.end());
  EXPECT_EQ(static_cast<int>(all.size()), a.dimension_count);
  // report.json lists them with what they drive.
  BuildSummary s;
  s.analysis = a;
  const Json report = report_json(s);
  ASSERT_EQ(report["meta_parameters"].size(), 4u);
  EXPECT_EQ(report["meta_parameters"][2]["name"], "height");
  EXPECT_EQ(report["meta_parameters"][2]["value"], 150);
  EXPECT_EQ(report["meta_parameters"][2]["drives"].size(), 4u);
}

Vec2 size_of(const Analysis& a, const std::string& piece) {
  for (const Piece& p : a.pieces) {
    if (p.name == piece) return bounds(Region2d{p.outline}).size();
  }
  ADD_FAILURE() << "no piece " << piece;
  return Vec2::Zero();
}

TEST(MetaParameters, ChangingOneResizesEveryPieceItDrivesAndNoOther) {
  const Design d = test::example("simple_table");
  const Analysis before = check(d);
  const std::vector<std::string> pieces{"top", "leg_fl", "leg_bl", "leg_fr", "leg_br"};
  const std::map<std::string, std::set<std::string>> resized{
      {"length", {"top"}},
      {"width", {"top"}},
      {"height", {"leg_fl", "leg_bl", "leg_fr", "leg_br"}},
      {"leg_width", {"leg_fl", "leg_bl", "leg_fr", "leg_br"}}};
  for (const auto& [meta, expected] : resized) {
    Design changed = d;
    for (DesignParameter& p : changed.parameters) {
      if (p.name == meta) p.value = *p.value + 20;
    }
    const Analysis after = check(changed);
    ASSERT_FALSE(after.diagnostics.has_errors()) << after.diagnostics.format();
    for (const std::string& p : pieces) {
      const Vec2 grown = size_of(after, p) - size_of(before, p);
      if (expected.count(p)) {
        EXPECT_NEAR(grown.x() + grown.y(), 20, 1e-9) << meta << " → " << p;
      } else {
        EXPECT_NEAR(grown.norm(), 0, 1e-9) << meta << " should not re-size " << p;
      }
    }
    // The structure stays: same joints, the legs still under the top's corners.
    EXPECT_EQ(after.joints.size(), before.joints.size()) << meta;
    EXPECT_EQ(after.diagnostics.size(), 0u) << after.diagnostics.format();
  }
}

}  // namespace
}  // namespace fabkit::flatpack

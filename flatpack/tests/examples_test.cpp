// Every bundled example is checked and built (3 mm as written, and 6 mm plywood); the paper's
// reading-desk counts are asserted.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>

#include "fabkit/flatpack/build.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

const char* kExamples[] = {"bookend", "reading_desk", "stool", "computer_desk"};

// Paper §4.4, Fig. 9: "a reading desk with 11 components and 17 joints ... users only need to
// specify 10 connections ... other necessary intersections (or joints) (from 11 to 17) inserted
// automatically". The graph's joints are the 10 user connections (one of which merges two
// coplanar components into one piece) and 7 automatic ones.
TEST(Examples, ReadingDeskHasThePapersCounts) {
  const Analysis a = check(test::example("reading_desk"));
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_EQ(a.components.size(), 11u);
  EXPECT_EQ(test::example("reading_desk").connections.size(), 10u);
  EXPECT_EQ(a.graph_joints(), 17);
  EXPECT_EQ(a.user_connection_joints(), 10);
  EXPECT_EQ(a.automatic_joints(), 7);
  EXPECT_EQ(a.merging_connections.size(), 1u);
  EXPECT_EQ(a.pieces.size(), 10u);  // shelf_left + shelf_right are one piece
  EXPECT_EQ(a.joints.size(), 16u);  // cut joints: 17 minus the merge
  EXPECT_FALSE(a.assembly.empty());
}

class EveryExample : public ::testing::TestWithParam<std::tuple<const char*, double>> {};

TEST_P(EveryExample, ChecksBuildsAndGivesClosedPieces) {
  const auto [name, thickness] = GetParam();
  Design d = test::example(name);
  if (thickness > 0) {
    d.material.thickness_mm = thickness;
    d.material.name = "plywood-6mm";
    for (auto& [type, sub] : d.library) {
      auto copy = std::make_shared<Design>(*sub);
      copy->material = d.material;
      sub = copy;
    }
  }
  BuildOptions o;
  o.output_dir = std::filesystem::temp_directory_path() /
                 fmt::format("fabkit-flatpack-{}-{}", name, thickness);
  const BuildSummary s = build(d, o);
  ASSERT_EQ(s.termination, Termination::kBuilt) << s.diagnostics.format();
  EXPECT_FALSE(s.diagnostics.has_errors()) << s.diagnostics.format();
  EXPECT_GE(s.analysis.joints.size(), 1u);
  for (const TriangleMesh& m : piece_meshes(s.analysis)) EXPECT_TRUE(test::closed_and_oriented(m));
  for (const char* f : {"sheet-1.svg", "sheet-1.dxf", "model.stl", "scene.glb", "report.json"}) {
    EXPECT_TRUE(std::filesystem::exists(o.output_dir / f)) << f;
  }
  // Nesting: every piece on a sheet, inside its margin, none overlapping (checked with Clipper).
  const NestingOptions& sheet = d.sheet;
  const Polygon2d usable = rectangle(sheet.margin_mm - 1e-3,
                                     sheet.margin_mm - 1e-3,
                                     sheet.sheet_width_mm - sheet.margin_mm + 1e-3,
                                     sheet.sheet_height_mm - sheet.margin_mm + 1e-3);
  for (std::size_t i = 0; i < s.analysis.pieces.size(); ++i) {
    ASSERT_GE(s.nesting.placements[i].sheet, 0);
    const Region2d pi{placed(s.analysis.pieces[i].cut[0], s.nesting.placements[i])};
    EXPECT_NEAR(area(subtract(pi, {usable})), 0, 1e-2) << s.analysis.pieces[i].name;
    for (std::size_t j = i + 1; j < s.analysis.pieces.size(); ++j) {
      if (s.nesting.placements[j].sheet != s.nesting.placements[i].sheet) continue;
      const Region2d pj{placed(s.analysis.pieces[j].cut[0], s.nesting.placements[j])};
      EXPECT_NEAR(area(intersect(pi, pj)), 0, 1e-2)
          << s.analysis.pieces[i].name << " / " << s.analysis.pieces[j].name;
    }
  }
  std::filesystem::remove_all(o.output_dir);
}

INSTANTIATE_TEST_SUITE_P(Examples,
                         EveryExample,
                         ::testing::Combine(::testing::ValuesIn(kExamples),
                                            ::testing::Values(0.0, 6.0)),
                         [](const auto& info) {
                           return std::string(std::get<0>(info.param)) +
                                  (std::get<1>(info.param) > 0 ? "_6mm" : "_3mm");
                         });

}  // namespace
}  // namespace fabkit::flatpack

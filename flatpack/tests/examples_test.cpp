// Every bundled example is checked and built in 3 mm plywood (as written) and in 6 mm plywood:
// no errors and no warnings, every piece nested inside its sheet without overlaps, and the STL
// written as closed solids of the right volume (read back from the file). The paper's
// reading-desk counts are asserted.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "fabkit/core/json.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/flatpack/build.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

// Everything in examples/flatpack/ except the locked picnic table, which is meant to fail its
// assembly check (assembly_test.cpp).
const char* kExamples[] = {"bookend",
                           "reading_desk",
                           "stool",
                           "computer_desk",
                           "simple_table",
                           "picnic_table",
                           "box_stool",
                           "bookshelf",
                           "bed",
                           "ladder",
                           "bunk_bed",
                           "cabinet",
                           "tv_console",
                           "box_with_lid"};

TEST(Examples, EveryExampleFileIsListedHere) {
  std::set<std::string> listed(std::begin(kExamples), std::end(kExamples));
  listed.insert("picnic_table_locked");
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(FABKIT_SOURCE_DIR) + "/examples/flatpack")) {
    if (entry.path().extension() != ".yaml") continue;
    EXPECT_TRUE(listed.count(entry.path().stem().string())) << entry.path();
  }
}

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

// A design and every design it uses, cut from another board.
void set_material(Design& d, const Material& m) {
  d.material = m;
  for (auto& [type, sub] : d.library) {
    auto copy = std::make_shared<Design>(*sub);
    set_material(*copy, m);
    sub = copy;
  }
}

// Volume of a closed, outward-oriented mesh (divergence theorem).
double volume(const TriangleMesh& m) {
  double v = 0;
  for (const auto& f : m.faces) {
    v += m.vertices[static_cast<std::size_t>(f[0])].dot(
             m.vertices[static_cast<std::size_t>(f[1])].cross(
                 m.vertices[static_cast<std::size_t>(f[2])])) /
         6;
  }
  return v;
}

// Every edge of the file's triangles (vertices matched by position to 1 µm) is used as often
// in one direction as in the other: the file is a union of closed, consistently oriented shells.
bool edges_balanced(const TriangleMesh& m) {
  using Key = std::array<long long, 3>;
  auto key = [&](int i) {
    const Vec3& p = m.vertices[static_cast<std::size_t>(i)];
    return Key{std::llround(p.x() * 1e3), std::llround(p.y() * 1e3), std::llround(p.z() * 1e3)};
  };
  std::map<std::pair<Key, Key>, int> directed;
  for (const auto& f : m.faces) {
    for (int k = 0; k < 3; ++k) ++directed[{key(f[k]), key(f[(k + 1) % 3])}];
  }
  for (const auto& [e, n] : directed) {
    const auto back = directed.find({e.second, e.first});
    if (back == directed.end() || back->second != n) return false;
  }
  return !m.faces.empty();
}

// Wherever a deadline falls in a build — solving the dimensions, the meta-parameters' effects,
// shapes, placement, joints, nesting, writing — the only error is the time limit, and a build
// it stopped wrote nothing: either every file or none (issue 10). Deadlines are placed at
// fractions of the unlimited build's time; no time is asserted.
TEST(Examples, ADeadlineAnywhereReportsOnlyTheTimeLimitAndWritesNothing) {
  using Clock = std::chrono::steady_clock;
  for (const char* name : {"bunk_bed", "reading_desk", "bookshelf"}) {
    const Design d = test::example(name);
    BuildOptions o;
    o.output_dir = std::filesystem::temp_directory_path() / fmt::format("fabkit-deadline-{}", name);
    std::filesystem::remove_all(o.output_dir);
    const auto start = Clock::now();
    const BuildSummary full = build(d, o);
    const auto took = Clock::now() - start;
    ASSERT_EQ(full.termination, Termination::kBuilt) << name << full.diagnostics.format();
    for (int k = 0; k <= 12; ++k) {
      std::filesystem::remove_all(o.output_dir);
      o.deadline = Clock::now() + took * k / 12;
      const BuildSummary s = build(d, o);
      for (const Diagnostic& x : s.diagnostics) {
        if (x.severity != Severity::kError) continue;
        EXPECT_EQ(x.kind(), DiagnosticClass::kTimeout)
            << name << " at " << k << "/12 of its time: " << x.message;
      }
      if (s.termination == Termination::kTimeout) {
        const bool wrote_any =
            std::filesystem::exists(o.output_dir) && !std::filesystem::is_empty(o.output_dir);
        EXPECT_FALSE(wrote_any) << name << " at " << k << "/12: a stopped build left files";
      } else {
        EXPECT_EQ(s.termination, Termination::kBuilt) << name << " at " << k << "/12";
        EXPECT_TRUE(std::filesystem::exists(o.output_dir / "report.json")) << name;
      }
    }
    std::filesystem::remove_all(o.output_dir);
  }
}

class EveryExample : public ::testing::TestWithParam<std::tuple<const char*, double>> {};

TEST_P(EveryExample, ChecksBuildsCleanlyAndGivesClosedPieces) {
  const auto [name, thickness] = GetParam();
  Design d = test::example(name);
  if (thickness > 0) {
    Material m = d.material;
    m.thickness_mm = thickness;
    m.name = "plywood-6mm";
    set_material(d, m);
  }
  BuildOptions o;
  o.output_dir = std::filesystem::temp_directory_path() /
                 fmt::format("fabkit-flatpack-{}-{}", name, thickness);
  const BuildSummary s = build(d, o);
  ASSERT_EQ(s.termination, Termination::kBuilt) << s.diagnostics.format();
  // A bundled example is clean: no errors, no warnings (notes say what was merged).
  for (const Diagnostic& x : s.diagnostics) {
    EXPECT_EQ(x.severity, Severity::kNote) << x.message;
  }
  EXPECT_GE(s.analysis.joints.size(), 1u);
  // Every piece in the assembly order, once.
  std::set<int> ordered;
  for (const AssemblyStep& st : s.analysis.assembly) ordered.insert(st.piece);
  EXPECT_EQ(ordered.size(), s.analysis.pieces.size());
  for (const TriangleMesh& m : piece_meshes(s.analysis)) EXPECT_TRUE(test::closed_and_oriented(m));
  for (const char* f : {"sheet-1.svg", "sheet-1.dxf", "model.stl", "scene.glb", "report.json"}) {
    EXPECT_TRUE(std::filesystem::exists(o.output_dir / f)) << f;
  }
  // The STL as written: closed shells whose volume is each piece's cut area × its thickness.
  Diagnostics io;
  const auto stl = read_mesh(o.output_dir / "model.stl", io);
  ASSERT_TRUE(stl) << io.format();
  EXPECT_TRUE(edges_balanced(*stl));
  double expected = 0;
  for (const Piece& p : s.analysis.pieces) expected += area(p.cut) * p.material.thickness_mm;
  EXPECT_NEAR(volume(*stl), expected, 1e-4 * expected);
  // report.json counts what was built.
  std::ifstream in(o.output_dir / "report.json");
  const Json report = Json::parse(in);
  EXPECT_EQ(report["counts"]["pieces"], s.analysis.pieces.size());
  EXPECT_EQ(report["counts"]["joints"], s.analysis.graph_joints());
  EXPECT_EQ(report["sheets"]["count"], s.nesting.sheet_count);
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

std::string example_name(const ::testing::TestParamInfo<std::tuple<const char*, double>>& p) {
  return std::string(std::get<0>(p.param)) + (std::get<1>(p.param) > 0 ? "_6mm" : "_3mm");
}

INSTANTIATE_TEST_SUITE_P(Examples,
                         EveryExample,
                         ::testing::Combine(::testing::ValuesIn(kExamples),
                                            ::testing::Values(0.0, 6.0)),
                         example_name);

}  // namespace
}  // namespace fabkit::flatpack

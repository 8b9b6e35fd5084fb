// The files a maker builds from (assembly.stl, assembly.obj) hold every part of every gallery
// design as closed solids: read back as a slicer reads them (float32, coincident vertices
// merged), every connected shell is closed, manifold, outward and free of self-intersections,
// and the shells are exactly the parts' solids (no two parts share a vertex). admesh judges
// the same files independently in cli/tests/hacks_solids_cli_tests.cmake.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "fabkit/core/export_formats.h"
#include "fabkit/core/mesh_boolean.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/hacks/part_solid.h"
#include "fabkit/hacks/solution_export.h"
#include "fabkit/hacks/solve.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

std::filesystem::path scratch(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("fabkit_solid_export_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

// Every shell of a mesh read back from a file is a valid solid; returns how many there are.
int expect_solid_shells(const TriangleMesh& mesh, const std::string& file) {
  const std::vector<TriangleMesh> shells = mesh_pieces(mesh);
  for (std::size_t i = 0; i < shells.size(); ++i) {
    const SolidCheck c = check_solid(shells[i]);
    EXPECT_TRUE(c.valid_solid()) << file << " shell " << i + 1 << " of " << shells.size() << ": "
                                 << c.problems();
  }
  return static_cast<int>(shells.size());
}

class GallerySolids : public ::testing::TestWithParam<const char*> {};

TEST_P(GallerySolids, EveryPartIsAClosedSolidInTheFiles) {
  const Design design = testing::load_example(GetParam());
  ASSERT_TRUE(design.feasible()) << design.diagnostics.format();
  const SolveResult result = solve(design.assembly);
  // A pose to export (the diaper caddy's passes through the seat: infeasible, still a pose).
  ASSERT_EQ(result.parts.size(), static_cast<std::size_t>(design.assembly.part_count()))
      << result.message;
  const std::filesystem::path dir = scratch(GetParam());
  PartSolidCache solids;
  ExportOptions options;
  options.solids = &solids;
  Diagnostics d;
  ASSERT_TRUE(export_solution(design.assembly, result, dir, d, options)) << d.format();
  EXPECT_TRUE(d.empty()) << d.format();  // no part fell back to its display mesh
  // Each part type was unioned once.
  EXPECT_EQ(solids.computed() + solids.reused(), design.assembly.part_count());
  int expected_shells = 0;
  for (const PartNode& n : design.assembly.nodes()) expected_shells += solids.solid(*n.part).shells;

  for (const char* file : {"assembly.stl", "assembly.obj"}) {
    SCOPED_TRACE(file);
    Diagnostics rd;
    const auto mesh = read_mesh(dir / file, rd);
    ASSERT_TRUE(mesh) << rd.format();
    EXPECT_EQ(expect_solid_shells(*mesh, file), expected_shells);
    // Where the parts are: the solids' bounds are the display meshes' bounds (mm).
    const TriangleMesh display = solution_mesh(design.assembly, result);
    EXPECT_LT((mesh->bounds_min() - display.bounds_min()).cwiseAbs().maxCoeff(), 0.02);
    EXPECT_LT((mesh->bounds_max() - display.bounds_max()).cwiseAbs().maxCoeff(), 0.02);
  }
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(Gallery,
                         GallerySolids,
                         ::testing::ValuesIn(testing::kGalleryExamples),
                         [](const ::testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param);
                         });

// ParamHanger's `length` is the width the exported file measures, tip to tip (docs/parts.md):
// the hanger is the environment, at the world origin, and the first shell of the STL.
TEST(SolidExport, ParamHangerIsAsWideAsItsLength) {
  for (const double length : {100.0, 435.0, 600.0, 1000.0}) {
    SCOPED_TRACE(length);
    const Design design = testing::load_text(fmt::format(R"(fabkit: hacks/1
name: hanger width
environment:
  - {{name: hanger, part: ParamHanger, params: {{length: {}}}, frame: {{pos: [0, 0, 0], rot: [0, 0, 0]}}}}
target: {{name: hook, part: DoubleHook, primitive: hook1, frame: {{pos: [0, 0, -150], rot: [0, 0, 0]}}}}
connections:
  - connect: [hook.hook2, hanger.rod]
)",
                                                         length));
    ASSERT_TRUE(design.feasible()) << design.diagnostics.format();
    const SolveResult result = solve(design.assembly);
    ASSERT_TRUE(result.feasible) << result.message;
    const std::filesystem::path dir = scratch("hanger");
    Diagnostics d;
    ASSERT_TRUE(export_solution(design.assembly, result, dir, d)) << d.format();
    const auto stl = read_mesh(dir / "assembly.stl", d);
    ASSERT_TRUE(stl) << d.format();
    const std::vector<TriangleMesh> shells = mesh_pieces(*stl);
    ASSERT_GE(shells.size(), 2u);
    const TriangleMesh& hanger = shells.front();
    EXPECT_TRUE(check_solid(hanger).valid_solid()) << check_solid(hanger).problems();
    // float32 at 500 mm is exact to 3e-5 mm.
    EXPECT_NEAR(hanger.bounds_max().y() - hanger.bounds_min().y(), length, 1e-4);
    EXPECT_NEAR(hanger.bounds_max().y(), length / 2, 1e-4);
    std::filesystem::remove_all(dir);
  }
}

}  // namespace
}  // namespace fabkit::hacks

// Parts as closed solids (part_solid.h): every built-in part's union is a printable solid, it
// keeps the part's shape (bounds, volume between its largest piece and the sum of its pieces),
// it survives float32 STL at a world pose, and the cache unions each type once.
#include "fabkit/hacks/part_solid.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "fabkit/core/file_io.h"
#include "fabkit/core/mesh_boolean.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::has_diagnostic;
using testing::make_part;

TEST(MeshPieces, SplitsAppendedShapesAndKeepsConnectedOnesWhole) {
  TriangleMesh m = shapes::box(Vec3(1, 2, 3));
  m.append(shapes::cylinder(1, 4, 8).transformed(translation(5.0, 0.0, 0.0)));
  m.append(shapes::torus_arc(10, 1, 270));
  m.vertices.emplace_back(100, 100, 100);  // used by no face: dropped
  const std::vector<TriangleMesh> pieces = mesh_pieces(m);
  ASSERT_EQ(pieces.size(), 3u);
  EXPECT_EQ(pieces[0].faces.size(), 12u);
  EXPECT_EQ(pieces[0].vertices.size(), 8u);
  EXPECT_EQ(pieces[1].faces.size(), shapes::cylinder(1, 4, 8).faces.size());
  EXPECT_NEAR(pieces[1].bounds_min().x(), 4, 1e-12);
  EXPECT_EQ(pieces[2].faces.size(), shapes::torus_arc(10, 1, 270).faces.size());
  std::size_t faces = 0;
  for (const TriangleMesh& p : pieces) faces += p.faces.size();
  EXPECT_EQ(faces, m.faces.size());
  EXPECT_EQ(mesh_pieces(shapes::sphere(3)).size(), 1u);
  EXPECT_TRUE(mesh_pieces(TriangleMesh{}).empty());
}

// The checks a solid of a part must pass, independent of how the union was computed.
void expect_solid_of(const Part& part, const PartSolid& s) {
  SCOPED_TRACE(part.type_name);
  ASSERT_TRUE(s.exact) << s.diagnostics.format();
  EXPECT_TRUE(s.diagnostics.empty()) << s.diagnostics.format();
  const SolidCheck c = check_solid(s.mesh);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_EQ(c.components, s.shells);
  EXPECT_GE(s.shells, 1);
  EXPECT_LE(s.shells, s.pieces);
  // The same shape: the same bounds (vertices move by at most the snap grid and the 10 µm
  // sliver removal), a volume no less than the largest piece's and no more than all pieces'.
  const double tol = 0.011;
  EXPECT_LT((s.mesh.bounds_min() - part.mesh.bounds_min()).cwiseAbs().maxCoeff(), tol);
  EXPECT_LT((s.mesh.bounds_max() - part.mesh.bounds_max()).cwiseAbs().maxCoeff(), tol);
  double largest = 0, sum = 0;
  const std::vector<TriangleMesh> pieces = mesh_pieces(part.mesh);
  EXPECT_EQ(static_cast<int>(pieces.size()), s.pieces);
  for (const TriangleMesh& p : pieces) {
    largest = std::max(largest, p.volume());
    sum += p.volume();
  }
  // (1e-4: the 0.06 µm snap grid times the surface area, relative to the volume.)
  EXPECT_GE(c.volume, largest * (1 - 1e-4));
  EXPECT_LE(c.volume, sum * (1 + 1e-4));
  // As a slicer gets it: placed in the world (a turn about a skew axis, 1.5 m away), written
  // as float32 STL, read back with coincident vertices merged.
  const std::filesystem::path stl =
      std::filesystem::temp_directory_path() / ("fabkit_part_solid_" + part.type_name + ".stl");
  Diagnostics d;
  const Mat4 pose = Frame(Vec3(812.3, -1247.9, 301.7), Vec3(17, 33, 71)).matrix();
  ASSERT_TRUE(write_stl(s.mesh.transformed(pose), stl, d)) << d.format();
  const auto back = read_mesh(stl, d);
  std::filesystem::remove(stl);
  ASSERT_TRUE(back) << d.format();
  const SolidCheck cb = check_solid(*back);
  EXPECT_TRUE(cb.valid_solid()) << "after float32 STL: " << cb.problems();
  EXPECT_EQ(back->faces.size(), s.mesh.faces.size());
}

class BuiltinPartSolid : public ::testing::TestWithParam<std::string> {};

TEST_P(BuiltinPartSolid, IsOneClosedSolid) {
  const auto part = make_part(GetParam());
  ASSERT_TRUE(part);
  expect_solid_of(*part, part_solid(*part));
}

std::vector<std::string> builtin_names() {
  std::vector<std::string> names;
  for (const PartGenerator& g : PartsLibrary::builtin().generators()) names.push_back(g.name);
  return names;
}

INSTANTIATE_TEST_SUITE_P(Library,
                         BuiltinPartSolid,
                         ::testing::ValuesIn(builtin_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

// The parametric parts at other values than their defaults (those the gallery and the
// ParamHanger tests use, and the extremes of their ranges).
TEST(PartSolid, ParametricPartsAtOtherValues) {
  const std::vector<std::pair<std::string, ParamValues>> variants{
      {"ParamTurnbuckle", {{"extended_length", 40}}},
      {"ParamTurnbuckle", {{"extended_length", 100}}},
      {"ParamHanger", {{"length", 100}, {"bend_d", 70}, {"bar_d", 2}}},
      {"ParamHanger", {{"length", 1000}, {"height", 400}, {"hook_d", 200}, {"hook_h", 400}}},
      {"ParamHanger", {{"length", 300}, {"height", 60}}},
  };
  for (const auto& [name, params] : variants) {
    const auto part = make_part(name, params);
    ASSERT_TRUE(part);
    expect_solid_of(*part, part_solid(*part));
  }
}

// A part made of loose primitives (a design's `environment: primitives:`) is unioned too.
TEST(PartSolid, LoosePrimitivesPart) {
  PrimitiveShape rod;
  rod.radius = 5;
  rod.length = 200;
  PrimitiveShape hook;
  hook.arc_radius = 20;
  hook.arc_angle = 200;
  hook.thickness = 2;
  const Part part = make_primitive_part(
      {Primitive::make("rod", PrimitiveType::kRod, rod, Frame(Vec3::Zero(), Vec3(0, 90, 0))),
       Primitive::make("hook", PrimitiveType::kHook, hook, Frame(Vec3(0, 0, 20), Vec3::Zero()))});
  const PartSolid s = part_solid(part);
  expect_solid_of(part, s);
  EXPECT_EQ(s.pieces, 2);
  EXPECT_EQ(s.shells, 1);  // the hook's wire passes through the rod
}

// Pieces drawn flush but computed along different paths (a rod turned onto x ending on a
// bracket's face, two S-hook arcs meeting cap to cap) join into one shell, without slivers.
TEST(PartSolid, FlushPiecesJoinIntoOneShell) {
  for (const char* name : {"ShowerCurtainRod", "Tack", "DoubleHook", "OpenHandleBasket"}) {
    const auto part = make_part(name);
    ASSERT_TRUE(part);
    const PartSolid s = part_solid(*part);
    expect_solid_of(*part, s);
    EXPECT_EQ(s.shells, 1) << name;
  }
}

TEST(PartSolid, OpenPieceIsExportedAsItIsWithAWarning) {
  Part part;
  part.type_name = "ScannedVase";
  part.mesh = shapes::box(Vec3(10, 10, 10));
  TriangleMesh open = shapes::cylinder(3, 20, 12);
  open.faces.pop_back();
  part.mesh.append(open);
  const PartSolid s = part_solid(part);
  EXPECT_FALSE(s.exact);
  EXPECT_EQ(s.mesh.faces, part.mesh.faces);
  EXPECT_EQ(s.mesh.vertices, part.mesh.vertices);
  EXPECT_EQ(s.pieces, 2);
  EXPECT_FALSE(s.diagnostics.has_errors());
  EXPECT_TRUE(has_diagnostic(s.diagnostics,
                             codes::kNotASolid,
                             "part ScannedVase: exported as its display mesh, not one solid: "
                             "piece 2 of 2 is not a closed solid (not closed (3 boundary edges))"));
}

TEST(PartSolid, InsideOutPieceIsNamed) {
  Part part;
  part.type_name = "Backwards";
  part.mesh = shapes::box(Vec3(10, 10, 10));
  for (auto& f : part.mesh.faces) std::swap(f[1], f[2]);
  const PartSolid s = part_solid(part);
  EXPECT_FALSE(s.exact);
  EXPECT_TRUE(has_diagnostic(
      s.diagnostics, codes::kNotASolid, "piece 1 of 1 is not a closed solid (inside out"));
}

TEST(PartSolid, EmptyMeshIsAnEmptySolid) {
  Part part;
  part.type_name = "Nothing";
  const PartSolid s = part_solid(part);
  EXPECT_TRUE(s.exact);
  EXPECT_TRUE(s.mesh.empty());
  EXPECT_EQ(s.pieces, 0);
  EXPECT_EQ(s.shells, 0);
}

TEST(PartSolidCache, UnionsEachTypeAndParametersOnce) {
  PartSolidCache cache;
  const auto a = make_part("DoubleHook");
  const auto b = make_part("DoubleHook");
  const auto t40 = make_part("ParamTurnbuckle", {{"extended_length", 40}});
  const auto t40b = make_part("ParamTurnbuckle", {{"extended_length", 40}});
  const auto t60 = make_part("ParamTurnbuckle", {{"extended_length", 60}});
  const PartSolid& sa = cache.solid(*a);
  EXPECT_EQ(&cache.solid(*b), &sa);
  EXPECT_EQ(cache.computed(), 1);
  EXPECT_EQ(cache.reused(), 1);
  const PartSolid& s40 = cache.solid(*t40);
  EXPECT_EQ(&cache.solid(*t40b), &s40);
  EXPECT_NE(&cache.solid(*t60), &s40);
  EXPECT_EQ(cache.computed(), 3);
  EXPECT_EQ(cache.reused(), 2);
  // The cached solid is the one part_solid computes.
  EXPECT_EQ(s40.mesh.faces, part_solid(*t40).mesh.faces);
  // A part whose mesh differs (a user's part of the same name) is not taken for another.
  Part edited = *a;
  edited.mesh.vertices[0].x() += 1;
  EXPECT_NE(&cache.solid(edited), &sa);
  EXPECT_EQ(cache.computed(), 4);
  // References stay valid as the cache grows.
  for (double l : {1.0, 2.0, 3.0, 4.0, 5.0})
    cache.solid(*make_part("ParamTurnbuckle", {{"extended_length", l}}));
  EXPECT_TRUE(check_solid(sa.mesh).valid_solid());
}

// Same display mesh, same solid, bit for bit: the files do not change from run to run.
TEST(PartSolid, SameMeshSameSolid) {
  for (const char* name : {"ParamTurnbuckle", "ParamHanger"}) {
    const auto part = make_part(name);
    ASSERT_TRUE(part);
    const PartSolid a = part_solid(*part), b = part_solid(*part);
    EXPECT_EQ(a.mesh.faces, b.mesh.faces) << name;
    EXPECT_EQ(a.mesh.vertices, b.mesh.vertices) << name;
  }
}

std::filesystem::path fresh_directory(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("fabkit_part_solid_cache_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

// A second process (a new cache on the same directory) reads the solid instead of computing
// it, and gets the same solid bit for bit.
TEST(PartSolidCache, KeepsSolidsInItsDirectory) {
  const std::filesystem::path dir = fresh_directory("keeps");
  const auto part = make_part("ParamTurnbuckle", {{"extended_length", 27.42}});
  ASSERT_TRUE(part);
  PartSolid first;
  {
    PartSolidCache cache(dir);
    first = cache.solid(*part);
    EXPECT_EQ(cache.computed(), 1);
    EXPECT_EQ(cache.loaded(), 0);
  }
  const std::filesystem::path file = dir / fmt::format("{:016x}.solid", part_solid_key(part->mesh));
  ASSERT_TRUE(std::filesystem::is_regular_file(file));
  PartSolidCache again(dir);
  const PartSolid& second = again.solid(*part);
  EXPECT_EQ(again.computed(), 0);
  EXPECT_EQ(again.loaded(), 1);
  EXPECT_TRUE(second.exact);
  EXPECT_EQ(second.pieces, first.pieces);
  EXPECT_EQ(second.shells, first.shells);
  EXPECT_EQ(second.mesh.faces, first.mesh.faces);
  EXPECT_EQ(second.mesh.vertices, first.mesh.vertices);
  // Another extension is another mesh, another file.
  const auto longer = make_part("ParamTurnbuckle", {{"extended_length", 43.415}});
  EXPECT_NE(part_solid_key(longer->mesh), part_solid_key(part->mesh));
  again.solid(*longer);
  EXPECT_EQ(again.computed(), 1);
  std::filesystem::remove_all(dir);
}

// A damaged, truncated or foreign file under the key's name is a miss: the solid is computed
// again (and the file rewritten), never read as garbage.
TEST(PartSolidCache, DamagedFileIsRecomputed) {
  const std::filesystem::path dir = fresh_directory("damaged");
  const auto part = make_part("DoubleHook");
  ASSERT_TRUE(part);
  const PartSolid good = [&] {
    PartSolidCache cache(dir);
    return cache.solid(*part);
  }();
  const std::filesystem::path file = dir / fmt::format("{:016x}.solid", part_solid_key(part->mesh));
  Diagnostics rd;
  const std::string bytes = read_input_file(file, "solid", rd).value_or("");
  ASSERT_GT(bytes.size(), 1000u);
  std::string flipped = bytes;
  flipped[bytes.size() / 2] = static_cast<char>(flipped[bytes.size() / 2] ^ 0x10);
  for (const std::string& damaged :
       {flipped, bytes.substr(0, bytes.size() / 3), std::string("not a solid"), std::string()}) {
    Diagnostics wd;
    ASSERT_TRUE(write_file_atomically(file, damaged, wd)) << wd.format();
    PartSolidCache cache(dir);
    const PartSolid& s = cache.solid(*part);
    EXPECT_EQ(cache.loaded(), 0);
    EXPECT_EQ(cache.computed(), 1);
    EXPECT_EQ(s.mesh.vertices, good.mesh.vertices);
    Diagnostics rd2;
    EXPECT_EQ(read_input_file(file, "solid", rd2).value_or(""), bytes);  // rewritten
  }
  std::filesystem::remove_all(dir);
}

// A directory that cannot be written costs time, not the export.
TEST(PartSolidCache, UnwritableDirectoryStillGivesTheSolid) {
  const std::filesystem::path dir = fresh_directory("blocked");
  Diagnostics wd;
  ASSERT_TRUE(write_file_atomically(dir, "a file where the directory would be", wd));
  const auto part = make_part("Phone");
  ASSERT_TRUE(part);
  PartSolidCache cache(dir / "solids");
  const PartSolid& s = cache.solid(*part);
  EXPECT_TRUE(s.exact);
  EXPECT_TRUE(check_solid(s.mesh).valid_solid());
  std::filesystem::remove_all(dir);
}

TEST(Float32SafePlacement, KeepsAGoodPlacementAndRefusesAHopelessSolid) {
  const TriangleMesh box = shapes::box(Vec3(10, 20, 30));
  const Mat4 pose = Frame(Vec3(812.3, -1247.9, 301.7), Vec3(17, 33, 71)).matrix();
  const std::optional<Mat4> kept = float32_safe_placement(box, pose);
  ASSERT_TRUE(kept);
  EXPECT_EQ(*kept, pose);
  // A box 10 nm across collapses to a point in float32 1 m away, however it is nudged.
  const TriangleMesh speck = shapes::box(Vec3(1e-5, 1e-5, 1e-5));
  ASSERT_TRUE(check_solid(speck).valid_solid());
  EXPECT_FALSE(float32_safe_placement(speck, translation(1000.0, 0.0, 0.0)));
}

}  // namespace
}  // namespace fabkit::hacks

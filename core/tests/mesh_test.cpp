#include "fabkit/core/mesh.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <string>
#include <utility>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"
#include "fabkit/core/mesh_io.h"

namespace fabkit {
namespace {

namespace fs = std::filesystem;
using std::numbers::pi;

/// Empty string if every undirected edge is shared by exactly two faces with opposite
/// orientation (closed, manifold, consistently oriented); otherwise a description of the first
/// problem found.
std::string watertight_problem(const TriangleMesh& mesh) {
  const int nv = static_cast<int>(mesh.vertices.size());
  std::map<std::pair<int, int>, int> directed;
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    const auto& f = mesh.faces[i];
    for (int c = 0; c < 3; ++c) {
      if (f[c] < 0 || f[c] >= nv) return fmt::format("face {} has bad index {}", i, f[c]);
    }
    if (f[0] == f[1] || f[1] == f[2] || f[2] == f[0]) {
      return fmt::format("face {} is degenerate", i);
    }
    for (int c = 0; c < 3; ++c) ++directed[{f[c], f[(c + 1) % 3]}];
  }
  for (const auto& [edge, count] : directed) {
    if (count != 1) {
      return fmt::format(
          "edge {}->{} used {} times in the same direction", edge.first, edge.second, count);
    }
    const auto reverse = directed.find({edge.second, edge.first});
    if (reverse == directed.end()) {
      return fmt::format("edge {}->{} has no opposite edge", edge.first, edge.second);
    }
  }
  return "";
}

void expect_watertight(const TriangleMesh& mesh, const std::string& what) {
  ASSERT_FALSE(mesh.empty()) << what;
  EXPECT_EQ(watertight_problem(mesh), "") << what;
  EXPECT_GT(mesh.volume(), 0.0) << what;
}

double max_coordinate(const TriangleMesh& mesh, int axis) {
  double m = -1e300;
  for (const auto& v : mesh.vertices) m = std::max(m, v[axis]);
  return m;
}

double min_distance(const TriangleMesh& mesh, const Vec3& p) {
  double d = 1e300;
  for (const auto& v : mesh.vertices) d = std::min(d, (v - p).norm());
  return d;
}

/// Area factor of a regular n-gon inscribed in a circle: n·sin(2π/n) / (2π).
double polygon_factor(int n) {
  return n * std::sin(2.0 * pi / n) / (2.0 * pi);
}

// ---------------------------------------------------------------------------------------------
// Watertightness and orientation

TEST(MeshShapes, AllShapesAreWatertightAndOutward) {
  expect_watertight(shapes::box(Vec3(1, 2, 3)), "box");
  expect_watertight(shapes::cylinder(2, 5), "cylinder");
  expect_watertight(shapes::cylinder(2, 5, 3), "cylinder/3");
  expect_watertight(shapes::tube(1, 2, 5), "tube");
  expect_watertight(shapes::sphere(3), "sphere");
  expect_watertight(shapes::sphere(3, 5), "sphere/5");
  expect_watertight(shapes::hemisphere(3), "hemisphere");
  expect_watertight(shapes::hemisphere(3, 6), "hemisphere/6");
  for (const double angle : {10.0, 90.0, 180.0, 270.0, 359.0, 360.0, 400.0}) {
    expect_watertight(shapes::torus_arc(20, 2, angle), fmt::format("torus_arc {}", angle));
  }
}

TEST(MeshShapes, WatertightHelperDetectsDefects) {
  TriangleMesh box = shapes::box(Vec3(1, 1, 1));
  TriangleMesh open = box;
  open.faces.pop_back();
  EXPECT_NE(watertight_problem(open), "");
  TriangleMesh flipped = box;
  std::swap(flipped.faces[0][1], flipped.faces[0][2]);
  EXPECT_NE(watertight_problem(flipped), "");
}

TEST(MeshShapes, InsideOutMeshHasNegativeVolume) {
  TriangleMesh box = shapes::box(Vec3(1, 2, 3));
  for (auto& f : box.faces) std::swap(f[1], f[2]);
  EXPECT_NEAR(box.volume(), -6.0, 1e-12);
}

// ---------------------------------------------------------------------------------------------
// Volumes. Vertices lie on the true surface, so tessellated volumes are slightly below the
// analytic ones; the tolerances follow from the default segment counts (24-gon: -1.1 %,
// 16×8 UV sphere: -6.3 %, 32×10 torus: -7.1 %), and a fine tessellation must converge.

TEST(MeshVolume, BoxIsExact) {
  EXPECT_NEAR(shapes::box(Vec3(2, 3, 4)).volume(), 24.0, 1e-12);
}

TEST(MeshVolume, Cylinder) {
  const double r = 3, l = 10;
  const double analytic = pi * r * r * l;
  const double v = shapes::cylinder(r, l).volume();
  EXPECT_NEAR(v, analytic, 0.02 * analytic);
  EXPECT_LT(v, analytic);
  // Exact volume of the inscribed 24-gon prism.
  EXPECT_NEAR(v, analytic * polygon_factor(24), 1e-9 * analytic);
  EXPECT_NEAR(shapes::cylinder(r, l, 256).volume(), analytic, 0.001 * analytic);
}

TEST(MeshVolume, Tube) {
  const double ri = 2, ro = 3, l = 7;
  const double analytic = pi * (ro * ro - ri * ri) * l;
  const double v = shapes::tube(ri, ro, l).volume();
  EXPECT_NEAR(v, analytic, 0.02 * analytic);
  EXPECT_NEAR(v, analytic * polygon_factor(24), 1e-9 * analytic);
}

TEST(MeshVolume, Sphere) {
  const double r = 5;
  const double analytic = 4.0 / 3.0 * pi * r * r * r;
  const double v = shapes::sphere(r).volume();
  EXPECT_NEAR(v, analytic, 0.07 * analytic);
  EXPECT_LT(v, analytic);
  EXPECT_NEAR(shapes::sphere(r, 128).volume(), analytic, 0.005 * analytic);
}

TEST(MeshVolume, Hemisphere) {
  const double r = 5;
  const double analytic = 2.0 / 3.0 * pi * r * r * r;
  const TriangleMesh h = shapes::hemisphere(r);
  EXPECT_NEAR(h.volume(), analytic, 0.07 * analytic);
  EXPECT_LT(h.volume(), analytic);
  EXPECT_NEAR(shapes::hemisphere(r, 128).volume(), analytic, 0.005 * analytic);
  // Lower half: z in [-r, 0], with the flat side exactly at z = 0.
  EXPECT_NEAR(h.bounds_max().z(), 0.0, 1e-12);
  EXPECT_NEAR(h.bounds_min().z(), -r, 1e-12);
  // Centre of mass of a solid hemisphere is 3r/8 below the flat face.
  EXPECT_NEAR(shapes::hemisphere(r, 128).centroid().z(), -3.0 * r / 8.0, 0.01 * r);
}

TEST(MeshVolume, ClosedTorus) {
  const double big = 20, small = 2;
  const double analytic = 2.0 * pi * pi * big * small * small;
  const double v = shapes::torus_arc(big, small, 360).volume();
  EXPECT_NEAR(v, analytic, 0.08 * analytic);
  // Exact for the polygonal torus: swept 10-gon (centroid on the centreline) along a 32-gon.
  EXPECT_NEAR(v, analytic * polygon_factor(32) * polygon_factor(10), 1e-9 * analytic);
  EXPECT_NEAR(shapes::torus_arc(big, small, 360, 256, 64).volume(), analytic, 0.005 * analytic);
  // Anything from a full turn on is the same closed torus.
  EXPECT_NEAR(shapes::torus_arc(big, small, 450).volume(), v, 1e-9 * v);
}

TEST(MeshVolume, TorusArcIsProportionalToAngle) {
  const double big = 20, small = 2;
  const double analytic = 2.0 * pi * pi * big * small * small;
  const double v = shapes::torus_arc(big, small, 90, 128, 64).volume();
  EXPECT_NEAR(v, analytic / 4.0, 0.005 * analytic / 4.0);
}

// ---------------------------------------------------------------------------------------------
// Shape placement

TEST(MeshShapes, BoxAndCylinderBounds) {
  const TriangleMesh box = shapes::box(Vec3(2, 4, 6));
  EXPECT_TRUE(box.bounds_min().isApprox(Vec3(-1, -2, -3)));
  EXPECT_TRUE(box.bounds_max().isApprox(Vec3(1, 2, 3)));
  const TriangleMesh cyl = shapes::cylinder(3, 10);
  EXPECT_NEAR(cyl.bounds_min().z(), -5.0, 1e-12);
  EXPECT_NEAR(cyl.bounds_max().z(), 5.0, 1e-12);
  EXPECT_NEAR(cyl.bounds_max().x(), 3.0, 1e-12);
  EXPECT_LT(cyl.centroid().norm(), 1e-9);
  EXPECT_LT(shapes::sphere(4).centroid().norm(), 1e-9);
}

TEST(MeshShapes, TorusArcStartsAtMinusZAndSweepsTowardsMinusY) {
  const double big = 20, small = 2;
  const TriangleMesh arc = shapes::torus_arc(big, small, 90);
  // The start cap is around (0, 0, -R) and the end cap around (0, -R, 0).
  EXPECT_LE(min_distance(arc, Vec3(0, 0, -big)), small + 1e-9);
  EXPECT_LE(min_distance(arc, Vec3(0, -big, 0)), small + 1e-9);
  // Sweeping towards -y: nothing on the +y side (beyond the wire), nor above z = 0.
  EXPECT_LE(max_coordinate(arc, 1), 1e-9);
  EXPECT_LE(max_coordinate(arc, 2), 1e-9);
  EXPECT_NEAR(arc.bounds_min().y(), -(big + small), 1e-9);
  EXPECT_NEAR(arc.bounds_min().z(), -(big + small), 1e-9);
  EXPECT_LE(arc.bounds_max().x(), small + 1e-9);
  EXPECT_GE(arc.bounds_max().x(), 0.9 * small);
  const Vec3 c = arc.centroid();
  EXPECT_NEAR(c.x(), 0.0, 1e-9);
  EXPECT_LT(c.y(), -big / 2);
  EXPECT_LT(c.z(), -big / 2);

  // A half turn ends at (0, 0, +R); a 30° arc never reaches the -y side beyond R sin 30°.
  const TriangleMesh half = shapes::torus_arc(big, small, 180);
  EXPECT_LE(min_distance(half, Vec3(0, 0, big)), small + 1e-9);
  EXPECT_NEAR(half.bounds_min().y(), -(big + small), 1e-9);
  const TriangleMesh small_arc = shapes::torus_arc(big, small, 30);
  EXPECT_GE(small_arc.bounds_min().y(), -(big + small) * 0.5 - 1e-9);
}

TEST(MeshShapes, TorusArcRejectsNonPositiveAngles) {
  EXPECT_TRUE(shapes::torus_arc(20, 2, 0).empty());
  EXPECT_TRUE(shapes::torus_arc(20, 2, -90).empty());
}

// ---------------------------------------------------------------------------------------------
// TriangleMesh methods

TEST(MeshMethods, CentroidOfOffsetBox) {
  TriangleMesh box = shapes::box(Vec3(2, 4, 6));
  for (auto& v : box.vertices) v += Vec3(10, -5, 3);
  EXPECT_NEAR(box.volume(), 48.0, 1e-9);
  EXPECT_TRUE(box.centroid().isApprox(Vec3(10, -5, 3), 1e-12));
}

TEST(MeshMethods, CentroidIsVolumeWeightedNotVertexAverage) {
  // Two boxes of different sizes: eight vertices each, but very different volumes.
  TriangleMesh solid = shapes::box(Vec3(2, 2, 2));  // volume 8 at the origin
  solid.append(shapes::box(Vec3(1, 1, 1)).transformed(translation(10.0, 0.0, 0.0)));  // 1
  EXPECT_NEAR(solid.volume(), 9.0, 1e-12);
  EXPECT_NEAR(solid.centroid().x(), 10.0 / 9.0, 1e-12);
  // The vertex average would be 5 (eight vertices each).
}

TEST(MeshMethods, CentroidFallsBackToVertexAverage) {
  TriangleMesh flat;
  flat.vertices = {Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0)};
  flat.faces = {Eigen::Vector3i(0, 1, 2)};
  EXPECT_NEAR(flat.volume(), 0.0, 1e-12);
  EXPECT_TRUE(flat.centroid().isApprox(Vec3(4.0 / 3.0, 4.0 / 3.0, 0.0)));
}

TEST(MeshMethods, TransformMovesCentroidAndKeepsVolume) {
  TriangleMesh cyl = shapes::cylinder(2, 6);
  const double v = cyl.volume();
  const Mat4 m = translation(5.0, -3.0, 7.0) * rot_euler(30.0, 45.0, 60.0);
  const TriangleMesh copy = cyl.transformed(m);
  EXPECT_LT(cyl.centroid().norm(), 1e-9);  // transformed() leaves the original alone
  EXPECT_TRUE(copy.centroid().isApprox(Vec3(5, -3, 7), 1e-9));
  EXPECT_NEAR(copy.volume(), v, 1e-9 * v);
  cyl.transform(m);
  EXPECT_TRUE(cyl.centroid().isApprox(Vec3(5, -3, 7), 1e-9));
  // The cylinder axis (z) is rotated: its top-cap centre vertex goes to R·(0, 0, 3) + t.
  const Vec3 top = m.topLeftCorner<3, 3>() * Vec3(0, 0, 3) + Vec3(5, -3, 7);
  EXPECT_LT(min_distance(cyl, top), 1e-9);
}

TEST(MeshMethods, AppendShiftsIndices) {
  TriangleMesh a = shapes::box(Vec3(1, 1, 1));
  const TriangleMesh b = shapes::sphere(1).transformed(translation(5.0, 0.0, 0.0));
  const std::size_t nv = a.vertices.size(), nf = a.faces.size();
  const double expected = a.volume() + b.volume();
  a.append(b);
  EXPECT_EQ(a.vertices.size(), nv + b.vertices.size());
  EXPECT_EQ(a.faces.size(), nf + b.faces.size());
  EXPECT_NEAR(a.volume(), expected, 1e-9);
  EXPECT_EQ(watertight_problem(a), "");
}

TEST(MeshMethods, EmptyMesh) {
  const TriangleMesh empty;
  EXPECT_TRUE(empty.empty());
  EXPECT_EQ(empty.volume(), 0.0);
  EXPECT_EQ(empty.bounds_min(), Vec3::Zero());
  EXPECT_EQ(empty.bounds_max(), Vec3::Zero());
  EXPECT_EQ(empty.centroid(), Vec3::Zero());
}

// ---------------------------------------------------------------------------------------------
// I/O

class MeshIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           fmt::format("fabkit_mesh_test_{}_{}", static_cast<long>(::getpid()), info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path file(const std::string& name) const { return dir_ / name; }

  fs::path write_text(const std::string& name, const std::string& text) const {
    const fs::path p = file(name);
    std::ofstream out(p, std::ios::binary);
    out << text;
    return p;
  }

  static std::string slurp(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  }

  /// Number of entries in the test directory (to check that no temporary is left behind).
  std::size_t entries() const {
    return static_cast<std::size_t>(
        std::distance(fs::directory_iterator(dir_), fs::directory_iterator()));
  }

  fs::path dir_;
};

/// Face by face, the corner positions of `a` and `b` agree within `tol`.
void expect_same_triangles(const TriangleMesh& a, const TriangleMesh& b, double tol) {
  ASSERT_EQ(a.faces.size(), b.faces.size());
  for (std::size_t i = 0; i < a.faces.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const Vec3 pa = a.vertices[a.faces[i][c]];
      const Vec3 pb = b.vertices[b.faces[i][c]];
      ASSERT_LE((pa - pb).norm(), tol) << "face " << i << " corner " << c;
    }
  }
}

const char* const kTetraAscii =
    "solid tetra\n"
    "  facet normal 0 0 -1\n"
    "    outer loop\n"
    "      vertex 0 0 0\n"
    "      vertex 0 1 0\n"
    "      vertex 1 0 0\n"
    "    endloop\n"
    "  endfacet\n"
    "  facet normal 0 -1 0\n"
    "    outer loop\n"
    "      vertex 0 0 0\n"
    "      vertex 1 0 0\n"
    "      vertex 0 0 1\n"
    "    endloop\n"
    "  endfacet\n"
    "  facet normal -1 0 0\n"
    "    outer loop\n"
    "      vertex 0 0 0\n"
    "      vertex 0 0 1\n"
    "      vertex 0 1 0\n"
    "    endloop\n"
    "  endfacet\n"
    "  facet normal 0.577 0.577 0.577\n"
    "    outer loop\n"
    "      vertex 1 0 0\n"
    "      vertex 0 1 0\n"
    "      vertex 0 0 1\n"
    "    endloop\n"
    "  endfacet\n"
    "endsolid tetra\n";

TEST_F(MeshIo, ObjRoundTrip) {
  const TriangleMesh mesh =
      shapes::torus_arc(20, 2, 120).transformed(translation(1.5, -2.25, 1000.125));
  Diagnostics diags;
  const fs::path p = file("arc.obj");
  ASSERT_TRUE(write_obj(mesh, p, diags)) << diags.format();
  EXPECT_TRUE(diags.empty());
  EXPECT_EQ(entries(), 1u);  // no temporary left behind
  const auto back = read_mesh(p, diags);
  ASSERT_TRUE(back.has_value()) << diags.format();
  ASSERT_EQ(back->vertices.size(), mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    ASSERT_LE((back->vertices[i] - mesh.vertices[i]).norm(), 1e-4) << i;
  }
  EXPECT_EQ(back->faces, mesh.faces);
  EXPECT_EQ(watertight_problem(*back), "");
}

TEST_F(MeshIo, StlBinaryRoundTrip) {
  const TriangleMesh mesh = shapes::sphere(7.5).transformed(translation(-3.0, 4.0, 12.0));
  Diagnostics diags;
  const fs::path p = file("ball.STL");
  ASSERT_TRUE(write_stl(mesh, p, diags)) << diags.format();
  EXPECT_EQ(entries(), 1u);
  const std::string bytes = slurp(p);
  ASSERT_EQ(bytes.size(), 84 + 50 * mesh.faces.size());
  EXPECT_NE(bytes.substr(0, 5), "solid");
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);  // the test machine is little-endian
  EXPECT_EQ(count, mesh.faces.size());

  const auto back = read_mesh(p, diags);
  ASSERT_TRUE(back.has_value()) << diags.format();
  expect_same_triangles(mesh, *back, 1e-4);
  // Shared corners are welded back together, so the mesh is still closed.
  EXPECT_EQ(back->vertices.size(), mesh.vertices.size());
  EXPECT_EQ(watertight_problem(*back), "");
  EXPECT_NEAR(back->volume(), mesh.volume(), 1e-4 * mesh.volume());
}

TEST_F(MeshIo, OutputIsDeterministicAndOverwritesAtomically) {
  const TriangleMesh mesh = shapes::tube(1, 2, 3);
  Diagnostics diags;
  for (const char* name : {"t.obj", "t.stl"}) {
    const fs::path p = file(name);
    write_text(name, "old contents");
    const bool is_obj = std::string(name).ends_with(".obj");
    ASSERT_TRUE(is_obj ? write_obj(mesh, p, diags) : write_stl(mesh, p, diags));
    const std::string first = slurp(p);
    ASSERT_TRUE(is_obj ? write_obj(mesh, p, diags) : write_stl(mesh, p, diags));
    EXPECT_EQ(slurp(p), first) << name;
    EXPECT_NE(first, "old contents");
    EXPECT_FALSE(fs::exists(file(std::string(name) + ".tmp")));
  }
  EXPECT_TRUE(diags.empty()) << diags.format();
  // -0 and +0 are written alike.
  TriangleMesh neg = shapes::box(Vec3(1, 1, 1));
  TriangleMesh pos = neg;
  neg.vertices[0] = Vec3(-0.0, -0.5, -0.5);
  pos.vertices[0] = Vec3(0.0, -0.5, -0.5);
  ASSERT_TRUE(write_obj(neg, file("neg.obj"), diags));
  ASSERT_TRUE(write_obj(pos, file("pos.obj"), diags));
  EXPECT_EQ(slurp(file("neg.obj")), slurp(file("pos.obj")));
}

TEST_F(MeshIo, ReadsAsciiStl) {
  Diagnostics diags;
  const auto mesh = read_mesh(write_text("tetra.stl", kTetraAscii), diags);
  ASSERT_TRUE(mesh.has_value()) << diags.format();
  EXPECT_TRUE(diags.empty());
  EXPECT_EQ(mesh->faces.size(), 4u);
  EXPECT_EQ(mesh->vertices.size(), 4u);
  EXPECT_EQ(watertight_problem(*mesh), "");
  EXPECT_NEAR(mesh->volume(), 1.0 / 6.0, 1e-12);
}

TEST_F(MeshIo, BinaryStlWhoseHeaderSaysSolidIsReadAsBinary) {
  // Some exporters write "solid ..." into binary headers; the size check must win.
  const TriangleMesh box = shapes::box(Vec3(1, 2, 3));
  Diagnostics diags;
  const fs::path p = file("box.stl");
  ASSERT_TRUE(write_stl(box, p, diags));
  std::string bytes = slurp(p);
  bytes.replace(0, 12, "solid box   ");
  write_text("box.stl", bytes);
  const auto back = read_mesh(p, diags);
  ASSERT_TRUE(back.has_value()) << diags.format();
  EXPECT_EQ(back->faces.size(), 12u);
  EXPECT_NEAR(back->volume(), 6.0, 1e-6);
}

TEST_F(MeshIo, AsciiStlErrors) {
  {
    Diagnostics diags;
    std::string text = kTetraAscii;
    text.replace(text.find("vertex 0 1 0"), 12, "vertex 0 nan 0");
    EXPECT_FALSE(read_mesh(write_text("nan.stl", text), diags).has_value());
    ASSERT_TRUE(diags.has_errors());
    EXPECT_EQ(diags.items()[0].where.line, 5);
  }
  {
    Diagnostics diags;
    std::string text = kTetraAscii;
    text.replace(text.find("vertex 1 0 0"), 12, "vertex 1 0 inf");
    EXPECT_FALSE(read_mesh(write_text("inf.stl", text), diags).has_value());
    EXPECT_TRUE(diags.has_errors());
  }
  {
    Diagnostics diags;
    std::string text = kTetraAscii;
    text.replace(text.find("vertex 0 1 0"), 12, "vertex 0 1x 0");
    EXPECT_FALSE(read_mesh(write_text("bad.stl", text), diags).has_value());
    ASSERT_TRUE(diags.has_errors());
    EXPECT_EQ(diags.items()[0].code, codes::kMalformedInput);
    EXPECT_EQ(diags.items()[0].where.line, 5);
  }
  {
    Diagnostics diags;
    EXPECT_FALSE(
        read_mesh(write_text("empty.stl", "solid nothing\nendsolid nothing\n"), diags).has_value());
    EXPECT_TRUE(diags.has_errors());
  }
  {
    Diagnostics diags;
    EXPECT_FALSE(read_mesh(write_text("junk.stl", "this is not an stl file"), diags).has_value());
    ASSERT_TRUE(diags.has_errors());
    EXPECT_EQ(diags.items()[0].code, codes::kMalformedInput);
  }
}

TEST_F(MeshIo, BinaryStlWithNanIsAnError) {
  const TriangleMesh box = shapes::box(Vec3(1, 1, 1));
  Diagnostics diags;
  const fs::path p = file("nan.stl");
  ASSERT_TRUE(write_stl(box, p, diags));
  std::string bytes = slurp(p);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(bytes.data() + 84 + 50 * 3 + 12 + 4, &nan, 4);  // triangle 4, first vertex, y
  write_text("nan.stl", bytes);
  EXPECT_FALSE(read_mesh(p, diags).has_value());
  EXPECT_TRUE(diags.has_errors());
}

TEST_F(MeshIo, BinaryStlWithWrongSizeIsAnError) {
  const TriangleMesh box = shapes::box(Vec3(1, 1, 1));
  Diagnostics diags;
  const fs::path p = file("short.stl");
  ASSERT_TRUE(write_stl(box, p, diags));
  std::string bytes = slurp(p);
  bytes.resize(bytes.size() - 10);
  write_text("short.stl", bytes);
  EXPECT_FALSE(read_mesh(p, diags).has_value());
  ASSERT_TRUE(diags.has_errors());
  EXPECT_EQ(diags.items()[0].code, codes::kMalformedInput);
}

TEST_F(MeshIo, ObjFaceFormsNegativeIndicesAndPolygons) {
  const std::string text =
      "# unit cube corners used by a quad and a triangle\n"
      "mtllib cube.mtl\n"
      "o cube\n"
      "v 0 0 0\n"
      "v 1 0 0\n"
      "v 1 1 0\n"
      "v 0 1 0 1.0\n"
      "vt 0 0\n"
      "vn 0 0 1\n"
      "g side\n"
      "usemtl red\n"
      "s off\n"
      "f 1/1/1 2/1/1 3/1/1 4/1/1\n"  // quad -> 2 triangles
      "f 1//1 2//1 3//1\n"
      "f -4/1 -3/1 -2/1\n"  // = 1 2 3
      "v 0 0 1\n"
      "f -1 1 2  # trailing comment\n"  // = 5 1 2
      "l 1 2\n";
  Diagnostics diags;
  const auto mesh = read_mesh(write_text("cube.OBJ", text), diags);
  ASSERT_TRUE(mesh.has_value()) << diags.format();
  EXPECT_TRUE(diags.empty()) << diags.format();
  ASSERT_EQ(mesh->vertices.size(), 5u);
  ASSERT_EQ(mesh->faces.size(), 5u);
  EXPECT_EQ(mesh->faces[0], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh->faces[1], Eigen::Vector3i(0, 2, 3));
  EXPECT_EQ(mesh->faces[2], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh->faces[3], Eigen::Vector3i(0, 1, 2));
  EXPECT_EQ(mesh->faces[4], Eigen::Vector3i(4, 0, 1));
  EXPECT_EQ(mesh->vertices[4], Vec3(0, 0, 1));
}

TEST_F(MeshIo, MalformedObjReportsTheLine) {
  struct Case {
    const char* text;
    int line;
  };
  const Case cases[] = {
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 abc 3\nf 1 2 3\n", 4},
      {"v 0 0 0\nv 1 0 0\n\nv 0 1 0\nf 1 2 3\nf 1 2 4\n", 6},   // index past the end
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", 4},             // negative, too far back
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", 4},              // OBJ indices start at 1
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\n# c\nf 1 2\n", 5},           // too few corners
      {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 x3\n", 4},             // not a number
      {"v 0 0 0\nv 1 0 0\nv 0 1\nf 1 2 3\n", 3},                // too few coordinates
      {"v 0 0 0\r\nv 1 0 0\r\nv 0 1 0.5.5\r\nf 1 2 3\r\n", 3},  // CRLF, bad number
  };
  for (const auto& c : cases) {
    Diagnostics diags;
    const fs::path p = write_text("bad.obj", c.text);
    EXPECT_FALSE(read_mesh(p, diags).has_value()) << c.text;
    ASSERT_EQ(diags.size(), 1u) << c.text;
    const Diagnostic& d = diags.items()[0];
    EXPECT_EQ(d.severity, Severity::kError);
    EXPECT_EQ(d.code, codes::kMalformedInput) << c.text;
    EXPECT_EQ(d.where.file, p.string());
    EXPECT_EQ(d.where.line, c.line) << c.text;
    EXPECT_NE(d.format().find(fmt::format("{}:{}", p.string(), c.line)), std::string::npos)
        << d.format();
  }
}

TEST_F(MeshIo, ObjWithNonFiniteCoordinateOrNoFacesIsAnError) {
  {
    Diagnostics diags;
    EXPECT_FALSE(read_mesh(write_text("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"), diags));
    ASSERT_TRUE(diags.has_errors());
    EXPECT_EQ(diags.items()[0].where.line, 2);
  }
  {
    Diagnostics diags;
    EXPECT_FALSE(read_mesh(write_text("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), diags));
    EXPECT_TRUE(diags.has_errors());
  }
}

TEST_F(MeshIo, MissingFileAndUnsupportedExtension) {
  {
    Diagnostics diags;
    const fs::path p = file("missing.obj");
    EXPECT_FALSE(read_mesh(p, diags).has_value());
    ASSERT_EQ(diags.size(), 1u);
    EXPECT_EQ(diags.items()[0].code, codes::kUnreadableFile);
    EXPECT_NE(diags.items()[0].format().find(p.string()), std::string::npos);
  }
  {
    Diagnostics diags;
    EXPECT_FALSE(read_mesh(dir_ / "subdir.stl", diags).has_value());
    fs::create_directory(dir_ / "dir.stl");
    EXPECT_FALSE(read_mesh(dir_ / "dir.stl", diags).has_value());
    ASSERT_EQ(diags.size(), 2u);
    EXPECT_EQ(diags.items()[1].code, codes::kUnreadableFile);
  }
  {
    Diagnostics diags;
    const fs::path p = write_text("part.ply", "ply\n");
    EXPECT_FALSE(read_mesh(p, diags).has_value());
    ASSERT_EQ(diags.size(), 1u);
    EXPECT_EQ(diags.items()[0].code, codes::kUnreadableFile);
    const std::string msg = diags.items()[0].format();
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find(".obj"), std::string::npos) << msg;
    EXPECT_NE(msg.find(".stl"), std::string::npos) << msg;
  }
}

TEST_F(MeshIo, WriteIntoMissingDirectoryFailsCleanly) {
  const TriangleMesh box = shapes::box(Vec3(1, 1, 1));
  const fs::path missing = dir_ / "no" / "such" / "dir";
  for (const bool obj : {true, false}) {
    Diagnostics diags;
    const fs::path p = missing / (obj ? "box.obj" : "box.stl");
    EXPECT_FALSE(obj ? write_obj(box, p, diags) : write_stl(box, p, diags));
    ASSERT_TRUE(diags.has_errors());
    EXPECT_NE(diags.format().find(p.string()), std::string::npos) << diags.format();
    EXPECT_FALSE(fs::exists(p));
    EXPECT_FALSE(fs::exists(p.string() + ".tmp"));
  }
  EXPECT_EQ(entries(), 0u);
}

TEST_F(MeshIo, FailedRenameRemovesTheTemporary) {
  // The target is a non-empty directory, so the rename cannot replace it.
  const fs::path target = dir_ / "target.obj";
  fs::create_directories(target / "inside");
  Diagnostics diags;
  EXPECT_FALSE(write_obj(shapes::box(Vec3(1, 1, 1)), target, diags));
  EXPECT_TRUE(diags.has_errors());
  EXPECT_FALSE(fs::exists(dir_ / "target.obj.tmp"));
  EXPECT_TRUE(fs::is_directory(target));
}

TEST_F(MeshIo, RefusesToWriteEmptyOrInvalidMeshes) {
  Diagnostics diags;
  EXPECT_FALSE(write_obj(TriangleMesh{}, file("empty.obj"), diags));
  TriangleMesh bad = shapes::box(Vec3(1, 1, 1));
  bad.vertices[2].y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(write_stl(bad, file("nan.stl"), diags));
  TriangleMesh out_of_range = shapes::box(Vec3(1, 1, 1));
  out_of_range.faces[0][0] = 8;
  EXPECT_FALSE(write_obj(out_of_range, file("range.obj"), diags));
  EXPECT_EQ(diags.size(), 3u);
  EXPECT_EQ(entries(), 0u);
}

}  // namespace
}  // namespace fabkit

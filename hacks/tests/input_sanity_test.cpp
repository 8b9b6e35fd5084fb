// Input sanity through the library API (what the Python API and the server call): absurd or
// non-finite positions are refused like absurd sizes, naming the part and the quantity, and
// leave the assembly unchanged; a loose-primitive environment (the paper's
// Environment({"left": Rod, "right": Rod})) places each of its primitives where it is added,
// draws only those placed, and refuses connects to one not placed yet. (Design files: the
// reader's range checks, design_file_test.)
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::has_diagnostic;
using testing::make_part;

PrimitiveShape rod_shape(double radius, double length) {
  PrimitiveShape s;
  s.radius = radius;
  s.length = length;
  return s;
}

std::shared_ptr<Part> two_rods() {
  return std::make_shared<Part>(
      make_primitive_part({Primitive::make("left", PrimitiveType::kRod, rod_shape(5, 100)),
                           Primitive::make("right", PrimitiveType::kRod, rod_shape(5, 100))}));
}

TEST(InputSanity, AbsurdOrNonFinitePositionsAreRefused) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Vec3& pos : {Vec3(2e6, 0, 0), Vec3(0, -1.5e6, 0), Vec3(0, 0, nan), Vec3(inf, 0, 0)}) {
    SCOPED_TRACE(pos.transpose());
    const bool finite = pos.allFinite();
    const std::string problem = finite
                                    ? "is absurd: positions are in mm and may be at most 1e+06 mm"
                                    : "has a non-finite value";
    // A whole environment part.
    Assembly a;
    const auto rods = make_part("ClosetRods");
    ASSERT_TRUE(rods);
    const ConnectReport whole = a.add(rods, Frame(pos, Vec3::Zero()));
    EXPECT_FALSE(whole.accepted);
    EXPECT_TRUE(has_diagnostic(whole.diagnostics, codes::kInvalidValue, "add ClosetRods: frame"));
    EXPECT_TRUE(has_diagnostic(whole.diagnostics, codes::kInvalidValue, problem));
    EXPECT_EQ(a.part_count(), 0);
    // One primitive of a loose-primitive environment.
    const auto env = two_rods();
    const ConnectReport one = a.add(PrimitiveRef(env, "left"), Frame(pos, Vec3::Zero()));
    EXPECT_FALSE(one.accepted);
    EXPECT_TRUE(
        has_diagnostic(one.diagnostics, codes::kInvalidValue, "add Environment.left: frame"));
    EXPECT_TRUE(has_diagnostic(one.diagnostics, codes::kInvalidValue, problem));
    EXPECT_EQ(a.part_count(), 0);
  }
  // At the limit (1 km) is still a place.
  Assembly a;
  EXPECT_TRUE(a.add(make_part("ClosetRods"), Frame(Vec3(1e6, -1e6, 0), Vec3::Zero())).accepted);
}

TEST(InputSanity, LoosePrimitiveEnvironmentPlacesEveryPrimitive) {
  const auto env = two_rods();
  Assembly a;
  const Frame left(Vec3(0, 0, 0), Vec3(0, 90, 0));
  const Frame right(Vec3(300, 0, 50), Vec3(0, 90, 0));
  ASSERT_TRUE(a.add(PrimitiveRef(env, "left"), left).accepted);
  // Not placed yet: no connects, not drawn.
  auto hook = make_part("DoubleHook");
  const ConnectReport early = a.connect({hook, "hook2"}, {env, "right"});
  EXPECT_FALSE(early.accepted);
  EXPECT_TRUE(has_diagnostic(early.diagnostics, codes::kNotInAssembly, "right is not placed yet"))
      << early.diagnostics.format();
  ASSERT_EQ(a.part_count(), 1);
  const TriangleMesh only_left = a.node(PartId{0}).part->mesh;
  EXPECT_EQ(only_left.faces.size(), primitive_mesh(env->primitives[0]).faces.size());
  EXPECT_LT(only_left.bounds_max().x(), 100);  // the unplaced rod is not drawn at the origin
  ASSERT_TRUE(a.add(PrimitiveRef(env, "right"), right).accepted);
  EXPECT_EQ(a.part_count(), 1);  // one environment part, two primitives placed
  const Part& placed = *a.node(PartId{0}).part;
  EXPECT_EQ(placed.primitives[0].frame.pos, left.pos);
  EXPECT_EQ(placed.primitives[1].frame.pos, right.pos);
  // Drawn where they were placed: the right rod spans x 250…350 at z 50 (a rod's axis is its
  // z; turned 90° about y it lies along x).
  EXPECT_NEAR(placed.mesh.bounds_max().x(), 350, 1e-9);
  EXPECT_NEAR(placed.mesh.bounds_min().x(), -50, 1e-9);
  EXPECT_NEAR(placed.mesh.bounds_max().z(), 55, 1e-9);
  // The caller's part is unchanged (the assembly keeps its own copy).
  EXPECT_EQ(env->primitives[1].frame.pos, Vec3::Zero());
  // Each primitive is placed once.
  const ConnectReport twice = a.add(PrimitiveRef(env, "right"), right);
  EXPECT_FALSE(twice.accepted);
  EXPECT_TRUE(has_diagnostic(twice.diagnostics, codes::kDuplicateName, "already placed"));
  // Now both connect.
  EXPECT_TRUE(a.connect({hook, "hook2"}, {env, "right"}).accepted);
}

}  // namespace
}  // namespace fabkit::hacks

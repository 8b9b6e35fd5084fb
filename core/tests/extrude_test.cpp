#include "fabkit/core/extrude.h"

#include <gtest/gtest.h>

#include "fabkit/core/mesh_boolean.h"

namespace fabkit {
namespace {

Ring2 square(double half, bool clockwise) {
  Ring2 r = {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
  if (clockwise) std::reverse(r.begin(), r.end());
  return r;
}

TEST(Extrude, SquareWithHoleIsAClosedSolidOfTheRightVolume) {
  // Orientation must not matter: give the outer ring clockwise and the hole too.
  const std::vector<Ring2> rings = {square(10, true), square(4, true)};
  const TriangleMesh m = extrude_rings(rings, -1, 2);
  const SolidCheck c = check_solid(m);
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_NEAR(c.volume, (400 - 64) * 3, 1e-9);
}

TEST(Extrude, IslandInsideAHoleIsSolid) {
  const std::vector<Ring2> rings = {square(10, false), square(6, false), square(2, false)};
  const SolidCheck c = check_solid(extrude_rings(rings, 0, 1));
  EXPECT_TRUE(c.valid_solid()) << c.problems();
  EXPECT_NEAR(c.volume, 400 - 144 + 16, 1e-9);
  EXPECT_EQ(c.components, 2);
}

TEST(Extrude, SignedArea) {
  EXPECT_NEAR(signed_area(square(1, false)), 4, 1e-12);
  EXPECT_NEAR(signed_area(square(1, true)), -4, 1e-12);
}

}  // namespace
}  // namespace fabkit

#include "fabkit/core/three_mf.h"

#include <gtest/gtest.h>

#include <clocale>
#include <string>

#include "fabkit/core/mesh_boolean.h"

namespace fabkit {
namespace {

TEST(ThreeMf, RoundTripKeepsNamesMeshesAndPlacements) {
  std::vector<ThreeMfObject> objects = {
      {"joint 01", shapes::box(Vec3(10, 20, 30)), translation(50.0, 0.0, 15.0)},
      {"joint 02", shapes::cylinder(5, 12, 16), translation(0.0, 40.0, 6.0)},
  };
  Diagnostics d;
  const auto bytes = encode_3mf(objects, d);
  ASSERT_TRUE(bytes) << d.format();
  EXPECT_EQ(bytes->substr(0, 2), "PK");  // a zip package
  const auto back = decode_3mf(*bytes, "joints.3mf", d);
  ASSERT_TRUE(back) << d.format();
  ASSERT_EQ(back->size(), 2u);
  EXPECT_EQ((*back)[0].name, "joint 01");
  EXPECT_EQ((*back)[1].name, "joint 02");
  EXPECT_EQ((*back)[1].mesh.faces.size(), objects[1].mesh.faces.size());
  EXPECT_NEAR((*back)[0].transform(0, 3), 50, 1e-6);
  EXPECT_NEAR(check_solid((*back)[0].mesh).volume, 6000, 1e-3);
  EXPECT_TRUE(check_solid((*back)[1].mesh).valid_solid());
}

TEST(ThreeMf, LeavesTheLocaleAsItWas) {
  // lib3mf switches to the C locale; a host program (Python) must keep its own.
  const std::string before = std::setlocale(LC_ALL, nullptr);
  if (!std::setlocale(LC_ALL, "C.UTF-8")) GTEST_SKIP() << "no C.UTF-8 locale here";
  Diagnostics d;
  ASSERT_TRUE(encode_3mf({{"a", shapes::box(Vec3(1, 1, 1))}}, d));
  EXPECT_STREQ(std::setlocale(LC_CTYPE, nullptr), "C.UTF-8");
  std::setlocale(LC_ALL, before.c_str());
}

TEST(ThreeMf, GarbageIsMalformed) {
  Diagnostics d;
  EXPECT_FALSE(decode_3mf("not a zip", "x.3mf", d));
  EXPECT_NE(d.format().find("x.3mf: not a readable 3MF package"), std::string::npos);
}

TEST(ThreeMf, NonFiniteVertexIsRefused) {
  std::vector<ThreeMfObject> objects = {{"bad", shapes::box(Vec3(1, 1, 1))}};
  objects[0].mesh.vertices[0].x() = std::nan("");
  Diagnostics d;
  EXPECT_FALSE(encode_3mf(objects, d));
  EXPECT_NE(d.format().find("object 'bad' has a non-finite vertex"), std::string::npos);
}

}  // namespace
}  // namespace fabkit

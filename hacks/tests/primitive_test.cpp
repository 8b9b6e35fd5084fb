#include "fabkit/hacks/primitive.h"

#include <gtest/gtest.h>

#include "fabkit/hacks/connector_frame.h"
#include "fabkit/hacks/part.h"

namespace fabkit::hacks {
namespace {

PrimitiveShape rod_shape(double r, double l) {
  PrimitiveShape s;
  s.radius = r;
  s.length = l;
  return s;
}

TEST(Primitive, TypeNamesRoundTripAndAcceptPaperSpellings) {
  for (PrimitiveType t : {PrimitiveType::kRod,
                          PrimitiveType::kHook,
                          PrimitiveType::kRing,
                          PrimitiveType::kClip,
                          PrimitiveType::kTube,
                          PrimitiveType::kEdge,
                          PrimitiveType::kSurface,
                          PrimitiveType::kHemisphere}) {
    EXPECT_EQ(primitive_type_from_string(to_string(t)), t);
  }
  EXPECT_EQ(primitive_type_from_string("hole"), PrimitiveType::kRing);
  EXPECT_EQ(primitive_type_from_string("Hemi"), PrimitiveType::kHemisphere);
  EXPECT_FALSE(primitive_type_from_string("screw").has_value());
}

TEST(Primitive, OpenRodParametersAreBoundedAndOpen) {
  const Primitive rod = Primitive::make("rod", PrimitiveType::kRod, rod_shape(5, 100));
  const auto ps = rod.connector_params();
  ASSERT_EQ(ps.size(), 3u);
  EXPECT_EQ(ps[0].name, "t");
  EXPECT_EQ(ps[0].tag, ParamTag::kBoundedAndOpen);
  EXPECT_TRUE(ps[0].critical_dim);
  EXPECT_DOUBLE_EQ(ps[0].init, 0.5);
  EXPECT_EQ(ps[1].name, "phi");
  EXPECT_DOUBLE_EQ(ps[1].lo, 45);
  EXPECT_DOUBLE_EQ(ps[1].hi, 135);
  // Where around the rod the contact is: any angle (the reference fixes it at 0).
  EXPECT_EQ(ps[2].name, "psi");
  EXPECT_EQ(ps[2].tag, ParamTag::kUnbounded);
  EXPECT_DOUBLE_EQ(ps[2].init, 0);
}

TEST(Primitive, ClosedRodClampsItsParameters) {
  Primitive rod = Primitive::make("rod", PrimitiveType::kRod, rod_shape(3, 72));
  rod.is_open = false;
  for (const auto& p : rod.connector_params()) {
    EXPECT_EQ(p.tag, p.name == "psi" ? ParamTag::kUnbounded : ParamTag::kBoundedAndClamped);
  }
}

TEST(Primitive, HookTagsAndRanges) {
  PrimitiveShape s;
  s.arc_radius = 20;
  s.arc_angle = 180;
  s.thickness = 3.1;
  Primitive hook = Primitive::make("hook1", PrimitiveType::kHook, s);
  hook.theta_range = std::array<double, 2>{0, 270};
  auto ps = hook.connector_params();
  ASSERT_EQ(ps.size(), 1u);
  EXPECT_DOUBLE_EQ(ps[0].init, 90);
  EXPECT_DOUBLE_EQ(ps[0].hi, 270);
  EXPECT_EQ(ps[0].tag, ParamTag::kBoundedAndOpen);
  // A full circle of hook wire (a ring-shaped hook) wraps around.
  s.arc_angle = 360;
  EXPECT_EQ(Primitive::make("h", PrimitiveType::kHook, s).connector_params()[0].tag,
            ParamTag::kUnbounded);
}

TEST(Primitive, RingsAreClosedAndSpinFreely) {
  PrimitiveShape s;
  s.arc_radius = 14.82;
  s.thickness = 4.5;
  Primitive ring = Primitive::make("ring", PrimitiveType::kRing, s);
  EXPECT_TRUE(ring.closed_for_connect());
  EXPECT_EQ(ring.connector_params()[0].tag, ParamTag::kUnbounded);
  ring.flex = true;
  const auto ps = ring.connector_params();
  ASSERT_EQ(ps.size(), 2u);
  EXPECT_EQ(ps[1].tag, ParamTag::kBoundedAndOpen);
  EXPECT_DOUBLE_EQ(ps[1].lo, 30);
  EXPECT_DOUBLE_EQ(ps[1].hi, 150);
}

TEST(Primitive, ClipParametersArePinnedUnderPhysicsAndSingleConnection) {
  PrimitiveShape s;
  s.width = 17;
  s.height = 8;
  s.thickness = 1;
  s.dist = 13;
  s.open_gap = 12;
  const Primitive clip = Primitive::make("clip", PrimitiveType::kClip, s);
  EXPECT_TRUE(clip.single_connection());
  EXPECT_TRUE(clip.connector_params()[0].fixed_under_physics);
  EXPECT_EQ(clip.connector_critical_dim(), std::vector<double>{8.5});
}

TEST(Primitive, CriticalDimensions) {
  EXPECT_EQ(Primitive::make("r", PrimitiveType::kRod, rod_shape(5, 100)).critical_dim(),
            std::vector<double>{100});
  PrimitiveShape surf;
  surf.width = 300;
  surf.length = 400;
  const Primitive s = Primitive::make("s", PrimitiveType::kSurface, surf);
  EXPECT_EQ(s.critical_dim(), (std::vector<double>{300, 400}));
  EXPECT_EQ(s.connector_critical_dim(), (std::vector<double>{150, 200}));
  // Surfaces are closed by default: things resting on them are clamped to the surface.
  EXPECT_EQ(s.connector_params()[0].tag, ParamTag::kBoundedAndClamped);
  EXPECT_EQ(s.connector_params()[2].tag, ParamTag::kUnbounded);
}

TEST(Primitive, ValidateReportsBadSizes) {
  Diagnostics d;
  Primitive::make("rod", PrimitiveType::kRod, rod_shape(-5, 100)).validate("Env.rod", d);
  ASSERT_TRUE(d.has_errors());
  EXPECT_NE(d.items()[0].message.find("Env.rod: rod radius -5 mm must be positive"),
            std::string::npos)
      << d.format();
  Diagnostics nan;
  Primitive::make("rod", PrimitiveType::kRod, rod_shape(std::nan(""), 100)).validate("X", nan);
  EXPECT_NE(nan.format().find("not a finite number"), std::string::npos);
  Diagnostics absurd;
  Primitive::make("rod", PrimitiveType::kRod, rod_shape(5, 1e9)).validate("X", absurd);
  EXPECT_NE(absurd.format().find("absurd"), std::string::npos);
  Diagnostics ok;
  Primitive::make("rod", PrimitiveType::kRod, rod_shape(5, 100)).validate("X", ok);
  EXPECT_TRUE(ok.empty());
}

TEST(Primitive, DescribeNamesTheSizes) {
  PrimitiveShape s;
  s.arc_radius = 11.6;
  s.arc_angle = 270;
  s.thickness = 2;
  EXPECT_EQ(Primitive::make("h", PrimitiveType::kHook, s).describe(),
            "hook (arc angle 270°, arc radius 11.6 mm, thickness 2 mm)");
}

}  // namespace
}  // namespace fabkit::hacks

namespace fabkit::hacks {
namespace {

// Every primitive type has a display mesh around its connector points.
TEST(PrimitiveMesh, EveryTypeHasAClosedMeshAroundItsConnectors) {
  std::vector<Primitive> all;
  auto shape = [](std::initializer_list<std::pair<const char*, double>> fields) {
    PrimitiveShape s;
    for (auto [name, value] : fields) *shape_field(s, name) = value;
    return s;
  };
  const Frame f(Vec3(10, -20, 30), Vec3(15, 25, 35));
  all.push_back(
      Primitive::make("rod", PrimitiveType::kRod, shape({{"radius", 5}, {"length", 100}}), f));
  all.push_back(Primitive::make("hook",
                                PrimitiveType::kHook,
                                shape({{"arc_radius", 20}, {"arc_angle", 210}, {"thickness", 3}}),
                                f));
  all.push_back(Primitive::make(
      "ring", PrimitiveType::kRing, shape({{"arc_radius", 15}, {"thickness", 4}}), f));
  all.push_back(Primitive::make("tube",
                                PrimitiveType::kTube,
                                shape({{"inner_radius", 8}, {"thickness", 2}, {"length", 200}}),
                                f));
  all.push_back(Primitive::make(
      "edge", PrimitiveType::kEdge, shape({{"width", 100}, {"length", 200}, {"height", 2}}), f));
  all.push_back(Primitive::make(
      "surface", PrimitiveType::kSurface, shape({{"width", 300}, {"length", 400}}), f));
  all.push_back(
      Primitive::make("hemisphere", PrimitiveType::kHemisphere, shape({{"radius", 9}}), f));
  all.push_back(Primitive::make(
      "clip",
      PrimitiveType::kClip,
      shape({{"width", 17}, {"height", 8}, {"dist", 13}, {"open_gap", 12}, {"thickness", 1}}),
      f));
  for (const Primitive& p : all) {
    SCOPED_TRACE(p.name);
    const TriangleMesh m = primitive_mesh(p);
    ASSERT_FALSE(m.empty());
    EXPECT_GT(m.volume(), 0);
    // The connector point at the default parameters lies on or near the mesh's bounds.
    std::vector<double> q;
    for (const ParamSpec& s : p.connector_params()) q.push_back(s.init);
    const Vec3 c = connector_frame<double>(p, q.data()).topRightCorner<3, 1>();
    const Vec3 lo = m.bounds_min().array() - 1.0;
    const Vec3 hi = m.bounds_max().array() + 1.0;
    EXPECT_TRUE((c.array() >= lo.array()).all() && (c.array() <= hi.array()).all())
        << c.transpose() << " not in [" << lo.transpose() << "] [" << hi.transpose() << "]";
  }
}

}  // namespace
}  // namespace fabkit::hacks

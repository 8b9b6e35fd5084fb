// Connector frames against the reference's Appendix A vectors.
#include "fabkit/hacks/connector_frame.h"

#include <gtest/gtest.h>

#include <vector>

namespace fabkit::hacks {
namespace {

const Frame kBase(Vec3(1, 2, 3), Vec3(10, 20, 30));

Primitive make(PrimitiveType type, PrimitiveShape shape, bool flex = false, bool ctl = false) {
  Primitive p = Primitive::make("p", type, shape, kBase);
  p.flex = flex;
  p.centerline = ctl;
  return p;
}

struct Vector {
  const char* name;
  Primitive primitive;
  std::vector<double> q;
  Vec3 euler;      // parametric_frame rot (mod 360)
  double m[3][4];  // connectorFrame matrix, first three rows
};

void check(const Vector& v) {
  SCOPED_TRACE(v.name);
  // The reference's RodMCF is ours at ψ = 0 (its contact is one line on the rod); every other
  // parameterisation has the reference's parameters.
  ASSERT_EQ(static_cast<int>(v.q.size()) + (v.primitive.connector_kind() == ConnectorKind::kRod),
            connector_dof(v.primitive.connector_kind()));
  std::vector<double> q = v.q;
  q.resize(static_cast<std::size_t>(connector_dof(v.primitive.connector_kind())), 0.0);
  const Mat4 c = connector_frame<double>(v.primitive, q.data());
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(c(r, k), v.m[r][k], 2e-6) << r << "," << k;
  }
  const Frame f = Frame::from_matrix(c);
  for (int i = 0; i < 3; ++i) {
    double d = std::fmod(std::abs(f.rot[i] - v.euler[i]), 360.0);
    EXPECT_LT(std::min(d, 360 - d), 1e-4) << "euler " << i << " got " << f.rot[i];
  }
}

PrimitiveShape rod_shape_of(double r, double l) {
  PrimitiveShape s;
  s.radius = r;
  s.length = l;
  return s;
}
PrimitiveShape hook(double r, double angle, double th) {
  PrimitiveShape s;
  s.arc_radius = r;
  s.arc_angle = angle;
  s.thickness = th;
  return s;
}
PrimitiveShape tube(double ri, double th, double l) {
  PrimitiveShape s;
  s.inner_radius = ri;
  s.thickness = th;
  s.length = l;
  return s;
}

TEST(ConnectorFrame, RodMatchesReference) {
  check({"Rod",
         make(PrimitiveType::kRod, rod_shape_of(5, 100)),
         {0.3, 70},
         {260, 20, 30},
         {{0.813798, -0.204874, -0.543838, -8.775294},
          {0.469846, -0.318796, 0.823173, 6.052254},
          {-0.34202, -0.925417, -0.163176, -14.692452}}});
}

TEST(ConnectorFrame, RodCenterlineMatchesReference) {
  check({"RodCtl",
         make(PrimitiveType::kRod, rod_shape_of(5, 100), false, true),
         {0.3},
         {280, 20, 30},
         {{0.813798, -0.378522, -0.44097, -6.570446},
          {0.469846, -0.018028, 0.882564, 1.639434},
          {-0.34202, -0.925417, 0.163176, -15.508332}}});
}

TEST(ConnectorFrame, HookMatchesReference) {
  check({"Hook",
         make(PrimitiveType::kHook, hook(20, 180, 3)),
         {60},
         {310, 20, 30},
         {{0.813798, -0.548295, -0.19263, 4.274705},
          {0.469846, 0.425669, 0.773337, -11.146731},
          {-0.34202, -0.719846, 0.604023, -7.268387}}});
}

TEST(ConnectorFrame, HookFlexMatchesReference) {
  check({"HookFlex",
         make(PrimitiveType::kHook, hook(20, 180, 3), true),
         {60, 100},
         {312.921409, 27.504875, 37.229423},
         {{0.706224, -0.681279, -0.19263, 4.274705},
          {0.536625, 0.337614, 0.773337, -11.146731},
          {-0.461824, -0.649519, 0.604023, -7.268387}}});
}

TEST(ConnectorFrame, RingMatchesReference) {
  check({"Ring",
         make(PrimitiveType::kRing, hook(15, 0, 4)),
         {200},
         {170, 20, 30},
         {{0.813798, 0.543838, -0.204874, 3.253615},
          {0.469846, -0.823173, -0.318796, 5.506754},
          {-0.34202, 0.163176, -0.925417, 13.179582}}});
}

TEST(ConnectorFrame, RingFlexMatchesReference) {
  check({"RingFlex",
         make(PrimitiveType::kRing, hook(15, 0, 4), true),
         {200, 120},
         {161.350658, 12.392658, 359.72501},
         {{0.976689, 0.064079, -0.204874, 3.253615},
          {-0.004688, -0.947812, -0.318796, 5.506754},
          {-0.21461, 0.312325, -0.925417, 13.179582}}});
}

TEST(ConnectorFrame, RingCenterlineMatchesReference) {
  check({"RingCtl",
         make(PrimitiveType::kRing, hook(15, 0, 4), false, true),
         {30, 250},
         {264.511681, 49.367885, 37.66203},
         {{0.515508, -0.53958, -0.665661, 1},
          {0.397885, -0.537282, 0.743651, 2},
          {-0.758906, -0.648214, -0.062283, 3}}});
}

TEST(ConnectorFrame, TubeMatchesReference) {
  check({"Tube",
         make(PrimitiveType::kTube, tube(8, 2, 200)),
         {0.7, 45},
         {262.218496, 20.930028, 341.792941},
         {{0.887254, -0.378522, 0.263629, 13.5046},
          {-0.291836, -0.018028, 0.956299, -6.841853},
          {-0.357228, -0.925417, -0.126462, 41.281283}}});
}

TEST(ConnectorFrame, TubeCenterlineMatchesReference) {
  check({"TubeCtl",
         make(PrimitiveType::kTube, tube(8, 2, 200), false, true),
         {0.7, 45},
         {262.218496, 20.930028, 341.792941},
         {{0.887254, -0.378522, 0.263629, 14.031858},
          {-0.291836, -0.018028, 0.956299, -4.929256},
          {-0.357228, -0.925417, -0.126462, 41.028359}}});
}

TEST(ConnectorFrame, ClipMatchesReference) {
  PrimitiveShape s;
  s.height = 30;
  s.width = 10;
  s.open_gap = 5;
  s.dist = 3;
  s.thickness = 1;
  check({"Clip",
         make(PrimitiveType::kClip, s),
         {0.25},
         {10, 20, 30},
         {{0.813798, -0.44097, 0.378522, -1.838917},
          {0.469846, 0.882564, 0.018028, 1.864788},
          {-0.34202, 0.163176, 0.925417, -3.940624}}});
}

TEST(ConnectorFrame, EdgeMatchesReference) {
  PrimitiveShape s;
  s.width = 100;
  s.length = 200;
  s.height = 2;
  check({"Edge",
         make(PrimitiveType::kEdge, s),
         {0.8},
         {10, 20, 30},
         {{0.813798, -0.44097, 0.378522, 27.77938},
          {0.469846, 0.882564, 0.018028, 74.318985},
          {-0.34202, 0.163176, 0.925417, -9.362413}}});
}

TEST(ConnectorFrame, SurfaceMatchesReference) {
  PrimitiveShape s;
  s.width = 300;
  s.length = 400;
  check({"Surface",
         make(PrimitiveType::kSurface, s),
         {0.2, 0.9, 33},
         {19.247705, 11.41829, 63.174777},
         {{0.442339, -0.813054, 0.378522, 91.53929},
          {0.874725, 0.484284, 0.018028, 156.607082},
          {-0.19797, 0.323128, 0.925417, -36.99112}}});
}

TEST(ConnectorFrame, HemisphereMatchesReference) {
  PrimitiveShape s;
  s.radius = 9;
  check({"Hemisphere",
         make(PrimitiveType::kHemisphere, s),
         {150, 200, 40},
         {342.586617, 320.229151, 267.211863},
         {{-0.037387, 0.943728, 0.328601, -2.41269},
          {-0.767699, -0.237632, 0.595121, -3.31034},
          {0.639719, -0.230017, 0.733384, -3.415125}}});
}

// The connector frame is a rigid transform for any parameters, including out of bounds.
TEST(ConnectorFrame, AlwaysRigid) {
  Primitive p = make(PrimitiveType::kHemisphere, [] {
    PrimitiveShape s;
    s.radius = 9;
    return s;
  }());
  const double q[] = {300, -20, 777};
  const Mat4 c = connector_frame<double>(p, q);
  const Mat3 r = c.topLeftCorner<3, 3>();
  EXPECT_TRUE((r * r.transpose()).isApprox(Mat3::Identity(), 1e-12));
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

}  // namespace
}  // namespace fabkit::hacks

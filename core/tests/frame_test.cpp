#include "fabkit/core/frame.h"

#include <gtest/gtest.h>

namespace fabkit {
namespace {

void expect_matrix_near(const Mat4& actual, const Mat4& expected, double tol) {
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) {
      EXPECT_NEAR(actual(r, c), expected(r, c), tol) << "entry (" << r << ", " << c << ")";
    }
  }
}

// Reference Appendix A: M(Frame([1,2,3],[10,20,30])).
TEST(Frame, MatrixMatchesReferenceVector) {
  Mat4 expected;
  expected << 0.813798, -0.44097, 0.378522, 1.0,  //
      0.469846, 0.882564, 0.018028, 2.0,          //
      -0.34202, 0.163176, 0.925417, 3.0,          //
      0, 0, 0, 1;
  expect_matrix_near(Frame(Vec3(1, 2, 3), Vec3(10, 20, 30)).matrix(), expected, 1e-6);
}

TEST(Frame, RotationOrderIsRzRyRx) {
  const Frame f(Vec3::Zero(), Vec3(90, 0, 0));
  // Rx(90) maps y to z.
  EXPECT_TRUE(f.apply(Vec3::UnitY()).isApprox(Vec3::UnitZ(), 1e-12));
  const Frame g(Vec3::Zero(), Vec3(90, 0, 90));
  // Rz(90)·Rx(90), the environment rods of the examples: the rod axis (local z) runs along +x
  // and the rod connector side (local +y) faces up.
  EXPECT_TRUE(g.apply(Vec3::UnitZ()).isApprox(Vec3::UnitX(), 1e-12));
  EXPECT_TRUE(g.apply(Vec3::UnitY()).isApprox(Vec3::UnitZ(), 1e-12));
}

TEST(Frame, EulerRoundTripReducesModulo360) {
  const Frame f(Vec3(4, 5, 6), Vec3(-90, 30, 200));
  const Frame g = Frame::from_matrix(f.matrix());
  EXPECT_NEAR(g.rot.x(), 270, 1e-9);
  EXPECT_NEAR(g.rot.y(), 30, 1e-9);
  EXPECT_NEAR(g.rot.z(), 200, 1e-9);
  EXPECT_TRUE(g.pos.isApprox(f.pos));
}

// At gimbal lock (the frame's x axis vertical, the middle angle ±90°) only the difference or
// sum of the other two angles is determined; the frame must still come back as the same
// rotation. (Environments written with rot [a, 90, c] are common: a rail along x.)
TEST(Frame, EulerRoundTripHoldsAtGimbalLock) {
  for (const double b : {90.0, -90.0, 270.0}) {
    for (const double a : {0.0, 30.0, -75.0, 180.0}) {
      for (const double c : {0.0, 45.0, 200.0}) {
        const Frame f(Vec3(1, -2, 3), Vec3(a, b, c));
        expect_matrix_near(Frame::from_matrix(f.matrix()).matrix(), f.matrix(), 1e-12);
      }
    }
  }
  // Exactly locked, as products of exact quarter turns give it (cos 90° is not 0 in floating
  // point, so frames built from angles are a hair away from the lock): x axis straight down.
  for (const double c : {0.0, 30.0, 135.0, 250.0}) {
    const double cs = std::cos(c * kDegToRad), sn = std::sin(c * kDegToRad);
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() << 0, -sn, cs, 0, cs, sn, -1, 0, 0;
    expect_matrix_near(Frame::from_matrix(m).matrix(), m, 1e-12);
    m.topLeftCorner<3, 3>() << 0, -sn, -cs, 0, cs, -sn, 1, 0, 0;  // x axis straight up
    expect_matrix_near(Frame::from_matrix(m).matrix(), m, 1e-12);
  }
  // Composition through a lock: a turn about the vertical of a rail along x.
  const Frame turn(Vec3::Zero(), Vec3(0, 0, 37));
  const Frame rail(Vec3(5, 0, 1200), Vec3(0, 90, 0));
  expect_matrix_near((turn * rail).matrix(), turn.matrix() * rail.matrix(), 1e-12);
}

TEST(Frame, CompositionAndInverse) {
  const Frame a(Vec3(1, 2, 3), Vec3(10, 20, 30));
  const Frame b(Vec3(-4, 0.5, 7), Vec3(-35, 80, 15));
  expect_matrix_near((a * b).matrix(), a.matrix() * b.matrix(), 1e-9);
  expect_matrix_near((a * a.inverse()).matrix(), Mat4::Identity(), 1e-9);
  const Vec3 p(3, -2, 9);
  EXPECT_TRUE(a.inverse().apply(a.apply(p)).isApprox(p, 1e-12));
}

// Reference §1.2: the symmetry-aware difference of one Euler component.
TEST(Frame, SymmetricAngleDifference) {
  EXPECT_DOUBLE_EQ(symmetric_angle_difference(123, 0), 0);      // ignored
  EXPECT_DOUBLE_EQ(symmetric_angle_difference(350, 360), -10);  // wraps into [-180, 180]
  EXPECT_DOUBLE_EQ(symmetric_angle_difference(-350, 360), 10);
  EXPECT_DOUBLE_EQ(symmetric_angle_difference(170, 360), 170);
  EXPECT_DOUBLE_EQ(symmetric_angle_difference(170, 180), -10);   // half-turn symmetric
  EXPECT_DOUBLE_EQ(symmetric_angle_difference(-190, 180), 170);  // |d| > s: Python modulo
  EXPECT_DOUBLE_EQ(symmetric_angle_difference(90, 180), 90);
}

TEST(Frame, FrameDifferenceUsesPeriods) {
  const Frame a(Vec3(1, 2, 3), Vec3(350, 10, 90));
  const Frame b(Vec3(0, 0, 0), Vec3(10, 190, 0));
  const Vec6 d = frame_difference(a, b, Vec3(360, 180, 0));
  EXPECT_DOUBLE_EQ(d[0], 1);
  EXPECT_DOUBLE_EQ(d[3], -20);
  EXPECT_DOUBLE_EQ(d[4], 0);  // 10 - 190 = -180 is a half turn
  EXPECT_DOUBLE_EQ(d[5], 0);
}

TEST(Frame, Wrap360) {
  EXPECT_DOUBLE_EQ(wrap_360(-90), 270);
  EXPECT_DOUBLE_EQ(wrap_360(720), 0);
  EXPECT_DOUBLE_EQ(wrap_360(359.5), 359.5);
  EXPECT_LT(wrap_360(-1e-18), 360.0);
}

}  // namespace
}  // namespace fabkit

#pragma once
/// Rigid frames as the FabHaL papers and the reference implementation spell them.
///
/// A Frame is a position in mm plus Euler angles [a, b, c] in degrees with
/// R = Rz(c) · Ry(b) · Rx(a) (extrinsic x-y-z; array order roll, pitch, yaw).
/// The templated helpers work on any scalar so that solvers can differentiate through them
/// (ceres::Jet); Euler angles are an input/output format only.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <numbers>
#include <string>

namespace fabkit {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Mat4 = Eigen::Matrix4d;
template <class T>
using Mat4T = Eigen::Matrix<T, 4, 4>;
template <class T>
using Mat3T = Eigen::Matrix<T, 3, 3>;
template <class T>
using Vec3T = Eigen::Matrix<T, 3, 1>;
using Vec6 = Eigen::Matrix<double, 6, 1>;

inline constexpr double kDegToRad = std::numbers::pi / 180.0;
inline constexpr double kRadToDeg = 180.0 / std::numbers::pi;

/// Homogeneous translation T(x, y, z), mm.
template <class T>
Mat4T<T> translation(const T& x, const T& y, const T& z) {
  Mat4T<T> m = Mat4T<T>::Identity();
  m(0, 3) = x;
  m(1, 3) = y;
  m(2, 3) = z;
  return m;
}

/// Elementary rotation about x by `deg` degrees, as a homogeneous matrix.
template <class T>
Mat4T<T> rot_x(const T& deg) {
  using std::cos;
  using std::sin;
  const T r = deg * T(kDegToRad);
  Mat4T<T> m = Mat4T<T>::Identity();
  m(1, 1) = cos(r);
  m(1, 2) = -sin(r);
  m(2, 1) = sin(r);
  m(2, 2) = cos(r);
  return m;
}

/// Elementary rotation about y by `deg` degrees, as a homogeneous matrix.
template <class T>
Mat4T<T> rot_y(const T& deg) {
  using std::cos;
  using std::sin;
  const T r = deg * T(kDegToRad);
  Mat4T<T> m = Mat4T<T>::Identity();
  m(0, 0) = cos(r);
  m(0, 2) = sin(r);
  m(2, 0) = -sin(r);
  m(2, 2) = cos(r);
  return m;
}

/// Elementary rotation about z by `deg` degrees, as a homogeneous matrix.
template <class T>
Mat4T<T> rot_z(const T& deg) {
  using std::cos;
  using std::sin;
  const T r = deg * T(kDegToRad);
  Mat4T<T> m = Mat4T<T>::Identity();
  m(0, 0) = cos(r);
  m(0, 1) = -sin(r);
  m(1, 0) = sin(r);
  m(1, 1) = cos(r);
  return m;
}

/// R(a, b, c) = Rz(c) · Ry(b) · Rx(a), degrees, as a homogeneous matrix.
template <class T>
Mat4T<T> rot_euler(const T& a, const T& b, const T& c) {
  return rot_z(c) * rot_y(b) * rot_x(a);
}

/// Inverse of a rigid homogeneous matrix (rotation transposed, translation rotated back).
template <class T>
Mat4T<T> rigid_inverse(const Mat4T<T>& m) {
  Mat4T<T> inv = Mat4T<T>::Identity();
  inv.template topLeftCorner<3, 3>() = m.template topLeftCorner<3, 3>().transpose();
  inv.template topRightCorner<3, 1>() =
      -(m.template topLeftCorner<3, 3>().transpose() * m.template topRightCorner<3, 1>());
  return inv;
}

/// A rigid transform x ↦ R·x + t. Solvers use it instead of 4×4 matrices: composing costs
/// a third as much, and right-multiplying by an elementary motion touches two columns.
template <class T>
struct Rigid {
  Mat3T<T> R = Mat3T<T>::Identity();
  Vec3T<T> t = Vec3T<T>::Zero();

  /// From a rigid homogeneous matrix (converted to T).
  static Rigid from_matrix(const Mat4& m) {
    Rigid r;
    r.R = m.topLeftCorner<3, 3>().cast<T>();
    r.t = m.topRightCorner<3, 1>().cast<T>();
    return r;
  }
  Mat4T<T> matrix() const {
    Mat4T<T> m = Mat4T<T>::Identity();
    m.template topLeftCorner<3, 3>() = R;
    m.template topRightCorner<3, 1>() = t;
    return m;
  }
  Rigid operator*(const Rigid& o) const {
    Rigid r;
    r.R = R * o.R;
    r.t = R * o.t + t;
    return r;
  }
  /// this · o for a constant o: cheaper than operator* when T carries derivatives.
  Rigid then(const Rigid<double>& o) const {
    Rigid r;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        r.R(i, j) = R(i, 0) * o.R(0, j) + R(i, 1) * o.R(1, j) + R(i, 2) * o.R(2, j);
      }
      r.t[i] = R(i, 0) * o.t[0] + R(i, 1) * o.t[1] + R(i, 2) * o.t[2] + t[i];
    }
    return r;
  }
  /// The same transform with another scalar type (no derivatives).
  template <class U>
  Rigid<U> cast() const {
    Rigid<U> r;
    r.R = R.template cast<U>();
    r.t = t.template cast<U>();
    return r;
  }
  Rigid inverse() const {
    Rigid r;
    r.R = R.transpose();
    r.t = -(r.R * t);
    return r;
  }
  /// this ← this · T(x, y, z)
  Rigid& translate(const T& x, const T& y, const T& z) {
    t += R.col(0) * x + R.col(1) * y + R.col(2) * z;
    return *this;
  }
  /// this ← this · Rx(deg)
  Rigid& rotate_x(const T& deg) {
    using std::cos;
    using std::sin;
    return rotate_x(deg, cos(deg * T(kDegToRad)), sin(deg * T(kDegToRad)));
  }
  /// this ← this · Rx(deg), whose cosine c and sine s the caller already has.
  Rigid& rotate_x(const T& /*deg*/, const T& c, const T& s) {
    const Vec3T<T> c1 = R.col(1);
    const Vec3T<T> c2 = R.col(2);
    R.col(1) = c1 * c + c2 * s;
    R.col(2) = c2 * c - c1 * s;
    return *this;
  }
  /// this ← this · Ry(deg)
  Rigid& rotate_y(const T& deg) {
    using std::cos;
    using std::sin;
    return rotate_y(deg, cos(deg * T(kDegToRad)), sin(deg * T(kDegToRad)));
  }
  /// this ← this · Ry(deg), whose cosine c and sine s the caller already has.
  Rigid& rotate_y(const T& /*deg*/, const T& c, const T& s) {
    const Vec3T<T> c0 = R.col(0);
    const Vec3T<T> c2 = R.col(2);
    R.col(0) = c0 * c - c2 * s;
    R.col(2) = c0 * s + c2 * c;
    return *this;
  }
  /// this ← this · Rz(deg)
  Rigid& rotate_z(const T& deg) {
    using std::cos;
    using std::sin;
    const T c = cos(deg * T(kDegToRad));
    const T s = sin(deg * T(kDegToRad));
    const Vec3T<T> c0 = R.col(0);
    const Vec3T<T> c1 = R.col(1);
    R.col(0) = c0 * c + c1 * s;
    R.col(1) = c1 * c - c0 * s;
    return *this;
  }
};

/// Euler angles [a, b, c] in degrees of a rotation matrix, each reduced into [0, 360).
/// a = atan2(R21, R22), b = -asin(R20), c = atan2(R10, R00), as in the reference.
Vec3 euler_from_rotation(const Mat3& r);

/// Reduces an angle in degrees into [0, 360).
double wrap_360(double deg);

/// A placement: `pos` in mm, `rot` = Euler angles [a, b, c] in degrees (R = Rz(c)·Ry(b)·Rx(a)).
struct Frame {
  Vec3 pos = Vec3::Zero();
  Vec3 rot = Vec3::Zero();

  Frame() = default;
  Frame(const Vec3& position, const Vec3& rotation_deg) : pos(position), rot(rotation_deg) {}

  /// 4×4 homogeneous matrix [[R, pos], [0, 1]].
  Mat4 matrix() const;
  /// Frame of a rigid homogeneous matrix; angles reduced into [0, 360).
  static Frame from_matrix(const Mat4& m);
  /// Composition: the frame whose matrix is this->matrix() · other.matrix().
  Frame operator*(const Frame& other) const;
  /// The inverse placement.
  Frame inverse() const;
  /// Maps a point given in this frame's coordinates into the parent coordinates.
  Vec3 apply(const Vec3& p) const;
  /// Same frame with angles reduced into [0, 360).
  Frame normalized() const;
  /// "pos [x, y, z] rot [a, b, c]" with 3 decimals, for messages.
  std::string to_string() const;
};

/// Symmetry-aware difference of one Euler component (reference §1.2): `period` 0 ignores the
/// component; 360 maps the difference into [-180, 180]; 180 treats half-turns as equal.
double symmetric_angle_difference(double d, double period);

/// 6-vector [dx, dy, dz, da, db, dc] between two frames (both reduced mod 360 first), with each
/// angle component reduced by `symmetric_angle_difference` using `periods` (degrees).
Vec6 frame_difference(const Frame& a, const Frame& b, const Vec3& periods);

}  // namespace fabkit

#include "fabkit/core/frame.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace fabkit {

double wrap_360(double deg) {
  double w = std::fmod(deg, 360.0);
  if (w < 0) w += 360.0;
  // fmod can return 360 - tiny for tiny negatives; keep the half-open interval.
  if (w >= 360.0) w -= 360.0;
  return w;
}

Vec3 euler_from_rotation(const Mat3& r) {
  const double b = -std::asin(std::clamp(r(2, 0), -1.0, 1.0));
  double a = 0;
  double c = 0;
  if (std::hypot(r(0, 0), r(1, 0)) < 1e-12) {
    // Gimbal lock (b = ±90°: the frame's x axis is vertical): only c ∓ a is determined, and
    // the formulas below read both from entries that are 0. With a = 0, R = Rz(c)·Ry(±90°),
    // whose middle column is (−sin c, cos c, 0). (Without this a frame such as [30, 90, 0]
    // came back as [0, 90, 0].)
    c = std::atan2(-r(0, 1), r(1, 1));
  } else {
    a = std::atan2(r(2, 1), r(2, 2));
    c = std::atan2(r(1, 0), r(0, 0));
  }
  return {wrap_360(a * kRadToDeg), wrap_360(b * kRadToDeg), wrap_360(c * kRadToDeg)};
}

Mat4 Frame::matrix() const {
  Mat4 m = rot_euler(rot.x(), rot.y(), rot.z());
  m.topRightCorner<3, 1>() = pos;
  return m;
}

Frame Frame::from_matrix(const Mat4& m) {
  return Frame(m.topRightCorner<3, 1>(), euler_from_rotation(m.topLeftCorner<3, 3>()));
}

Frame Frame::operator*(const Frame& other) const {
  return from_matrix(matrix() * other.matrix());
}

Frame Frame::inverse() const {
  return from_matrix(rigid_inverse<double>(matrix()));
}

Vec3 Frame::apply(const Vec3& p) const {
  const Mat4 m = matrix();
  return m.topLeftCorner<3, 3>() * p + pos;
}

Frame Frame::normalized() const {
  return Frame(pos, Vec3(wrap_360(rot.x()), wrap_360(rot.y()), wrap_360(rot.z())));
}

std::string Frame::to_string() const {
  return fmt::format("pos [{:.3f}, {:.3f}, {:.3f}] rot [{:.3f}, {:.3f}, {:.3f}]",
                     pos.x(),
                     pos.y(),
                     pos.z(),
                     rot.x(),
                     rot.y(),
                     rot.z());
}

double symmetric_angle_difference(double d, double period) {
  if (period == 0.0) return 0.0;
  if (std::abs(d) > period) {
    // Python modulo: result in [0, period).
    d = std::fmod(d, period);
    if (d < 0) d += period;
    return d;
  }
  if (std::abs(d + period) < std::abs(d)) d += period;
  if (std::abs(d - period) < std::abs(d)) d -= period;
  return d;
}

Vec6 frame_difference(const Frame& a, const Frame& b, const Vec3& periods) {
  const Frame na = a.normalized();
  const Frame nb = b.normalized();
  Vec6 d;
  d.head<3>() = na.pos - nb.pos;
  for (int i = 0; i < 3; ++i) {
    d[3 + i] = symmetric_angle_difference(na.rot[i] - nb.rot[i], periods[i]);
  }
  return d;
}

}  // namespace fabkit

#include "target.h"

#include <algorithm>

namespace fabkit::hacks::detail {

TargetSymmetry target_symmetry(PrimitiveType t) {
  switch (t) {
    case PrimitiveType::kRod:
    case PrimitiveType::kTube:
      return {Vec3::UnitZ(), Vec3::UnitX()};
    case PrimitiveType::kRing:
      return {Vec3::UnitX(), Vec3::UnitY()};
    case PrimitiveType::kHemisphere:
      return {Vec3::UnitZ(), std::nullopt};
    case PrimitiveType::kClip:
    case PrimitiveType::kSurface:
      return {std::nullopt, Vec3::UnitZ()};
    case PrimitiveType::kEdge:
      return {std::nullopt, Vec3::UnitY()};
    case PrimitiveType::kHook:
      return {};
  }
  return {};
}

std::optional<TargetModel> make_target(const Assembly& a) {
  if (!a.target()) return std::nullopt;
  const std::optional<PartId> id = a.find(a.target()->part.get());
  if (!id) return std::nullopt;
  TargetModel t;
  t.part = *id;
  const Primitive& p = a.node(*id).part->primitive(a.target()->primitive);
  t.base = Rigid<double>::from_matrix(p.frame.matrix());
  t.goal = Rigid<double>::from_matrix(a.target()->frame.matrix());
  t.symmetry = target_symmetry(p.type);
  t.goal_turned = t.goal;
  if (t.symmetry.half_turn_axis) {
    t.goal_turned.R = t.goal.R * Eigen::AngleAxisd(std::numbers::pi, *t.symmetry.half_turn_axis);
  }
  return t;
}

PoseError pose_error(const TargetModel& t, const Rigid<double>& part_frame) {
  const Rigid<double> actual = part_frame.then(t.base);
  PoseError e;
  e.position_mm = (actual.t - t.goal.t).norm();
  auto angle_between = [](const Vec3& u, const Vec3& v) {
    return std::atan2(u.cross(v).norm(), u.dot(v)) * kRadToDeg;
  };
  // Tilt: how far the direction that is up in the goal pose is carried away from up; twist:
  // what is left after undoing the tilt, a turn about the vertical. Against `goal`, which is
  // the goal itself or its symmetric twin, whichever the target is nearer.
  auto tilt_of = [&](const Mat3& goal) {
    return angle_between(actual.R * (goal.transpose() * Vec3::UnitZ()), Vec3::UnitZ());
  };
  auto twist_to = [&](const Mat3& goal) {
    const Vec3 up_now = actual.R * (goal.transpose() * Vec3::UnitZ());
    const Mat3 untilt =
        Eigen::Quaterniond::FromTwoVectors(up_now, Vec3::UnitZ()).toRotationMatrix();
    const Mat3 rest = untilt * actual.R * goal.transpose();
    return std::atan2(rest(1, 0), rest(0, 0)) * kRadToDeg;
  };
  e.tilt_deg = tilt_of(t.goal.R);
  if (t.symmetry.free_axis) {
    // A target free to spin about an axis (a rod, a ring) is only its axis: the error is the
    // angle between the axes, split into how much higher or lower the axis points (tilt) and
    // how far it is turned about the vertical (twist).
    const Vec3 u = actual.R * *t.symmetry.free_axis;
    Vec3 g = t.goal.R * *t.symmetry.free_axis;
    if (t.symmetry.half_turn_axis && u.dot(g) < 0) g = -g;  // end for end is the same
    e.rotation_deg = angle_between(u, g);
    auto elevation = [](const Vec3& v) {
      return std::asin(std::clamp(v.z(), -1.0, 1.0)) * kRadToDeg;
    };
    e.tilt_deg = std::abs(elevation(u) - elevation(g));
    const Vec3 uh(u.x(), u.y(), 0);
    const Vec3 gh(g.x(), g.y(), 0);
    e.twist_deg = 0;
    if (uh.norm() > 1e-9 && gh.norm() > 1e-9) {
      e.twist_deg = std::atan2(gh.cross(uh).z(), gh.dot(uh)) * kRadToDeg;
    }
    return e;
  }
  auto geodesic = [&](const Mat3& goal) {
    return Eigen::AngleAxisd(Mat3(goal.transpose() * actual.R)).angle() * kRadToDeg;
  };
  e.rotation_deg = geodesic(t.goal.R);
  e.twist_deg = twist_to(t.goal.R);
  if (t.symmetry.half_turn_axis) {
    const double turned = geodesic(t.goal_turned.R);
    if (turned < e.rotation_deg) {
      e.rotation_deg = turned;
      e.tilt_deg = tilt_of(t.goal_turned.R);
      e.twist_deg = twist_to(t.goal_turned.R);
    }
  }
  return e;
}

}  // namespace fabkit::hacks::detail

#include "fabkit/templates/box.h"

#include <algorithm>

#include "fabkit/templates/source_design.h"

namespace fabkit::templates {

std::string_view axis_name(int axis) {
  static constexpr std::string_view kNames[] = {"x", "y", "z"};
  return axis >= 0 && axis < 3 ? kNames[axis] : "?";
}

Box Box::from_min_max(const Vec3& lo, const Vec3& hi) {
  Box b;
  b.center = 0.5 * (lo + hi);
  b.size = (hi - lo).cwiseMax(0.0);
  return b;
}

double Box::overlap(const Box& other, int axis) const {
  return std::min(max()[axis], other.max()[axis]) - std::max(min()[axis], other.min()[axis]);
}

bool Box::intersects(const Box& other, double tol) const {
  for (int k = 0; k < 3; ++k) {
    if (overlap(other, k) <= tol) return false;
  }
  return true;
}

bool Box::touches(const Box& other, double tol) const {
  for (int k = 0; k < 3; ++k) {
    if (overlap(other, k) < -tol) return false;
  }
  return true;
}

Box Box::united(const Box& other) const {
  return from_min_max(min().cwiseMin(other.min()), max().cwiseMax(other.max()));
}

std::string_view to_string(PartRole r) {
  return r == PartRole::kPrincipal ? "principal" : "connecting";
}

std::string_view to_string(JointType t) {
  switch (t) {
    case JointType::kPrismatic:
      return "prismatic";
    case JointType::kHinge:
      return "hinge";
    case JointType::kBall:
      return "ball";
  }
  return "hinge";
}

const DesignPart* SourceDesign::find(std::string_view part) const {
  for (const DesignPart& p : parts) {
    if (p.name == part) return &p;
  }
  return nullptr;
}

}  // namespace fabkit::templates

#pragma once
/// Axis-aligned boxes: what every part, element and template is to the template model (the
/// paper's q = centre + three sizes). World frame: mm, z up, the floor at z = 0.

#include <array>
#include <string_view>

#include "fabkit/core/frame.h"

namespace fabkit::templates {

/// "x", "y", "z".
std::string_view axis_name(int axis);

struct Box {
  Vec3 center = Vec3::Zero();  ///< mm, world frame
  Vec3 size = Vec3::Zero();    ///< mm along x, y, z (non-negative)

  Vec3 min() const { return center - 0.5 * size; }
  Vec3 max() const { return center + 0.5 * size; }
  static Box from_min_max(const Vec3& lo, const Vec3& hi);
  /// Overlap length along `axis` (negative: the gap between them).
  double overlap(const Box& other, int axis) const;
  /// Whether the boxes share a volume thicker than `tol` mm in every axis.
  bool intersects(const Box& other, double tol) const;
  /// Whether they touch or overlap: the gap along every axis is at most `tol` mm.
  bool touches(const Box& other, double tol) const;
  /// The smallest box holding both.
  Box united(const Box& other) const;
  double volume() const { return size.x() * size.y() * size.z(); }
};

}  // namespace fabkit::templates

#pragma once
/// Extruding planar regions into prisms (CGAL constrained triangulation; fabkit::geometry):
/// text outlines for engraving, plate shapes, profiles.

#include <Eigen/Core>
#include <span>
#include <vector>

#include "fabkit/core/mesh.h"

namespace fabkit {

/// A closed ring in the plane (mm), last point not repeated.
using Ring2 = std::vector<Eigen::Vector2d>;

/// The prism over the region bounded by `rings`, from z = `z0` to z = `z1` (z0 < z1): a closed,
/// outward-oriented triangle mesh. Which side is inside is decided by nesting (a ring inside
/// one other ring is a hole, inside two is an island), so ring orientation does not matter.
/// Rings must not cross each other or themselves; empty when they bound no area.
TriangleMesh extrude_rings(std::span<const Ring2> rings, double z0, double z1);

/// Signed area of a ring (mm², positive when counter-clockwise).
double signed_area(const Ring2& ring);

}  // namespace fabkit

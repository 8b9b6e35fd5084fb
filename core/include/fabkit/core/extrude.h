#pragma once
/// Extruding planar regions into prisms (CGAL constrained triangulation; fabkit::geometry):
/// text outlines for engraving, plate shapes, profiles.

#include <Eigen/Core>
#include <span>
#include <vector>

#include "fabkit/core/mesh.h"
#include "fabkit/core/polygon2d.h"

namespace fabkit {

/// A closed ring in the plane (mm), last point not repeated: the 2D polygons' ring
/// (`signed_area` and the rest of the ring geometry are in polygon2d.h).
using Ring2 = Ring;

/// The prism over the region bounded by `rings`, from z = `z0` to z = `z1` (z0 < z1): a closed,
/// outward-oriented triangle mesh. Which side is inside is decided by nesting (a ring inside
/// one other ring is a hole, inside two is an island), so ring orientation does not matter.
/// Rings must not cross each other or themselves; empty when they bound no area.
TriangleMesh extrude_rings(std::span<const Ring2> rings, double z0, double z1);

}  // namespace fabkit

#pragma once
/// Planar polygons with holes, their booleans and offsets (on Clipper 1), and the few planar
/// queries kits need: point tests with a tolerance, a line classified against a polygon, and
/// extrusion of a polygon into a closed triangle mesh.
///
/// Conventions: coordinates in mm in some planar frame the caller names; an outer ring is
/// counter-clockwise (positive area) and holes are clockwise. Functions that return polygons
/// return them in that orientation. Booleans snap coordinates to kPolygonResolutionMm.

#include <Eigen/Core>
#include <vector>

#include "fabkit/core/mesh.h"

namespace fabkit {

using Vec2 = Eigen::Vector2d;
/// A closed ring of vertices (the last joins the first; not repeated).
using Ring = std::vector<Vec2>;

/// Booleans and offsets work on integers of this size (0.1 µm): far below any cutter's
/// precision, far above double rounding at furniture sizes.
inline constexpr double kPolygonResolutionMm = 1e-4;

/// A polygon with holes: `outer` counter-clockwise, each hole clockwise and inside it.
struct Polygon2d {
  Ring outer;
  std::vector<Ring> holes;

  /// Area in mm² (outer minus holes).
  double area() const;
  bool empty() const { return outer.size() < 3; }
};

/// Several disjoint polygons, e.g. the result of a boolean.
using Region2d = std::vector<Polygon2d>;

/// Signed area of a ring (positive when counter-clockwise), mm².
double signed_area(const Ring& ring);
double area(const Region2d& region);

/// An axis-aligned box; empty when min > max.
struct Box2d {
  Vec2 min{1e300, 1e300};
  Vec2 max{-1e300, -1e300};
  bool empty() const { return min.x() > max.x(); }
  Vec2 size() const { return empty() ? Vec2(0, 0) : Vec2(max - min); }
  void extend(const Vec2& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};
Box2d bounds(const Ring& ring);
Box2d bounds(const Region2d& region);

/// A rectangle [x0, x1] × [y0, y1] as a counter-clockwise polygon.
Polygon2d rectangle(double x0, double y0, double x1, double y1);
/// A regular `segments`-gon inscribed in a circle of `radius` around `centre`.
Polygon2d circle(const Vec2& centre, double radius, int segments = 48);

/// Orients rings (outer counter-clockwise, holes clockwise).
Polygon2d oriented(Polygon2d polygon);

enum class BooleanOp { kUnion, kIntersection, kDifference, kXor };

/// a ∘ b with non-zero filling of each operand; the result's polygons are disjoint.
Region2d boolean(const Region2d& a, const Region2d& b, BooleanOp op);
Region2d unite(const Region2d& a, const Region2d& b);
Region2d intersect(const Region2d& a, const Region2d& b);
Region2d subtract(const Region2d& a, const Region2d& b);
/// The union of all polygons of `a` (overlapping ones merged).
Region2d unite_all(const Region2d& a);

enum class OffsetJoin { kMiter, kRound, kSquare };
/// Grows (delta > 0) or shrinks (delta < 0) a region by `delta` mm. Miter joins keep right
/// angles exact (limit: 2 × delta).
Region2d offset(const Region2d& region, double delta, OffsetJoin join = OffsetJoin::kMiter);

/// Where a point is relative to a polygon, within `tolerance` mm of the boundary.
enum class PointLocation { kOutside, kBoundary, kInside };
PointLocation locate(const Polygon2d& polygon, const Vec2& p, double tolerance = 1e-6);
/// Distance from `p` to the polygon's boundary (outer ring and holes), mm.
double boundary_distance(const Polygon2d& polygon, const Vec2& p);

/// A stretch of a line o + s·d (|d| = 1, s in mm) and how it lies relative to a polygon.
struct LineStretch {
  double s0 = 0;
  double s1 = 0;
  /// kInside: material on both sides of the line there; kBoundary: on one side only (the
  /// line runs along an edge); stretches outside the polygon are not returned.
  PointLocation where = PointLocation::kInside;
};

/// The stretches of the infinite line o + s·d (d normalised by the function) that lie in the
/// closed polygon, in increasing s, adjacent stretches of the same kind merged. `tolerance`
/// (mm) decides "on an edge".
std::vector<LineStretch> classify_line(const Polygon2d& polygon,
                                       const Vec2& o,
                                       const Vec2& d,
                                       double tolerance = 1e-6);

/// The polygon extruded along z from z0 to z1 (z0 < z1): a closed, outward-oriented triangle
/// mesh (caps triangulated with holes). Empty for an empty polygon.
TriangleMesh extrude(const Polygon2d& polygon, double z0, double z1);

/// A point well inside the polygon (far from its boundary), for labels; the centroid of the
/// outer ring when that is inside and clear of holes.
Vec2 interior_point(const Polygon2d& polygon);

/// Rotation by `degrees` about the origin, then translation by `t`.
Ring transformed(const Ring& ring, double degrees, const Vec2& t);
Polygon2d transformed(const Polygon2d& polygon, double degrees, const Vec2& t);

}  // namespace fabkit

#pragma once
// Convex pieces of the shapes parts are drawn with, for contact queries
// (core/collision.h): each piece a closed convex mesh; non-convex shapes (wire arcs, tubes)
// become several. Pieces may overlap and may leave hairline gaps at the joints of an arc;
// they follow the drawn shape to within a fraction of a millimetre.

#include <vector>

#include "fabkit/core/collision.h"
#include "fabkit/core/mesh.h"

namespace fabkit::hacks::detail {

/// A wire arc drawn by shapes::torus_arc (same parameters and placement): straight wire
/// segments of at most `max_segment_deg` of arc each.
std::vector<TriangleMesh> arc_pieces(double arc_radius,
                                     double wire_radius,
                                     double angle_deg,
                                     double max_segment_deg = 15.0);

/// A tube drawn by shapes::tube: annular sectors of at most 30°.
std::vector<TriangleMesh> tube_pieces(double inner_radius, double outer_radius, double length);

/// The round rims of tube_pieces' sectors (same order): each sector's outer surface is the
/// tube's, not a flat face across it.
std::vector<std::vector<collision::Arc>> tube_piece_rims(double inner_radius,
                                                         double outer_radius,
                                                         double length);

/// The rims of a solid cylinder along z centred at the origin (shapes::cylinder): its two end
/// circles, whose convex hull is the exact cylinder.
std::vector<collision::Arc> cylinder_rims(double radius, double length);

/// Transforms every piece by `m`.
void transform_pieces(std::vector<TriangleMesh>& pieces, const Mat4& m);
/// Transforms every rim of every piece by `m`.
void transform_rims(std::vector<std::vector<collision::Arc>>& rims, const Mat4& m);

}  // namespace fabkit::hacks::detail

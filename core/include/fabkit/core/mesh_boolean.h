#pragma once
/// Exact solid operations on triangle meshes for every kit (CGAL corefinement with exact
/// constructions; fabkit::geometry): union of many solids, difference, convex hull, and the
/// checks that a mesh is a printable solid (closed, manifold, free of self-intersections).
///
///   Diagnostics diags;
///   auto joint = mesh_boolean({hull, prism1, prism2}, {socket1, socket2}, "joint 07", diags);
///   if (joint && check_solid(*joint).valid_solid()) write_stl(*joint, "joint_07.stl", diags);
///
/// Inputs are closed, outward-oriented solids in mm. Every operation works in exact arithmetic
/// from its double inputs and rounds to double once, at the end.

#include <chrono>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"

namespace fabkit {

namespace codes {
/// An exact boolean could not be computed (an input is not a closed manifold solid, or the
/// result is not a manifold). Internal: fabkit made the inputs.
inline constexpr DiagnosticCode kBooleanFailed{"boolean-failed", DiagnosticClass::kInternal};
}  // namespace codes

/// What a solid check found about a mesh.
struct SolidCheck {
  bool manifold = false;           ///< every edge has at most two faces, consistently oriented,
                                   ///< and every vertex has one fan of faces
  bool closed = false;             ///< manifold and no boundary edges (watertight)
  bool self_intersecting = false;  ///< two non-adjacent triangles intersect
  bool outward = false;            ///< closed with positive enclosed volume
  int boundary_edges = 0;          ///< edges with one face (0 for a closed mesh)
  int components = 0;              ///< connected pieces
  double volume = 0;               ///< mm³, enclosed volume (meaningful when closed)
  int intersecting_pairs = 0;      ///< pairs of triangles that intersect
  Vec3 intersection_at = Vec3::Zero();  ///< mm: centroid of the first such pair
  /// closed, manifold, not self-intersecting, outward: a printable solid.
  bool valid_solid() const { return manifold && closed && !self_intersecting && outward; }
  /// "" when valid, else what is wrong ("not closed (12 boundary edges); self-intersecting").
  std::string problems() const;
};

/// Checks a mesh as a solid (independent of how it was made).
SolidCheck check_solid(const TriangleMesh& mesh);
/// `mesh` as a file with float32 coordinates holds it (STL, 3MF, glTF): each vertex rounded
/// to float, and vertices that round to the same point merged, as STL readers and slicers do.
TriangleMesh rounded_to_float32(const TriangleMesh& mesh);
/// Closed and manifold (watertight, every edge shared by exactly two faces).
bool is_closed_manifold(const TriangleMesh& mesh);
/// Whether two non-adjacent triangles intersect.
bool self_intersects(const TriangleMesh& mesh);

/// Convex hull of `points` as a closed outward triangle mesh whose vertices are input points;
/// empty when the points span less than 3 dimensions.
TriangleMesh convex_hull(std::span<const Vec3> points);

/// Points in their own frame, placed by an affine map applied in exact arithmetic.
struct PlacedPoints {
  std::vector<Vec3> points;
  Mat4 placement = Mat4::Identity();
};

/// One operand of an exact boolean: a closed solid in its own frame placed by `placement`, or
/// (when `hull` is not empty) the convex hull of placed point sets. Placements are applied
/// exactly, so what is coplanar or collinear in a solid's own frame (a prism's cap, a vertex
/// shared with a hull) stays exactly so in the result: build primitives axis-aligned and place
/// them, rather than rotating them in double first.
struct SolidInput {
  TriangleMesh mesh;
  Mat4 placement = Mat4::Identity();
  std::vector<PlacedPoints> hull;
};

/// How the result of an exact boolean is finished.
struct BooleanOptions {
  /// mm. 0: the exact result rounded to double, every sliver kept. Above 0: for files that
  /// store float32 coordinates (STL, 3MF, glTF): edges shorter than this are collapsed and
  /// triangles thinner than it flipped away (the slivers left where surfaces touch, are
  /// tangent or nearly coincide), in exact arithmetic, and the result must stay a solid with
  /// its coordinates rounded to float32 — else the boolean fails. 0.01 mm is far below what a
  /// printer resolves and far above float32's spacing (0.24 µm at 2 m).
  double min_feature_mm = 0;
  /// Checked before each binary union and difference (a joint's take tens of milliseconds
  /// each): past it, nullopt with a time-limit error instead of the rest.
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

/// (∪ `add`) \ (∪ `subtract`) of placed solids, exactly, rounded to double once. nullopt with
/// a boolean-failed diagnostic naming `what` (and the operand) when an operand is not a
/// closed manifold solid, a hull is flat, or the result is not a manifold.
std::optional<TriangleMesh> mesh_boolean(std::span<const SolidInput> add,
                                         std::span<const SolidInput> subtract,
                                         std::string_view what,
                                         Diagnostics& diags,
                                         const BooleanOptions& options = {});

/// (∪ `add`) \ (∪ `subtract`), exactly, rounded once. `what` names the result in messages
/// ("joint 07"). nullopt with a boolean-failed diagnostic when an input is not a closed
/// manifold solid or CGAL cannot produce a manifold result; inputs are left unchanged.
std::optional<TriangleMesh> mesh_boolean(std::span<const TriangleMesh> add,
                                         std::span<const TriangleMesh> subtract,
                                         std::string_view what,
                                         Diagnostics& diags,
                                         const BooleanOptions& options = {});
/// The union of `solids`.
std::optional<TriangleMesh> mesh_union(std::span<const TriangleMesh> solids,
                                       std::string_view what,
                                       Diagnostics& diags,
                                       const BooleanOptions& options = {});
/// `solid` minus the union of `cutters`.
std::optional<TriangleMesh> mesh_difference(const TriangleMesh& solid,
                                            std::span<const TriangleMesh> cutters,
                                            std::string_view what,
                                            Diagnostics& diags);

}  // namespace fabkit

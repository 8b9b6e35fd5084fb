#pragma once
/// Parts: annotated everyday objects carrying connector primitives (paper §3).

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/collision.h"
#include "fabkit/core/ids.h"
#include "fabkit/core/mesh.h"
#include "fabkit/hacks/primitive.h"

namespace fabkit::hacks {

/// Which list of the paper's library a part belongs to (§10.2 "library" column).
enum class PartCategory {
  kEnvironment,  ///< environment / target objects (env_library)
  kHack,         ///< parts to build hacks from (full_library)
  kBoth,         ///< in both lists (TwoholeBasket)
  kOther,        ///< used by examples or the study but in neither list
};
std::string_view to_string(PartCategory c);
/// The category a name spells (any case), as to_string writes it; nothing for another word.
std::optional<PartCategory> category_named(std::string_view name);

/// A part: its primitives at fixed frames in the part's coordinates, its mass properties and
/// a display mesh. Values, cheap to copy apart from the mesh.
struct Part {
  std::string type_name;  ///< library name, e.g. "DoubleHook"; "Environment" for loose primitives
  /// Optional label of this instance ("eyehook1"); diagnostics use it instead of "Type#k".
  std::string instance_name;
  std::string description;
  PartCategory category = PartCategory::kOther;
  std::vector<Primitive> primitives;
  /// Mass in the reference's units: mesh volume in mm³ at density 1. Only ratios matter.
  double mass = 0;
  /// Centre of mass in the part's coordinates, mm.
  Vec3 center_of_mass = Vec3::Zero();
  /// Display mesh in the part's coordinates, mm.
  TriangleMesh mesh;
  /// The object as convex pieces (closed convex meshes, part coordinates) for contact
  /// queries: a part may touch another but not pass through it. `collision_tags` holds, per
  /// piece, the index of the primitive it draws, or -1 for the rest of the body. Empty for a
  /// part known only by a mesh file: its contacts are not checked.
  std::vector<TriangleMesh> collision_pieces;
  std::vector<int> collision_tags;
  /// The pieces' round rims (collision::Arc), one list per piece; it may be shorter than
  /// `collision_pieces` (the rest have none). A rod is the convex hull of its two end
  /// circles, an exact cylinder; a tube's sectors have its round outer surface.
  std::vector<std::vector<collision::Arc>> collision_rims;
  /// `collision_pieces` as a collision body, built on first use (a copy builds its own).
  collision::CachedBody collision_body;
  /// Values of a parametric part's parameters (empty for fixed parts).
  std::map<std::string, double> params;

  /// The primitive called `name` (invalid id if none). "holeN" and "ringN" name the same
  /// primitive (the paper calls rings holes).
  PrimitiveId find_primitive(std::string_view name) const;
  const Primitive& primitive(PrimitiveId id) const { return primitives.at(id.index()); }
  /// "hook1, hook2" for messages.
  std::string primitive_list() const;
};

/// Display mesh of one primitive in its part's coordinates (torus arcs, cylinders, boxes,
/// spheres), built from the shape parameters.
TriangleMesh primitive_mesh(const Primitive& p);
/// The same primitive as convex pieces (see Part::collision_pieces), in its part's
/// coordinates.
std::vector<TriangleMesh> primitive_pieces(const Primitive& p);
/// The round rims of primitive_pieces(p), one list per piece (empty when none has any).
std::vector<std::vector<collision::Arc>> primitive_piece_rims(const Primitive& p);
/// Appends primitive `index`'s pieces (and their rims) to `part`'s collision pieces, tagged
/// with `index`.
void add_primitive_pieces(Part& part, int index);

/// A part made of loose primitives, as the paper's Environment({"name": Primitive, ...}).
/// Its display mesh is the union of the primitive meshes and its mass is 0.
Part make_primitive_part(std::vector<Primitive> primitives);

}  // namespace fabkit::hacks

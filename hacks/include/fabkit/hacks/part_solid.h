#pragma once
/// A part as one closed solid, for the files people build from (assembly.stl, assembly.obj,
/// scene.glb): the exact union of the pieces its mesh is made of — the body's boxes, cylinders,
/// spheres and wire arcs, and the primitives' shapes — in the part's own frame (mm). A part's
/// display mesh (Part::mesh) keeps the pieces overlapping, which is all a picture or the mass
/// properties need; a slicer needs one watertight surface without inner walls.
///
///   PartSolidCache solids;
///   const PartSolid& s = solids.solid(*part);  // computed once per part type and parameters
///   world.append(s.mesh.transformed(frame));
///   diags.append(s.diagnostics);               // warnings when a piece is not a solid
///
/// The union is exact (fabkit::geometry), so it is slow next to a solve: tens to hundreds of
/// milliseconds per part type (docs/benchmarks.md). A cache given a directory keeps the
/// solids there, so that only the first export of a part type on a machine pays for it.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"
#include "fabkit/hacks/part.h"

namespace fabkit::hacks {

/// A part's solid and how it was made.
struct PartSolid {
  /// The solid in the part's frame, mm: closed, manifold, outward and free of
  /// self-intersections when `exact`; otherwise the part's display mesh as it is.
  TriangleMesh mesh;
  int pieces = 0;  ///< closed pieces the display mesh is made of
  int shells = 0;  ///< separate closed surfaces of the solid (1 when all pieces touch)
  /// Whether `mesh` is the union. False when a piece is not a closed solid itself (a user's
  /// open mesh) or the union failed; `diagnostics` then holds a warning saying which and why.
  bool exact = false;
  Diagnostics diagnostics;
};

/// The pieces of a mesh: its groups of faces connected through shared vertices, each as a
/// mesh of its own (vertices renumbered, faces in their original order). A part's display
/// mesh is its pieces appended one after another, so these are the body shapes and primitive
/// shapes it was built from.
std::vector<TriangleMesh> mesh_pieces(const TriangleMesh& mesh);

/// The solid of `part` (see PartSolid); never fails, warns instead. `part` names it in the
/// warnings by its instance name or type.
PartSolid part_solid(const Part& part);

/// A placement of `solid` (a valid solid in its part's frame, mm) at which it stays one once
/// placed and rounded to float32 (rounded_to_float32, mesh_boolean.h): `placement` itself, or, in
/// the rare pose where rounding folds a thin wedge of the solid (where two of its faces meet at a
/// few degrees), `placement` moved by a fraction of a micrometre. nullopt if none of the few tried
/// does.
std::optional<Mat4> float32_safe_placement(const TriangleMesh& solid, const Mat4& placement);

/// Solids of parts, each computed once: parts of the same type with the same parameters (and
/// so the same mesh) share one. With a directory, solids are also kept on disk between
/// processes (one small file per distinct display mesh, named by its hash and checked
/// against it on reading), so that a second `fabkit solve -o` of a design does no boolean.
/// Not thread-safe; one cache per export or per session, any number of processes per
/// directory (files are written atomically).
class PartSolidCache {
 public:
  PartSolidCache() = default;
  /// `directory` (created when first written to) keeps the solids; empty: memory only.
  explicit PartSolidCache(std::filesystem::path directory);
  /// The solid of `part`; the reference stays valid as long as the cache.
  const PartSolid& solid(const Part& part);
  /// How many solids were computed (unions run).
  int computed() const { return computed_; }
  /// How many solids were read from the directory instead of computed.
  int loaded() const { return loaded_; }
  /// How many lookups found a solid this cache held already (hits).
  int reused() const { return reused_; }

 private:
  struct Entry {
    std::map<std::string, double> params;
    TriangleMesh source;  ///< the display mesh it was computed from, compared on every hit
    PartSolid solid;
  };
  std::optional<PartSolid> load(const TriangleMesh& source, std::uint64_t hash) const;
  void store(const TriangleMesh& source, std::uint64_t hash, const PartSolid& solid) const;
  std::filesystem::path directory_;
  // Keyed by type and mesh size; entries are boxed so that references stay valid.
  std::map<std::pair<std::string, std::size_t>, std::vector<std::unique_ptr<Entry>>> entries_;
  int computed_ = 0;
  int loaded_ = 0;
  int reused_ = 0;
};

/// The hash a cache directory names a part's solid file by: of the display mesh's vertex
/// coordinates and faces (bit for bit) and of the version of the solid computation.
std::uint64_t part_solid_key(const TriangleMesh& display_mesh);

}  // namespace fabkit::hacks

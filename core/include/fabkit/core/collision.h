#pragma once
/// Distance and penetration between rigid bodies made of convex pieces (FCL's GJK distance
/// and libccd's MPR penetration on each piece's support mapping; fabkit::core,
/// core/src/collision.cpp only). Every kit that must keep parts from passing through each
/// other asks here.
///
/// A body is a list of convex pieces — closed convex triangle meshes in the body's own
/// coordinates (mm) — each with a tag the caller chooses (which connector it draws, or -1 for
/// the rest of the object). Non-convex objects are described by several pieces; a body is the
/// union of its pieces. A piece may also have round rims (`Arc`s): it is then the convex hull
/// of its mesh's vertices and its arcs, so that a rod or a tube is a real cylinder, whose
/// distance to an edge and contact normal change smoothly as it rolls (a faceted one's jump
/// from facet to facet, which stalls a relaxation resting on it).

#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <span>
#include <vector>

#include "fabkit/core/frame.h"
#include "fabkit/core/mesh.h"

namespace fabkit::collision {

/// The signed distance between two convex pieces: positive when apart (the gap), negative
/// when they overlap (the depth to push them apart by); the witness points are in world
/// coordinates, `point_b - point_a` along the separating direction from a to b.
struct Proximity {
  double distance = 0;
  Vec3 point_a = Vec3::Zero();
  Vec3 point_b = Vec3::Zero();
  /// Unit normal from a to b (the direction that separates b from a).
  Vec3 normal = Vec3::UnitZ();
};

/// A circular arc on a piece's boundary: centre + radius (cos a u + sin a v) for a in
/// [from, to] (radians; to - from at most 2π), u and v orthonormal.
struct Arc {
  Vec3 centre = Vec3::Zero();
  Vec3 u = Vec3::UnitX();
  Vec3 v = Vec3::UnitY();
  double radius = 0;
  double from = 0;
  double to = 2 * std::numbers::pi;
  /// The arc moved by the rigid transform `m`.
  Arc transformed(const Mat4& m) const;
  /// The arc's point farthest along `direction` (any point when it is normal to the arc).
  Vec3 support(const Vec3& direction) const;
};

class Body;
Proximity piece_distance(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb);
struct DistanceBounds;
DistanceBounds piece_distance_bounds(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb);

class Body {
 public:
  Body() = default;
  /// `pieces` must be closed and convex (their vertices' convex hull is what is used);
  /// `tags` has one entry per piece; `arcs`, when given, the round rims of each piece (it may
  /// be shorter than `pieces`: the rest have none).
  Body(std::span<const TriangleMesh> pieces,
       std::span<const int> tags,
       std::span<const std::vector<Arc>> arcs = {});

  bool empty() const { return pieces_ == nullptr || piece_count() == 0; }
  int piece_count() const;
  int tag(int piece) const;
  /// Bounds of piece `piece` in body coordinates.
  Vec3 piece_min(int piece) const;
  Vec3 piece_max(int piece) const;
  /// Bounds of the whole body in body coordinates.
  Vec3 bounds_min() const { return min_; }
  Vec3 bounds_max() const { return max_; }
  /// Whether the two are one set of shapes (built once, shared).
  bool shares_shapes_with(const Body& other) const {
    return pieces_ != nullptr && pieces_ == other.pieces_;
  }

 private:
  friend Proximity piece_distance(
      const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb);
  friend DistanceBounds piece_distance_bounds(
      const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb);
  struct Pieces;
  std::shared_ptr<const Pieces> pieces_;
  Vec3 min_ = Vec3::Zero();
  Vec3 max_ = Vec3::Zero();
};

/// A body its owner builds on first use and keeps (building one costs a convex shape per
/// piece, and so does freeing it: a solve should not pay either for parts it was handed).
/// Owners are copied and then edited, so a copy starts without a body and gets its own; a
/// change of the number or the storage of the pieces gets it again. Owners of equal pieces
/// get one body, built once per process (collision.cpp keeps the bodies built so far, by
/// their contents). Safe to share between threads.
class CachedBody {
 public:
  CachedBody() = default;
  CachedBody(const CachedBody&) {}
  CachedBody& operator=(const CachedBody&);
  /// The body of `pieces`, `tags` and `arcs`, built on the first call.
  Body get(std::span<const TriangleMesh> pieces,
           std::span<const int> tags,
           std::span<const std::vector<Arc>> arcs = {}) const;

 private:
  mutable std::mutex mutex_;
  mutable std::optional<Body> body_;
  mutable const TriangleMesh* built_from_ = nullptr;
  mutable std::size_t built_count_ = 0;
  mutable std::size_t built_arc_count_ = 0;
};

/// Signed distance between piece `pa` of `a` at world pose `ta` and piece `pb` of `b` at `tb`.
Proximity piece_distance(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb);

/// A lower bound of the distance between the two pieces from their world-aligned bounding
/// boxes (0 when the boxes overlap): pairs farther apart than a cut-off need no exact query.
double piece_gap_bound(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb);

/// Bounds of the signed distance between two pieces from two support queries along the line
/// between their centres, where an exact distance takes GJK's dozens: `lower` is how far apart
/// they are along that line (at most the distance; when they overlap, at most minus the
/// depth), `upper` the distance between the two points of theirs that bound that gap (at least
/// the distance). Pairs the bounds place on one side of a cut-off need no exact query.
struct DistanceBounds {
  double lower = 0;
  double upper = 0;
};
DistanceBounds piece_distance_bounds(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb);

/// A world-aligned box.
struct Box {
  Vec3 lo = Vec3::Zero();
  Vec3 hi = Vec3::Zero();
};
/// The world-aligned box around the box [lo, hi] of a body's coordinates moved by `t`.
Box world_box(const Vec3& lo, const Vec3& hi, const Mat4& t);
/// The distance between two boxes (0 when they overlap): a lower bound of the distance between
/// anything inside them. For many pairs, compute each box once and compare them with this.
double box_gap(const Box& a, const Box& b);

}  // namespace fabkit::collision

#pragma once
// Contacts between parts (issue 9: no part passes through another or the environment): every
// part's convex pieces as a collision body, which piece pairs are watched (near each other
// and not the two sides of one connection), and their signed distances. Step 2 keeps them
// apart with one inequality row per watched pair; the verdict lists what touches.

#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "fabkit/core/collision.h"
#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks::detail {

/// Two pieces of two parts that must not pass through each other.
struct PiecePair {
  int part_a = 0;
  int piece_a = 0;
  int part_b = 0;
  int piece_b = 0;
  bool operator==(const PiecePair& o) const = default;
};

/// The collision bodies of an assembly's parts (built once per solve).
class ContactModel {
 public:
  explicit ContactModel(const Assembly& a);

  const collision::Body& body(int part) const { return bodies_[static_cast<std::size_t>(part)]; }
  bool has_body(int part) const { return !body(part).empty(); }
  int part_count() const { return static_cast<int>(bodies_.size()); }

  /// Piece pairs between parts (at least one of them in `moving`, a per-part flag) that come
  /// within `cutoff` mm at `frames`, excluding, for each connection, the pieces at it on both
  /// sides: a hook and the rod it hangs on touch by design, and so may what they are joined to
  /// right there (the basket wall under the rim a hook wraps, the bar of a link at its hook);
  /// the connection itself keeps them where they are.
  /// With `distances`, each returned pair's signed distance is appended to it (computed once);
  /// then, and whenever `cutoff` > 0, only pairs whose distance is within `cutoff` are
  /// returned (with neither, all pairs whose bounds overlap).
  /// Past `deadline` (checked per pair of parts) it stops and sets `*cut_short`.
  std::vector<PiecePair> watched_pairs(
      const std::vector<Mat4>& frames,
      const std::vector<bool>& moving,
      double cutoff,
      std::vector<double>* distances = nullptr,
      std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt,
      bool* cut_short = nullptr) const;

  /// The same pairs for `cutoff` > 0, and in `deepest` how deep the deepest of them overlaps
  /// (0 when none does): pairs certainly apart and certainly within the cut-off need no exact
  /// query.
  std::vector<PiecePair> watched_pairs(const std::vector<Mat4>& frames,
                                       const std::vector<bool>& moving,
                                       double cutoff,
                                       double& deepest) const;

  /// For each pair of parts (at least one in `moving`) whose bodies come within `cutoff` mm at
  /// `frames`, apart from the pieces a connection joins: the smallest signed distance.
  struct PartPairDistance {
    int part_a = 0;
    int part_b = 0;
    double distance = 0;
  };
  std::vector<PartPairDistance> closest_parts(
      const std::vector<Mat4>& frames,
      const std::vector<bool>& moving,
      double cutoff,
      std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt,
      bool* cut_short = nullptr) const;

  /// Signed distance of a pair at `frames` (negative: interpenetration depth).
  collision::Proximity distance(const PiecePair& p, const std::vector<Mat4>& frames) const;
  /// Bounds of the pair's signed distance (collision::piece_distance_bounds).
  collision::DistanceBounds distance_bounds(const PiecePair& p,
                                            const std::vector<Mat4>& frames) const;
  /// A lower bound of the pair's distance (0 when their bounds overlap).
  double gap_bound(const PiecePair& p, const std::vector<Mat4>& frames) const;

 private:
  bool excluded(int part_a, int piece_a, int part_b, int piece_b) const;
  // A collision query on the pair's two pieces where `frames` put them.
  template <class Query>
  auto on_pair(const PiecePair& p, const std::vector<Mat4>& frames, Query query) const {
    return query(body(p.part_a),
                 p.piece_a,
                 frames[static_cast<std::size_t>(p.part_a)],
                 body(p.part_b),
                 p.piece_b,
                 frames[static_cast<std::size_t>(p.part_b)]);
  }
  // Calls take(pair) for each piece pair between two parts (at least one moving) whose bounds
  // come within `cutoff` and that no connection joins; false when cut short by `deadline`.
  template <class Take>
  bool for_near_pairs(const std::vector<Mat4>& frames,
                      const std::vector<bool>& moving,
                      double cutoff,
                      std::optional<std::chrono::steady_clock::time_point> deadline,
                      Take take) const;

  std::vector<collision::Body> bodies_;
  // Per connection: (part, primitive) of each side.
  struct Joined {
    int part_a, prim_a, part_b, prim_b;
  };
  std::vector<Joined> joined_;
  // [part][piece]: the primitives (indices) whose pieces this piece touches or is part of.
  std::vector<std::vector<std::vector<int>>> at_primitive_;
};

/// Pieces closer than this (mm) are watched from the start of a relaxation.
inline constexpr double kContactWatchMm = 25.0;
/// Deeper than this (mm) counts as passing through: the verdict reports it.
inline constexpr double kPenetrationToleranceMm = 0.5;
/// Iterations of a relaxation with contact rows, and how many times it is run, each time with
/// the pairs the last run came near added (deterministic bounds on the cost of contacts): twice,
/// or, once a run has had to start again from the start because it ended inside pairs it did
/// not watch, five times. A run that swings parts far (the reading nook's hoop turning 75°)
/// meets new pairs run after run: its runs came apart in the fourth. (Five for every run cost
/// the mug hanger a look for new pairs after its second run that never found any: +9 %.)
inline constexpr int kContactIterations = 150;
inline constexpr int kContactRounds = 2;
inline constexpr int kContactRestartedRounds = 5;
/// Pieces within this (mm) of each other touch (listed as contacts in result.json).
inline constexpr double kTouchingMm = 0.5;

}  // namespace fabkit::hacks::detail

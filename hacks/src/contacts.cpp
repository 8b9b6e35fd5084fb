#include "contacts.h"

#include <algorithm>

#include "fabkit/core/stop_clock.h"

namespace fabkit::hacks::detail {

ContactModel::ContactModel(const Assembly& a) {
  for (const PartNode& n : a.nodes()) {
    const Part& part = *n.part;
    bodies_.push_back(
        part.collision_body.get(part.collision_pieces, part.collision_tags, part.collision_rims));
  }
  for (const Connection& c : a.connections()) {
    joined_.push_back({c.first.part.value,
                       c.first.primitive.value,
                       c.second.part.value,
                       c.second.primitive.value});
  }
  // Which primitives each piece is at: its own, and those whose pieces it touches (bounds
  // within 1 mm, in the part's own coordinates: it does not change as the part moves).
  constexpr double kAdjacentMm = 1.0;
  for (const collision::Body& b : bodies_) {
    std::vector<std::vector<int>> at(static_cast<std::size_t>(b.piece_count()));
    for (int i = 0; i < b.piece_count(); ++i) {
      for (int j = 0; j < b.piece_count(); ++j) {
        const int prim = b.tag(j);
        if (prim < 0) continue;
        const bool own = i == j;
        const Vec3 gap = (b.piece_min(j) - b.piece_max(i))
                             .cwiseMax(b.piece_min(i) - b.piece_max(j))
                             .cwiseMax(Vec3::Zero());
        if (!own && gap.norm() > kAdjacentMm) continue;
        auto& list = at[static_cast<std::size_t>(i)];
        if (std::find(list.begin(), list.end(), prim) == list.end()) list.push_back(prim);
      }
    }
    at_primitive_.push_back(std::move(at));
  }
}

bool ContactModel::excluded(int part_a, int piece_a, int part_b, int piece_b) const {
  auto at = [&](int part, int piece, int prim) {
    const std::vector<int>& list =
        at_primitive_[static_cast<std::size_t>(part)][static_cast<std::size_t>(piece)];
    return std::find(list.begin(), list.end(), prim) != list.end();
  };
  for (const Joined& j : joined_) {
    if (j.part_a == part_a && j.part_b == part_b && at(part_a, piece_a, j.prim_a) &&
        at(part_b, piece_b, j.prim_b)) {
      return true;
    }
    if (j.part_a == part_b && j.part_b == part_a && at(part_b, piece_b, j.prim_a) &&
        at(part_a, piece_a, j.prim_b)) {
      return true;
    }
  }
  return false;
}

template <class Take>
bool ContactModel::for_near_pairs(const std::vector<Mat4>& frames,
                                  const std::vector<bool>& moving,
                                  double cutoff,
                                  std::optional<std::chrono::steady_clock::time_point> deadline,
                                  Take take) const {
  const int n = part_count();
  // World boxes of every body and piece, once: the pair loops below only compare them.
  std::vector<collision::Box> whole(static_cast<std::size_t>(n));
  std::vector<std::vector<collision::Box>> pieces(static_cast<std::size_t>(n));
  for (int a = 0; a < n; ++a) {
    if (!has_body(a)) continue;
    const collision::Body& A = body(a);
    const Mat4& f = frames[static_cast<std::size_t>(a)];
    whole[static_cast<std::size_t>(a)] = collision::world_box(A.bounds_min(), A.bounds_max(), f);
    for (int i = 0; i < A.piece_count(); ++i) {
      pieces[static_cast<std::size_t>(a)].push_back(
          collision::world_box(A.piece_min(i), A.piece_max(i), f));
    }
  }
  for (int a = 0; a < n; ++a) {
    if (!has_body(a)) continue;
    for (int b = a + 1; b < n; ++b) {
      if (!has_body(b)) continue;
      if (!moving[static_cast<std::size_t>(a)] && !moving[static_cast<std::size_t>(b)]) continue;
      if (deadline_passed(deadline)) return false;
      if (collision::box_gap(whole[static_cast<std::size_t>(a)],
                             whole[static_cast<std::size_t>(b)]) > cutoff) {
        continue;
      }
      const std::vector<collision::Box>& pa = pieces[static_cast<std::size_t>(a)];
      const std::vector<collision::Box>& pb = pieces[static_cast<std::size_t>(b)];
      for (std::size_t i = 0; i < pa.size(); ++i) {
        for (std::size_t j = 0; j < pb.size(); ++j) {
          if (collision::box_gap(pa[i], pb[j]) > cutoff) continue;
          const PiecePair p{a, static_cast<int>(i), b, static_cast<int>(j)};
          if (excluded(a, p.piece_a, b, p.piece_b)) continue;
          take(p);
        }
      }
    }
  }
  return true;
}

std::vector<PiecePair> ContactModel::watched_pairs(
    const std::vector<Mat4>& frames,
    const std::vector<bool>& moving,
    double cutoff,
    std::vector<double>* distances,
    std::optional<std::chrono::steady_clock::time_point> deadline,
    bool* cut_short) const {
  std::vector<PiecePair> out;
  const bool whole = for_near_pairs(frames, moving, cutoff, deadline, [&](const PiecePair& p) {
    // Bounds are loose (a box around a slanted wire): the true distance decides, so that only
    // pairs that can meet become rows of the solve. Two support queries put most pairs that
    // boxes cannot tell apart beyond the cut-off; the exact query (GJK's dozens of them) is for
    // the rest.
    if (cutoff > 0 || distances) {
      if (distance_bounds(p, frames).lower > cutoff) return;
      const double d = distance(p, frames).distance;
      if (d > cutoff) return;
      if (distances) distances->push_back(d);
    }
    out.push_back(p);
  });
  if (!whole && cut_short) *cut_short = true;
  return out;
}

std::vector<PiecePair> ContactModel::watched_pairs(const std::vector<Mat4>& frames,
                                                   const std::vector<bool>& moving,
                                                   double cutoff,
                                                   double& deepest) const {
  std::vector<PiecePair> out;
  deepest = 0;
  for_near_pairs(frames, moving, cutoff, std::nullopt, [&](const PiecePair& p) {
    const collision::DistanceBounds bounds = distance_bounds(p, frames);
    if (bounds.lower > cutoff) return;
    // Certainly apart (a positive lower bound) and certainly within the cut-off (an upper
    // bound inside it): watched, and no part of the depth; no exact query needed.
    if (bounds.lower > 0 && bounds.upper <= cutoff) {
      out.push_back(p);
      return;
    }
    const double d = distance(p, frames).distance;
    if (d > cutoff) return;
    deepest = std::max(deepest, -d);
    out.push_back(p);
  });
  return out;
}

std::vector<ContactModel::PartPairDistance> ContactModel::closest_parts(
    const std::vector<Mat4>& frames,
    const std::vector<bool>& moving,
    double cutoff,
    std::optional<std::chrono::steady_clock::time_point> deadline,
    bool* cut_short) const {
  std::vector<PartPairDistance> out;
  std::vector<double> distances;
  const std::vector<PiecePair> near =
      watched_pairs(frames, moving, cutoff, &distances, deadline, cut_short);
  for (std::size_t k = 0; k < near.size(); ++k) {
    const PiecePair& w = near[k];
    const double d = distances[k];
    if (d > cutoff) continue;
    auto same = [&](const PartPairDistance& x) {
      return x.part_a == w.part_a && x.part_b == w.part_b;
    };
    auto it = std::find_if(out.begin(), out.end(), same);
    if (it == out.end()) {
      out.push_back({w.part_a, w.part_b, d});
    } else {
      it->distance = std::min(it->distance, d);
    }
  }
  std::stable_sort(
      out.begin(), out.end(), [](const auto& u, const auto& v) { return u.distance < v.distance; });
  return out;
}

collision::Proximity ContactModel::distance(const PiecePair& p,
                                            const std::vector<Mat4>& frames) const {
  return on_pair(p, frames, collision::piece_distance);
}

collision::DistanceBounds ContactModel::distance_bounds(const PiecePair& p,
                                                        const std::vector<Mat4>& frames) const {
  return on_pair(p, frames, collision::piece_distance_bounds);
}

double ContactModel::gap_bound(const PiecePair& p, const std::vector<Mat4>& frames) const {
  return on_pair(p, frames, collision::piece_gap_bound);
}

}  // namespace fabkit::hacks::detail

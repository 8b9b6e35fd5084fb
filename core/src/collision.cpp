// The only translation unit that includes FCL. Its GJK distance (libccd's algorithm with FCL's
// distance extension) is compiled here from FCL's headers, on our own support mapping of each
// piece (its vertices and round rims), rather than called through libfcl.so: the library's
// 29,183 symbol relocations were most of the dynamic loader's work at every start of a fabkit
// process, and its convex shapes cost more to build than the queries needed (docs/hacks.md).
#include "fabkit/core/collision.h"

#include <ccd/ccd.h>
#include <fcl/narrowphase/detail/convexity_based_algorithm/gjk_libccd-inl.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string_view>
#include <unordered_map>

// The one instantiation used, defined here (the header declares it extern for libfcl.so).
namespace fcl::detail {
template bool GJKDistance<double>(void* obj1,
                                  ccd_support_fn supp1,
                                  void* obj2,
                                  ccd_support_fn supp2,
                                  unsigned int max_iterations,
                                  double tolerance,
                                  double* dist,
                                  Vector3d* p1,
                                  Vector3d* p2);
}  // namespace fcl::detail

namespace fabkit::collision {

struct Body::Pieces {
  std::vector<int> tags;
  std::vector<Vec3> lo, hi;
  std::vector<Vec3> centre;
  std::vector<std::vector<Vec3>> vertices;
  std::vector<std::vector<Arc>> arcs;
};

Arc Arc::transformed(const Mat4& m) const {
  Arc out = *this;
  const Mat3 r = m.topLeftCorner<3, 3>();
  out.centre = r * centre + m.topRightCorner<3, 1>();
  out.u = r * u;
  out.v = r * v;
  return out;
}

Vec3 Arc::support(const Vec3& direction) const {
  const double du = direction.dot(u);
  const double dv = direction.dot(v);
  double a = from;
  if (std::hypot(du, dv) > 1e-15 * direction.norm()) {
    const double toward = std::atan2(dv, du);
    const double turn = std::remainder(toward - from - std::numbers::pi, 2 * std::numbers::pi) +
                        std::numbers::pi;  // toward - from, in [0, 2π)
    if (turn <= to - from) {
      a = from + turn;
    } else {
      a = std::cos(from - toward) >= std::cos(to - toward) ? from : to;
    }
  }
  return centre + radius * (std::cos(a) * u + std::sin(a) * v);
}

Body::Body(std::span<const TriangleMesh> pieces,
           std::span<const int> tags,
           std::span<const std::vector<Arc>> arcs) {
  auto out = std::make_shared<Pieces>();
  bool first = true;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const TriangleMesh& m = pieces[i];
    if (m.vertices.size() < 4 || m.faces.empty()) continue;
    out->tags.push_back(i < tags.size() ? tags[i] : -1);
    const std::vector<Arc> rims = i < arcs.size() ? arcs[i] : std::vector<Arc>{};
    Vec3 lo = m.bounds_min();
    Vec3 hi = m.bounds_max();
    for (const Arc& rim : rims) {
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], rim.support(-Vec3::Unit(k))[k]);
        hi[k] = std::max(hi[k], rim.support(Vec3::Unit(k))[k]);
      }
    }
    out->lo.push_back(lo);
    out->hi.push_back(hi);
    Vec3 c = Vec3::Zero();
    for (const Vec3& v : m.vertices) c += v;
    out->centre.push_back(c / static_cast<double>(m.vertices.size()));
    out->vertices.push_back(m.vertices);
    out->arcs.push_back(rims);
    min_ = first ? lo : min_.cwiseMin(lo);
    max_ = first ? hi : max_.cwiseMax(hi);
    first = false;
  }
  pieces_ = std::move(out);
}

int Body::piece_count() const {
  return pieces_ ? static_cast<int>(pieces_->tags.size()) : 0;
}
int Body::tag(int piece) const {
  return pieces_->tags.at(static_cast<std::size_t>(piece));
}
Vec3 Body::piece_min(int piece) const {
  return pieces_->lo.at(static_cast<std::size_t>(piece));
}
Vec3 Body::piece_max(int piece) const {
  return pieces_->hi.at(static_cast<std::size_t>(piece));
}

CachedBody& CachedBody::operator=(const CachedBody& other) {
  if (this != &other) {
    const std::lock_guard lock(mutex_);
    body_.reset();
  }
  return *this;
}

namespace {

// Bodies already built in this process, by their contents: a design's copies of one part (the
// S-hooks of a chain, the eye hooks of a basket) and later solves of the same parts share one
// set of pieces instead of building them per copy (24 S-hooks: a sixth
// of 8 independent cycles' solve). Keyed by every number the body is built from, compared
// exactly; bounded, and emptied when full (bodies in use live on in their owners).
class BodyLibrary {
 public:
  Body get(std::span<const TriangleMesh> pieces,
           std::span<const int> tags,
           std::span<const std::vector<Arc>> arcs) {
    std::vector<double> key;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      const TriangleMesh& m = pieces[i];
      key.push_back(static_cast<double>(m.vertices.size()));
      for (const Vec3& v : m.vertices) key.insert(key.end(), {v.x(), v.y(), v.z()});
      key.push_back(static_cast<double>(m.faces.size()));
      for (const Eigen::Vector3i& f : m.faces)
        key.insert(key.end(), {double(f[0]), double(f[1]), double(f[2])});
      key.push_back(i < tags.size() ? tags[i] : -1);
      if (i < arcs.size()) {
        key.push_back(static_cast<double>(arcs[i].size()));
        for (const Arc& a : arcs[i]) {
          key.insert(key.end(),
                     {a.centre.x(),
                      a.centre.y(),
                      a.centre.z(),
                      a.u.x(),
                      a.u.y(),
                      a.u.z(),
                      a.v.x(),
                      a.v.y(),
                      a.v.z(),
                      a.radius,
                      a.from,
                      a.to});
        }
      } else {
        key.push_back(-1);
      }
    }
    const std::size_t hash = std::hash<std::string_view>{}(
        std::string_view(reinterpret_cast<const char*>(key.data()), key.size() * sizeof(double)));
    const std::lock_guard lock(mutex_);
    auto [first, last] = bodies_.equal_range(hash);
    for (auto it = first; it != last; ++it) {
      if (it->second.first == key) return it->second.second;
    }
    if (bodies_.size() >= kCapacity) bodies_.clear();
    Body body(pieces, tags, arcs);
    bodies_.emplace(hash, std::make_pair(std::move(key), body));
    return body;
  }

 private:
  static constexpr std::size_t kCapacity = 512;
  std::mutex mutex_;
  std::unordered_multimap<std::size_t, std::pair<std::vector<double>, Body>> bodies_;
};

BodyLibrary& body_library() {
  static BodyLibrary library;
  return library;
}

}  // namespace

Body CachedBody::get(std::span<const TriangleMesh> pieces,
                     std::span<const int> tags,
                     std::span<const std::vector<Arc>> arcs) const {
  const std::lock_guard lock(mutex_);
  if (!body_ || built_from_ != pieces.data() || built_count_ != pieces.size() ||
      built_arc_count_ != arcs.size()) {
    body_ = body_library().get(pieces, tags, arcs);
    built_from_ = pieces.data();
    built_count_ = pieces.size();
    built_arc_count_ = arcs.size();
  }
  return *body_;
}

Box world_box(const Vec3& lo, const Vec3& hi, const Mat4& t) {
  const Mat3 r = t.topLeftCorner<3, 3>();
  const Vec3 c = r * (0.5 * (lo + hi)) + t.topRightCorner<3, 1>();
  const Vec3 half = r.cwiseAbs() * (0.5 * (hi - lo));
  return {c - half, c + half};
}

double box_gap(const Box& a, const Box& b) {
  return (b.lo - a.hi).cwiseMax(a.lo - b.hi).cwiseMax(Vec3::Zero()).norm();
}

double piece_gap_bound(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb) {
  return box_gap(world_box(a.piece_min(pa), a.piece_max(pa), ta),
                 world_box(b.piece_min(pb), b.piece_max(pb), tb));
}

namespace {

// A piece at a pose, for libccd's support-mapping algorithms.
struct Placed {
  const std::vector<Vec3>* vertices;
  const std::vector<Arc>* arcs;
  Mat3 r;
  Vec3 t;
  Vec3 centre;
};

void support(const void* obj, const ccd_vec3_t* dir, ccd_vec3_t* out) {
  const Placed& p = *static_cast<const Placed*>(obj);
  const Vec3 local = p.r.transpose() * Vec3(dir->v[0], dir->v[1], dir->v[2]);
  const Vec3* best = &p.vertices->front();
  double extent = local.dot(*best);
  for (const Vec3& v : *p.vertices) {
    const double e = local.dot(v);
    if (e > extent) {
      extent = e;
      best = &v;
    }
  }
  Vec3 point = *best;
  for (const Arc& rim : *p.arcs) {
    const Vec3 on = rim.support(local);
    if (local.dot(on) > extent) {
      extent = local.dot(on);
      point = on;
    }
  }
  const Vec3 w = p.r * point + p.t;
  ccdVec3Set(out, w.x(), w.y(), w.z());
}

// The point of a placed piece farthest along the world direction `direction`.
Vec3 farthest(const Placed& p, const Vec3& direction) {
  ccd_vec3_t dir, out;
  ccdVec3Set(&dir, direction.x(), direction.y(), direction.z());
  support(&p, &dir, &out);
  return Vec3(out.v[0], out.v[1], out.v[2]);
}

void centre(const void* obj, ccd_vec3_t* out) {
  const Placed& p = *static_cast<const Placed*>(obj);
  ccdVec3Set(out, p.centre.x(), p.centre.y(), p.centre.z());
}

Placed placed(const std::vector<Vec3>& vertices,
              const std::vector<Arc>& arcs,
              const Vec3& centre,
              const Mat4& t) {
  const Mat3 r = t.topLeftCorner<3, 3>();
  const Vec3 shift = t.topRightCorner<3, 1>();
  return {&vertices, &arcs, r, shift, r * centre + shift};
}

}  // namespace

DistanceBounds piece_distance_bounds(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb) {
  const Body::Pieces& A = *a.pieces_;
  const Body::Pieces& B = *b.pieces_;
  const auto ia = static_cast<std::size_t>(pa);
  const auto ib = static_cast<std::size_t>(pb);
  const Placed pa_world = placed(A.vertices[ia], A.arcs[ia], A.centre[ia], ta);
  const Placed pb_world = placed(B.vertices[ib], B.arcs[ib], B.centre[ib], tb);
  const Vec3 centres = pb_world.centre - pa_world.centre;
  if (!(centres.norm() > 1e-12)) {
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  }
  // Projected on a line, the pieces are intervals no farther apart than the pieces themselves
  // (projection shortens every distance); overlapping, their overlap there is at least the
  // depth that would separate them. The line of their centres is where that gap is usually
  // widest. The two points that bound it are points of the pieces, so no farther apart than
  // the pieces' nearest points are.
  const Vec3 n = centres.normalized();
  const Vec3 near_a = farthest(pa_world, n);
  const Vec3 near_b = farthest(pb_world, -n);
  return {n.dot(near_b - near_a), (near_b - near_a).norm()};
}

Proximity piece_distance(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb) {
  const Body::Pieces& A = *a.pieces_;
  const Body::Pieces& B = *b.pieces_;
  const auto ia = static_cast<std::size_t>(pa);
  const auto ib = static_cast<std::size_t>(pb);
  Proximity p;
  const Placed pa_world = placed(A.vertices[ia], A.arcs[ia], A.centre[ia], ta);
  const Placed pb_world = placed(B.vertices[ib], B.arcs[ib], B.centre[ib], tb);
  // Apart: GJK distance and nearest points, on each piece's exact support mapping (its
  // vertices and round rims). Overlaps go to libccd's MPR below. The tolerance of round pieces
  // is tight because their nearest points, and so the contact normal, converge only as the
  // square root of the distance's; flat pieces keep FCL's own (10⁻⁶ mm, 1,000 iterations).
  const bool round = !A.arcs[ia].empty() || !B.arcs[ib].empty();
  struct Nearest {
    double min_distance = -1;
    Vec3 nearest_points[2] = {Vec3::Zero(), Vec3::Zero()};
  };
  auto gjk = [&](const Vec3& shift) {
    Nearest out;
    Placed b_moved = pb_world;
    b_moved.t += shift;
    b_moved.centre += shift;
    Placed a_copy = pa_world;
    double d = -1;
    fcl::Vector3d near_a = fcl::Vector3d::Zero(), near_b = fcl::Vector3d::Zero();
    const unsigned iterations = round ? 500 : 1000;
    const double tolerance = round ? 1e-12 : 1e-6;
    if (fcl::detail::GJKDistance<double>(
            &a_copy, support, &b_moved, support, iterations, tolerance, &d, &near_a, &near_b)) {
      out.min_distance = d;
      out.nearest_points[0] = near_a;
      out.nearest_points[1] = near_b;
    }
    return out;
  };
  const Nearest result = gjk(Vec3::Zero());
  // Round pieces: GJK finds their nearest points only to about 1e-9 mm, so when they (nearly)
  // touch, the direction between those points is not the normal. Moving b away along the
  // true normal keeps the same nearest points; moving it along a guess tilts the normal found
  // by about the guess's error times the move over the radius of curvature, so a few moves,
  // each along the normal the last one found, converge to it.
  auto refine_round = [&](Vec3 guess, double distance_now) {
    constexpr double kShiftMm = 0.02;
    bool found = false;
    for (int k = 0; k < 4; ++k) {
      const Vec3 shift = (kShiftMm + std::max(0.0, -distance_now)) * guess;
      const Nearest apart = gjk(shift);
      if (!(apart.min_distance > 1e-9)) break;
      const Vec3 b_moved = apart.nearest_points[1];
      const Vec3 normal = (b_moved - Vec3(apart.nearest_points[0])).normalized();
      p.distance = distance_now;
      p.point_a = apart.nearest_points[0];
      p.point_b = b_moved - shift;
      p.normal = normal;
      found = true;
      if ((normal - guess).norm() < 1e-12) break;
      guess = normal;
    }
    return found;
  };
  const Vec3 centres = pb_world.centre - pa_world.centre;
  const Vec3 centre_line = centres.norm() > 1e-12 ? Vec3(centres.normalized()) : Vec3::UnitZ();
  if (result.min_distance > 1e-9) {
    p.distance = result.min_distance;
    p.point_a = result.nearest_points[0];
    p.point_b = result.nearest_points[1];
    const Vec3 d = p.point_b - p.point_a;
    p.normal = d.norm() > 1e-12 ? Vec3(d.normalized()) : centre_line;
    constexpr double kRoundNormalExactBeyondMm = 1e-3;
    if (round && p.distance < kRoundNormalExactBeyondMm) {
      const Vec3 guess = p.distance > 1e-6 ? p.normal : centre_line;
      refine_round(guess, p.distance);
    }
    return p;
  }
  // Overlapping (or touching): the penetration depth and the direction that separates b
  // from a, by Minkowski portal refinement.
  ccd_t ccd;
  CCD_INIT(&ccd);
  ccd.support1 = support;
  ccd.support2 = support;
  ccd.center1 = centre;
  ccd.center2 = centre;
  ccd.max_iterations = 200;
  ccd.mpr_tolerance = 1e-7;
  ccd_real_t depth = 0;
  ccd_vec3_t dir, pos;
  // Touching or barely overlapping, the contact normal is what a solver needs and the
  // algorithms do not give it: GJK's nearest points coincide and MPR's portal direction is
  // arbitrary near depth 0. Moving b a little away from a (along the line between their
  // centres, which points to b's side of any plane separating them) and asking GJK gives the
  // real normal: for a face against a vertex, that face's.
  auto from_separated = [&](double depth_now) {
    if (round) return refine_round(centre_line, -depth_now);
    const Vec3 away = centre_line;
    for (const double step : {0.05, 1.0}) {
      const Vec3 shift = step * away;
      const Nearest apart = gjk(shift);
      if (apart.min_distance > 1e-9) {
        p.distance = -depth_now;
        p.point_a = apart.nearest_points[0];
        p.point_b = Vec3(apart.nearest_points[1]) - shift;
        p.normal = (Vec3(apart.nearest_points[1]) - p.point_a).normalized();
        return true;
      }
    }
    return false;
  };
  if (ccdMPRPenetration(&pa_world, &pb_world, &ccd, &depth, &dir, &pos) != 0) {
    // MPR sees no overlap: they touch.
    if (from_separated(0.0)) return p;
    p.distance = 0;
    p.point_a = result.nearest_points[0];
    p.point_b = result.nearest_points[1];
    const Vec3 c = pb_world.centre - pa_world.centre;
    p.normal = c.norm() > 1e-12 ? Vec3(c.normalized()) : Vec3::UnitZ();
    return p;
  }
  if (depth < 1e-4 && from_separated(depth)) return p;
  p.distance = -depth;
  p.normal = Vec3(dir.v[0], dir.v[1], dir.v[2]);
  if (p.normal.norm() < 1e-12) p.normal = Vec3::UnitZ();
  p.normal.normalize();
  const Vec3 at(pos.v[0], pos.v[1], pos.v[2]);
  // The deepest points of each inside the other, on either side of the contact position.
  p.point_a = at + 0.5 * depth * p.normal;
  p.point_b = at - 0.5 * depth * p.normal;
  return p;
}

}  // namespace fabkit::collision

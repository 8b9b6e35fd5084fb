// The only translation unit that includes FCL.
#include "fabkit/core/collision.h"

#include <ccd/ccd.h>
#include <fcl/fcl.h>

#include <algorithm>
#include <limits>

namespace fabkit::collision {

struct Body::Pieces {
  std::vector<std::shared_ptr<fcl::Convexd>> shapes;
  std::vector<int> tags;
  std::vector<Vec3> lo, hi;
  std::vector<Vec3> centre;
  std::vector<std::vector<Vec3>> vertices;
};

Body::Body(std::span<const TriangleMesh> pieces, std::span<const int> tags) {
  auto out = std::make_shared<Pieces>();
  bool first = true;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const TriangleMesh& m = pieces[i];
    if (m.vertices.size() < 4 || m.faces.empty()) continue;
    auto vertices = std::make_shared<std::vector<fcl::Vector3d>>();
    vertices->reserve(m.vertices.size());
    for (const Vec3& v : m.vertices) vertices->emplace_back(v.x(), v.y(), v.z());
    auto faces = std::make_shared<std::vector<int>>();
    faces->reserve(m.faces.size() * 4);
    for (const Eigen::Vector3i& f : m.faces) {
      faces->push_back(3);
      faces->push_back(f[0]);
      faces->push_back(f[1]);
      faces->push_back(f[2]);
    }
    // Faces are only a hint for FCL's vertex walk; a piece whose triangulation it does not
    // accept is searched vertex by vertex (no throw).
    auto shape = std::make_shared<fcl::Convexd>(
        vertices, static_cast<int>(m.faces.size()), faces, /*throw_if_invalid=*/false);
    shape->computeLocalAABB();
    out->shapes.push_back(std::move(shape));
    out->tags.push_back(i < tags.size() ? tags[i] : -1);
    const Vec3 lo = m.bounds_min();
    const Vec3 hi = m.bounds_max();
    out->lo.push_back(lo);
    out->hi.push_back(hi);
    Vec3 c = Vec3::Zero();
    for (const Vec3& v : m.vertices) c += v;
    out->centre.push_back(c / static_cast<double>(m.vertices.size()));
    out->vertices.push_back(m.vertices);
    min_ = first ? lo : min_.cwiseMin(lo);
    max_ = first ? hi : max_.cwiseMax(hi);
    first = false;
  }
  pieces_ = std::move(out);
}

int Body::piece_count() const {
  return pieces_ ? static_cast<int>(pieces_->shapes.size()) : 0;
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

Body CachedBody::get(std::span<const TriangleMesh> pieces, std::span<const int> tags) const {
  const std::lock_guard lock(mutex_);
  if (!body_ || built_from_ != pieces.data() || built_count_ != pieces.size()) {
    body_.emplace(pieces, tags);
    built_from_ = pieces.data();
    built_count_ = pieces.size();
  }
  return *body_;
}

namespace {

fcl::Transform3d to_fcl(const Mat4& m) {
  fcl::Transform3d t = fcl::Transform3d::Identity();
  t.linear() = m.topLeftCorner<3, 3>();
  t.translation() = m.topRightCorner<3, 1>();
  return t;
}

}  // namespace

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
  const Vec3 w = p.r * *best + p.t;
  ccdVec3Set(out, w.x(), w.y(), w.z());
}

void centre(const void* obj, ccd_vec3_t* out) {
  const Placed& p = *static_cast<const Placed*>(obj);
  ccdVec3Set(out, p.centre.x(), p.centre.y(), p.centre.z());
}

}  // namespace

Proximity piece_distance(
    const Body& a, int pa, const Mat4& ta, const Body& b, int pb, const Mat4& tb) {
  const Body::Pieces& A = *a.pieces_;
  const Body::Pieces& B = *b.pieces_;
  const auto ia = static_cast<std::size_t>(pa);
  const auto ib = static_cast<std::size_t>(pb);
  Proximity p;
  // Apart: FCL's GJK distance and nearest points. (Its signed distance runs EPA, which
  // asserts on touching and nearly degenerate pairs; overlaps go to libccd's MPR below.)
  fcl::DistanceRequestd request;
  request.enable_nearest_points = true;
  request.enable_signed_distance = false;
  request.gjk_solver_type = fcl::GST_LIBCCD;
  fcl::DistanceResultd result;
  fcl::distance(A.shapes[ia].get(), to_fcl(ta), B.shapes[ib].get(), to_fcl(tb), request, result);
  const Placed pa_world{&A.vertices[ia],
                        ta.topLeftCorner<3, 3>(),
                        ta.topRightCorner<3, 1>(),
                        ta.topLeftCorner<3, 3>() * A.centre[ia] + ta.topRightCorner<3, 1>()};
  const Placed pb_world{&B.vertices[ib],
                        tb.topLeftCorner<3, 3>(),
                        tb.topRightCorner<3, 1>(),
                        tb.topLeftCorner<3, 3>() * B.centre[ib] + tb.topRightCorner<3, 1>()};
  if (result.min_distance > 1e-9) {
    p.distance = result.min_distance;
    p.point_a = result.nearest_points[0];
    p.point_b = result.nearest_points[1];
    const Vec3 d = p.point_b - p.point_a;
    p.normal = d.norm() > 1e-12 ? Vec3(d.normalized())
                                : Vec3((pb_world.centre - pa_world.centre).normalized());
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
    const Vec3 c = pb_world.centre - pa_world.centre;
    const Vec3 away = c.norm() > 1e-12 ? Vec3(c.normalized()) : Vec3::UnitZ();
    for (const double step : {0.05, 1.0}) {
      const Vec3 shift = step * away;
      Mat4 moved = tb;
      moved.topRightCorner<3, 1>() += shift;
      fcl::DistanceResultd apart;
      fcl::distance(
          A.shapes[ia].get(), to_fcl(ta), B.shapes[ib].get(), to_fcl(moved), request, apart);
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

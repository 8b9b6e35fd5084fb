#include "fabkit/rods/check.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "fabkit/core/mesh_boolean.h"
#include "fabkit/rods/diagnostic_codes.h"
#include "fabkit/rods/joint_geometry.h"

namespace fabkit::rods {
namespace {

using Vec2 = Eigen::Vector2d;

double cross(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x();
}

// Andrew's monotone chain; counter-clockwise, no collinear points.
std::vector<Vec2> hull_2d(std::vector<Vec2> pts) {
  std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  pts.erase(std::unique(pts.begin(),
                        pts.end(),
                        [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1e-9; }),
            pts.end());
  if (pts.size() < 3) return pts;
  std::vector<Vec2> h(2 * pts.size());
  std::size_t k = 0;
  for (const Vec2& p : pts) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p) <= 1e-12) --k;
    h[k++] = p;
  }
  for (std::size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], pts[i]) <= 1e-12) --k;
    h[k++] = pts[i];
  }
  h.resize(k - 1);
  return h;
}

double point_segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + t * ab)).norm();
}

std::string list_joints(const Structure& s, const std::vector<int>& nodes) {
  std::string out;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (i == 6 && nodes.size() > 7) return out + fmt::format(" and {} more", nodes.size() - 6);
    out += (i ? ", " : "") + s.joint_label(nodes[i]);
  }
  return out;
}

}  // namespace

SegmentDistance segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1) {
  // Ericson, Real-Time Collision Detection §5.1.9.
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  constexpr double kEps = 1e-18;
  double s = 0, t = 0;
  if (a <= kEps && e <= kEps) {
    return {r.norm(), 0, 0};
  }
  if (a <= kEps) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= kEps) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      const double denom = a * e - b * b;
      s = denom > kEps * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return {((p0 + s * d1) - (q0 + t * d2)).norm(), s, t};
}

std::vector<RodPair> find_rod_intersections(const Structure& s,
                                            const Parameters& p,
                                            const Layout& l,
                                            double extra_clearance,
                                            std::optional<RodPair>* closest) {
  struct Segment {
    int rod;
    Vec3 a, b, lo, hi;
  };
  const double reach = p.radius + std::max(0.0, extra_clearance) / 2;
  std::vector<Segment> segs;
  segs.reserve(s.rods.size());
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    if (l.rod_length[e] <= 0) continue;
    const RodEnd& end = l.ends[e][0];
    const Vec3& origin = s.nodes[static_cast<std::size_t>(end.node)].position;
    const Vec3 a = origin + end.offset * end.direction;
    const Vec3 b = origin + (end.offset + l.rod_length[e]) * end.direction;
    segs.push_back(
        {static_cast<int>(e), a, b, a.cwiseMin(b).array() - reach, a.cwiseMax(b).array() + reach});
  }
  std::sort(segs.begin(), segs.end(), [](const Segment& x, const Segment& y) {
    return x.lo.x() < y.lo.x();
  });
  std::vector<RodPair> hits;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const Segment& u = segs[i];
    const Rod& ru = s.rods[static_cast<std::size_t>(u.rod)];
    for (std::size_t j = i + 1; j < segs.size() && segs[j].lo.x() <= u.hi.x(); ++j) {
      const Segment& v = segs[j];
      if (v.lo.y() > u.hi.y() || v.hi.y() < u.lo.y() || v.lo.z() > u.hi.z() || v.hi.z() < u.lo.z())
        continue;
      const Rod& rv = s.rods[static_cast<std::size_t>(v.rod)];
      if (ru.a == rv.a || ru.a == rv.b || ru.b == rv.a || ru.b == rv.b) continue;
      const SegmentDistance d = segment_distance(u.a, u.b, v.a, v.b);
      const double clearance = d.distance - 2 * p.radius;
      if (clearance > extra_clearance) continue;
      const Vec3 mid = 0.5 * ((u.a + d.s * (u.b - u.a)) + (v.a + d.t * (v.b - v.a)));
      RodPair pair{std::min(u.rod, v.rod), std::max(u.rod, v.rod), d.distance, clearance, mid};
      if (closest && (!*closest || clearance < (*closest)->clearance)) *closest = pair;
      if (clearance < 0) hits.push_back(pair);
    }
  }
  std::sort(hits.begin(), hits.end(), [](const RodPair& x, const RodPair& y) {
    return std::tie(x.rod_a, x.rod_b) < std::tie(y.rod_a, y.rod_b);
  });
  return hits;
}

std::vector<JointMass> estimate_joint_masses(const Structure& s,
                                             const Parameters& p,
                                             const Layout& l) {
  std::vector<JointMass> out;
  out.reserve(s.nodes.size());
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const JointPieces pieces = joint_pieces(s, p, l, static_cast<int>(i), 1.0 / 1024, false);
    out.push_back(estimate_joint_mass(s, p, l, static_cast<int>(i), pieces));
  }
  return out;
}

Balance compute_balance(const Structure& s,
                        const Parameters& p,
                        const Layout& l,
                        std::span<const JointMass> joints,
                        double ground_tolerance,
                        std::span<const PointLoad> loads,
                        double gravity) {
  Balance b;
  Vec3 moment = Vec3::Zero();
  const double rod_kg_per_mm = p.rod_material.density * 1e-9 * p.section_area();
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    const double length = std::max(0.0, l.rod_length[e]);
    const double m = rod_kg_per_mm * length;
    const RodEnd& end = l.ends[e][0];
    const Vec3 center = s.nodes[static_cast<std::size_t>(end.node)].position +
                        (end.offset + length / 2) * end.direction;
    b.mass += m;
    moment += m * center;
  }
  for (const JointMass& j : joints) {
    b.mass += j.mass;
    moment += j.mass * j.center;
  }
  for (const PointLoad& load : loads) {
    const double m = std::max(0.0, -load.force.z()) / gravity;
    b.mass += m;
    moment += m * s.nodes[static_cast<std::size_t>(load.node)].position;
  }
  b.center_of_mass = b.mass > 0 ? Vec3(moment / b.mass) : Vec3::Zero();
  b.ground_z = std::numeric_limits<double>::infinity();
  for (const Node& n : s.nodes) b.ground_z = std::min(b.ground_z, n.position.z());
  std::vector<Vec2> contacts;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    if (s.nodes[i].position.z() <= b.ground_z + ground_tolerance) {
      b.ground_nodes.push_back(static_cast<int>(i));
      contacts.emplace_back(s.nodes[i].position.x(), s.nodes[i].position.y());
    }
  }
  b.support_polygon = hull_2d(contacts);
  const Vec2 c(b.center_of_mass.x(), b.center_of_mass.y());
  const auto& poly = b.support_polygon;
  double boundary = std::numeric_limits<double>::infinity();
  if (poly.size() == 1) boundary = (c - poly[0]).norm();
  for (std::size_t k = 0; k < poly.size() && poly.size() > 1; ++k) {
    boundary = std::min(boundary, point_segment_distance(c, poly[k], poly[(k + 1) % poly.size()]));
  }
  bool inside = poly.size() >= 3;
  for (std::size_t k = 0; k < poly.size() && inside; ++k) {
    inside = cross(poly[k], poly[(k + 1) % poly.size()], c) > 0;
  }
  b.margin = inside ? boundary : -boundary;
  b.stands = b.margin > 1e-9;
  return b;
}

CheckReport check(const Structure& s,
                  const Parameters& p,
                  const Layout& l,
                  const CheckOptions& options,
                  std::span<const JointMass> joint_masses) {
  CheckReport r;
  r.red_rods.assign(s.rods.size(), false);
  r.red_joints.assign(s.nodes.size(), false);
  auto mark_rod = [&](int e) {
    r.red_rods[static_cast<std::size_t>(e)] = true;
    r.red_joints[static_cast<std::size_t>(s.rods[static_cast<std::size_t>(e)].a)] = true;
    r.red_joints[static_cast<std::size_t>(s.rods[static_cast<std::size_t>(e)].b)] = true;
  };
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    const auto& ends = l.ends[e];
    const double ga = ends[0].offset, gb = ends[1].offset, L = l.edge_length[e];
    const std::string name = s.rod_name(static_cast<int>(e));
    const SourceLocation& where = s.rods[e].where;
    if (l.rod_length[e] <= 0) {
      r.findings.error(
          codes::kNoRodLeft,
          fmt::format("{}: the offsets {:.2f} mm (at joint {}) and {:.2f} mm (at joint {}) "
                      "leave no rod on the {:.2f} mm edge (ℓ = {:.2f} mm); widen the "
                      "angles at its joints or lengthen the edge",
                      name,
                      ga,
                      s.joint_label(ends[0].node),
                      gb,
                      s.joint_label(ends[1].node),
                      L,
                      l.rod_length[e]),
          where);
      mark_rod(static_cast<int>(e));
      r.swallowed_rods.push_back(static_cast<int>(e));
      continue;
    }
    if (ga + gb + 2 * p.socket > L) {
      r.findings.error(
          codes::kJointSwallowsRod,
          fmt::format("{}: joints {} and {} overlap and swallow the rod: offsets {:.2f} + "
                      "{:.2f} mm plus 2 × {:g} mm sockets = {:.2f} mm exceed the edge "
                      "length {:.2f} mm",
                      name,
                      s.joint_label(ends[0].node),
                      s.joint_label(ends[1].node),
                      ga,
                      gb,
                      p.socket,
                      ga + gb + 2 * p.socket,
                      L),
          where);
      mark_rod(static_cast<int>(e));
      r.swallowed_rods.push_back(static_cast<int>(e));
    }
    if (l.rod_length[e] < p.min_rod_length) {
      r.findings.error(
          codes::kRodTooShort,
          fmt::format("{} is {:.2f} mm long, shorter than the minimum rod length {:g} mm",
                      name,
                      l.rod_length[e],
                      p.min_rod_length),
          where);
      r.red_rods[e] = true;
      r.short_rods.push_back(static_cast<int>(e));
    }
  }
  std::optional<RodPair> closest;
  r.intersections = find_rod_intersections(s, p, l, options.near_miss, &closest);
  for (const RodPair& pair : r.intersections) {
    r.findings.error(
        codes::kRodsIntersect,
        fmt::format("{} and {} intersect: their axes come {:.2f} mm apart, less than 2r = "
                    "{:.2f} mm (overlap {:.2f} mm) near [{:.1f}, {:.1f}, {:.1f}]",
                    s.rod_name(pair.rod_a),
                    s.rod_name(pair.rod_b),
                    pair.distance,
                    2 * p.radius,
                    -pair.clearance,
                    pair.point.x(),
                    pair.point.y(),
                    pair.point.z()),
        s.rods[static_cast<std::size_t>(pair.rod_b)].where);
    r.red_rods[static_cast<std::size_t>(pair.rod_a)] = true;
    r.red_rods[static_cast<std::size_t>(pair.rod_b)] = true;
  }
  if (closest && closest->clearance >= 0) {
    r.closest_pair = closest;
    r.findings.note(codes::kRodsIntersect,
                    fmt::format("closest rods: {} and {} pass {:.2f} mm apart (surface to surface)",
                                s.rod_name(closest->rod_a),
                                s.rod_name(closest->rod_b),
                                closest->clearance));
  } else if (closest) {
    r.closest_pair = closest;
  }

  // Connectivity: a structure in pieces is assembled (and stands) as separate objects.
  {
    std::vector<int> component(s.nodes.size(), -1);
    int count = 0;
    for (std::size_t start = 0; start < s.nodes.size(); ++start) {
      if (component[start] >= 0) continue;
      std::vector<int> stack = {static_cast<int>(start)};
      component[start] = count;
      while (!stack.empty()) {
        const int i = stack.back();
        stack.pop_back();
        for (const int e : l.rods_at[static_cast<std::size_t>(i)]) {
          const Rod& rod = s.rods[static_cast<std::size_t>(e)];
          const int j = rod.a == i ? rod.b : rod.a;
          if (component[static_cast<std::size_t>(j)] < 0) {
            component[static_cast<std::size_t>(j)] = count;
            stack.push_back(j);
          }
        }
      }
      ++count;
    }
    if (count > 1) {
      r.findings.warning(
          codes::kDisconnected,
          fmt::format("the structure is in {} separate pieces; each is assembled and "
                      "stands on its own",
                      count));
    }
  }

  if (options.balance) {
    std::vector<JointMass> estimated;
    if (joint_masses.empty()) {
      estimated = estimate_joint_masses(s, p, l);
      joint_masses = estimated;
    }
    r.balance = compute_balance(
        s, p, l, joint_masses, options.ground_tolerance, options.loads, options.gravity);
    const Balance& b = r.balance;
    const std::string contacts = list_joints(s, b.ground_nodes);
    if (!b.stands) {
      r.findings.error(
          codes::kUnbalanced,
          fmt::format("unbalanced: the centre of mass [{:.1f}, {:.1f}, {:.1f}] mm ({:.3f} kg) "
                      "projects {:.1f} mm outside the support polygon of joint{} {} on "
                      "the floor z = {:g} mm; it tips over",
                      b.center_of_mass.x(),
                      b.center_of_mass.y(),
                      b.center_of_mass.z(),
                      b.mass,
                      -b.margin,
                      b.ground_nodes.size() == 1 ? "" : "s",
                      contacts,
                      b.ground_z));
      for (const int i : b.ground_nodes) r.red_joints[static_cast<std::size_t>(i)] = true;
    } else {
      r.findings.note(
          codes::kUnbalanced,
          fmt::format("balanced: the centre of mass ({:.3f} kg) projects {:.1f} mm inside "
                      "the support polygon of joints {}",
                      b.mass,
                      b.margin,
                      contacts));
    }
  }
  return r;
}

}  // namespace fabkit::rods

#include "fabkit/rods/joint_geometry.h"

#include <cmath>
#include <numbers>

#include "fabkit/core/mesh_boolean.h"

namespace fabkit::rods {

namespace {
// Snapping to dyadic grids makes radius × (cos, sin) exact in double: every ring vertex at
// angle k is then an exact multiple of the same (cos, sin), so rings of different radii are
// exactly radially aligned (and stay so under the exact placements of the booleans). Without
// it, points meant to lie on one line miss it by an ulp, and exact booleans turn such near
// misses into slivers that fold when the result is rounded back to double.
double snap(double v, double grid) {
  return std::round(v / grid) * grid;
}
constexpr double kLengthGrid = 1.0 / (1 << 20);  // mm (~1 nm)
constexpr double kUnitGrid = 1.0 / (1 << 24);
}  // namespace

TriangleMesh local_prism(double radius, int sides, double t0, double t1, double t1_ring_radius) {
  TriangleMesh m;
  radius = snap(radius, kLengthGrid);
  t0 = snap(t0, kLengthGrid);
  t1 = snap(t1, kLengthGrid);
  t1_ring_radius = snap(t1_ring_radius, kLengthGrid);
  const bool ring = t1_ring_radius > 0 && t1_ring_radius < radius;
  m.vertices.reserve(static_cast<std::size_t>((ring ? 3 : 2) * sides + 2));
  std::vector<double> c(static_cast<std::size_t>(sides)), s(static_cast<std::size_t>(sides));
  for (int k = 0; k < sides; ++k) {
    const double a = 2 * std::numbers::pi * k / sides;
    c[static_cast<std::size_t>(k)] = snap(std::cos(a), kUnitGrid);
    s[static_cast<std::size_t>(k)] = snap(std::sin(a), kUnitGrid);
  }
  for (const double t : {t0, t1}) {
    for (int k = 0; k < sides; ++k) {
      m.vertices.emplace_back(
          radius * c[static_cast<std::size_t>(k)], radius * s[static_cast<std::size_t>(k)], t);
    }
  }
  for (int k = 0; k < sides; ++k) {
    const int k1 = (k + 1) % sides;
    m.faces.emplace_back(k, k1, sides + k1);
    m.faces.emplace_back(k, sides + k1, sides + k);
  }
  // Caps as fans around their centres (no needle triangles for the booleans to cut up).
  const int bottom = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, t0);
  const int top = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0, 0, t1);
  int inner = sides;  // the t1 cap's inner boundary: the outer ring, or the extra ring
  if (ring) {
    inner = static_cast<int>(m.vertices.size());
    for (int k = 0; k < sides; ++k) {
      // The same products as a socket of this radius computes, bit for bit.
      m.vertices.emplace_back(t1_ring_radius * c[static_cast<std::size_t>(k)],
                              t1_ring_radius * s[static_cast<std::size_t>(k)],
                              t1);
    }
  }
  for (int k = 0; k < sides; ++k) {
    const int k1 = (k + 1) % sides;
    m.faces.emplace_back(bottom, k1, k);
    if (ring) {
      m.faces.emplace_back(inner + k, sides + k, sides + k1);
      m.faces.emplace_back(inner + k, sides + k1, inner + k1);
    }
    m.faces.emplace_back(top, inner + k, inner + k1);
  }
  return m;
}

namespace {
Mat4 placement_of(const Mat3& frame, const Vec3& origin) {
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() = frame;
  m.topRightCorner<3, 1>() = origin;
  return m;
}
}  // namespace

TriangleMesh profile_prism(
    const Mat3& frame, const Vec3& origin, double radius, int sides, double t0, double t1) {
  return local_prism(radius, sides, t0, t1).transformed(placement_of(frame, origin));
}

JointPieces joint_pieces(const Structure& s,
                         const Parameters& p,
                         const Layout& l,
                         int node,
                         double separation,
                         bool exact_operands) {
  (void)s;
  JointPieces j;
  const int sides = p.profile_sides();
  SolidInput hull;
  hull.hull.push_back(PlacedPoints{{Vec3::Zero()}, Mat4::Identity()});
  std::vector<Vec3> hull_points = {Vec3::Zero()};
  const auto ends = l.ends_at(node);
  std::vector<double> outer(ends.size()), socket_radius(ends.size());
  for (std::size_t k = 0; k < ends.size(); ++k) {
    outer[k] = p.radius + p.wall + static_cast<double>(k) * separation;
    socket_radius[k] = p.socket_circumradius() + static_cast<double>(k) * separation;
  }
  for (std::size_t k = 0; k < ends.size(); ++k) {
    const RodEnd* end = ends[k];
    const double g = end->offset;
    const Mat4 place = placement_of(end->frame, Vec3::Zero());
    TriangleMesh prism = local_prism(outer[k], sides, g - p.wall, g + p.socket, socket_radius[k]);
    // The inner ring V_ij: the prism's first `sides` vertices, placed exactly for the hull.
    PlacedPoints ring{{prism.vertices.begin(), prism.vertices.begin() + sides}, place};
    for (const Vec3& v : ring.points) hull_points.push_back(end->frame * v);
    j.reach = std::max(j.reach, g + p.socket + outer[k]);
    j.prisms.push_back(prism.transformed(place));
    if (exact_operands) {
      hull.hull.push_back(std::move(ring));
      j.add.push_back(SolidInput{std::move(prism), place, {}});
    }
  }
  for (const Vec3& v : hull_points) j.reach = std::max(j.reach, v.norm());
  j.hull = convex_hull(hull_points);
  if (!j.hull.empty() && exact_operands) j.add.insert(j.add.begin(), std::move(hull));
  for (std::size_t k = 0; k < ends.size(); ++k) {
    const RodEnd* end = ends[k];
    const double g = end->offset;
    const double full = l.rod_length[static_cast<std::size_t>(end->rod)] + 2 * p.tolerance;
    const double length = std::min(full, j.reach + 1 - (g - p.tolerance));
    j.socket_length.push_back(length);
    if (length <= 0) {
      j.sockets.emplace_back();
      continue;
    }
    const Mat4 place = placement_of(end->frame, Vec3::Zero());
    TriangleMesh socket =
        local_prism(socket_radius[k], sides, g - p.tolerance, g - p.tolerance + length);
    j.sockets.push_back(socket.transformed(place));
    j.subtract.push_back(SolidInput{std::move(socket), place, {}});
  }
  return j;
}

TriangleMesh rod_mesh(const Structure& s, const Parameters& p, const Layout& l, int rod) {
  const RodEnd& a = l.ends[static_cast<std::size_t>(rod)][0];
  const Vec3& origin = s.nodes[static_cast<std::size_t>(a.node)].position;
  const double start = a.offset;
  const double end = start + std::max(l.rod_length[static_cast<std::size_t>(rod)], 1e-6);
  return profile_prism(a.frame, origin, p.radius, p.profile_sides(), start, end);
}

Preview make_preview(const Structure& s, const Parameters& p, const Layout& l) {
  Preview v;
  v.joints.reserve(s.nodes.size());
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    JointPieces pieces = joint_pieces(s, p, l, static_cast<int>(i), 1.0 / 1024, false);
    v.joint_masses.push_back(estimate_joint_mass(s, p, l, static_cast<int>(i), pieces));
    TriangleMesh joint = std::move(pieces.hull);
    for (const TriangleMesh& prism : pieces.prisms) joint.append(prism);
    const Vec3& at = s.nodes[i].position;
    joint.transform(translation(at.x(), at.y(), at.z()));
    v.joints.push_back(std::move(joint));
  }
  v.rods.reserve(s.rods.size());
  for (std::size_t e = 0; e < s.rods.size(); ++e) {
    v.rods.push_back(rod_mesh(s, p, l, static_cast<int>(e)));
  }
  return v;
}

JointMass estimate_joint_mass(
    const Structure& s, const Parameters& p, const Layout& l, int node, const JointPieces& pieces) {
  const int sides = p.profile_sides();
  auto area = [&](double circumradius) {
    return 0.5 * sides * circumradius * circumradius * std::sin(2 * std::numbers::pi / sides);
  };
  const double shell = area(p.radius + p.wall) * (p.socket + p.wall) -
                       area(p.socket_circumradius()) * (p.socket + p.tolerance);
  double volume = pieces.hull.empty() ? 0 : pieces.hull.volume();
  Vec3 moment = volume * (pieces.hull.empty() ? Vec3::Zero() : pieces.hull.centroid());
  for (const RodEnd* end : l.ends_at(node)) {
    volume += shell;
    moment += shell * (end->offset + (p.socket - p.wall) / 2) * end->direction;
  }
  JointMass m;
  m.mass = std::max(0.0, volume) * p.joint_material.density * 1e-9;
  m.center = s.nodes[static_cast<std::size_t>(node)].position +
             (volume > 0 ? Vec3(moment / volume) : Vec3::Zero());
  return m;
}

Mat4 print_pose(const Layout& l, int node, const TriangleMesh& local_mesh) {
  Vec3 sum = Vec3::Zero();
  for (const RodEnd* end : l.ends_at(node)) sum += end->direction;
  Mat4 pose = Mat4::Identity();
  if (sum.norm() > 1e-9) pose.topLeftCorner<3, 3>() = rotation_to(sum.normalized()).transpose();
  const TriangleMesh turned = local_mesh.transformed(pose);
  const Vec3 lo = turned.bounds_min(), hi = turned.bounds_max();
  const Vec3 shift(-(lo.x() + hi.x()) / 2, -(lo.y() + hi.y()) / 2, -lo.z());
  return translation(shift.x(), shift.y(), shift.z()) * pose;
}

}  // namespace fabkit::rods

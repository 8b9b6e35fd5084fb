#include "fabkit/core/mesh.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace fabkit {

void TriangleMesh::append(const TriangleMesh& other) {
  const int offset = static_cast<int>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  faces.reserve(faces.size() + other.faces.size());
  for (const auto& f : other.faces) faces.emplace_back(f.array() + offset);
}

void TriangleMesh::transform(const Mat4& m) {
  const Mat3 r = m.topLeftCorner<3, 3>();
  const Vec3 t = m.topRightCorner<3, 1>();
  for (auto& v : vertices) v = r * v + t;
}

TriangleMesh TriangleMesh::transformed(const Mat4& m) const {
  TriangleMesh copy = *this;
  copy.transform(m);
  return copy;
}

double TriangleMesh::volume() const {
  double six_v = 0.0;
  for (const auto& f : faces) {
    const Vec3& a = vertices[f[0]];
    const Vec3& b = vertices[f[1]];
    const Vec3& c = vertices[f[2]];
    six_v += a.dot(b.cross(c));
  }
  return six_v / 6.0;
}

Vec3 TriangleMesh::centroid() const {
  if (vertices.empty()) return Vec3::Zero();
  double six_v = 0.0;
  Vec3 weighted = Vec3::Zero();
  for (const auto& f : faces) {
    const Vec3& a = vertices[f[0]];
    const Vec3& b = vertices[f[1]];
    const Vec3& c = vertices[f[2]];
    const double t = a.dot(b.cross(c));  // 6 × volume of the origin tetrahedron
    six_v += t;
    weighted += t * (a + b + c);  // the tetrahedron's centroid is (0 + a + b + c) / 4
  }
  // "~0" relative to the size of the mesh, so that tiny and huge meshes behave alike.
  const double diag = (bounds_max() - bounds_min()).norm();
  const double eps = 1e-12 * diag * diag * diag;
  if (faces.empty() || std::abs(six_v) <= eps) {
    Vec3 sum = Vec3::Zero();
    for (const auto& v : vertices) sum += v;
    return sum / static_cast<double>(vertices.size());
  }
  return weighted / (4.0 * six_v);
}

Vec3 TriangleMesh::bounds_min() const {
  if (empty() || vertices.empty()) return Vec3::Zero();
  Vec3 lo = vertices.front();
  for (const auto& v : vertices) lo = lo.cwiseMin(v);
  return lo;
}

Vec3 TriangleMesh::bounds_max() const {
  if (empty() || vertices.empty()) return Vec3::Zero();
  Vec3 hi = vertices.front();
  for (const auto& v : vertices) hi = hi.cwiseMax(v);
  return hi;
}

namespace shapes {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// A point of a revolution profile: distance from the z axis and height.
struct ProfilePoint {
  double rho;
  double z;
};

/// Surface of revolution about z, with the azimuth increasing counter-clockwise seen from +z.
/// The profile must be ordered so that (profile direction) × e_phi points out of the solid:
/// top to bottom along the outside (a sphere's meridian from the north pole down).
/// Points with rho == 0 become single pole vertices. If `closed_profile`, the last point
/// connects back to the first.
TriangleMesh revolve(const std::vector<ProfilePoint>& profile, bool closed_profile, int slices) {
  TriangleMesh mesh;
  const int n = std::max(3, slices);
  // first vertex index of each profile point; poles have one vertex, rings n.
  std::vector<int> start(profile.size());
  std::vector<bool> pole(profile.size());
  for (std::size_t k = 0; k < profile.size(); ++k) {
    start[k] = static_cast<int>(mesh.vertices.size());
    pole[k] = profile[k].rho == 0.0;
    if (pole[k]) {
      mesh.vertices.emplace_back(0.0, 0.0, profile[k].z);
      continue;
    }
    for (int j = 0; j < n; ++j) {
      const double phi = kTwoPi * j / n;
      mesh.vertices.emplace_back(
          profile[k].rho * std::cos(phi), profile[k].rho * std::sin(phi), profile[k].z);
    }
  }
  const std::size_t segments = closed_profile ? profile.size() : profile.size() - 1;
  for (std::size_t k = 0; k < segments; ++k) {
    const std::size_t a = k;
    const std::size_t b = (k + 1) % profile.size();
    if (pole[a] && pole[b]) continue;
    for (int j = 0; j < n; ++j) {
      const int jn = (j + 1) % n;
      if (pole[a]) {
        mesh.faces.emplace_back(start[a], start[b] + j, start[b] + jn);
      } else if (pole[b]) {
        mesh.faces.emplace_back(start[a] + j, start[b], start[a] + jn);
      } else {
        mesh.faces.emplace_back(start[a] + j, start[b] + j, start[b] + jn);
        mesh.faces.emplace_back(start[a] + j, start[b] + jn, start[a] + jn);
      }
    }
  }
  return mesh;
}

/// Number of latitude bands of a full sphere with `segments` longitudes (the usual UV-sphere
/// proportion: bands span 180° with the same angular step as the longitudes span 360°).
int sphere_stacks(int segments) {
  return std::max(2, segments / 2);
}

}  // namespace

TriangleMesh box(const Vec3& size) {
  TriangleMesh mesh;
  const Vec3 h = 0.5 * size;
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back((i & 1) ? h.x() : -h.x(),  //
                               (i & 2) ? h.y() : -h.y(),
                               (i & 4) ? h.z() : -h.z());
  }
  // Quads counter-clockwise seen from outside; vertex i has bit 0 = +x, bit 1 = +y, bit 2 = +z.
  constexpr int kQuads[6][4] = {
      {0, 2, 3, 1},  // -z
      {4, 5, 7, 6},  // +z
      {0, 1, 5, 4},  // -y
      {2, 6, 7, 3},  // +y
      {0, 4, 6, 2},  // -x
      {1, 3, 7, 5},  // +x
  };
  for (const auto& q : kQuads) {
    mesh.faces.emplace_back(q[0], q[1], q[2]);
    mesh.faces.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

TriangleMesh cylinder(double radius, double length, int segments) {
  const double h = 0.5 * length;
  return revolve({{0.0, h}, {radius, h}, {radius, -h}, {0.0, -h}}, false, segments);
}

TriangleMesh tube(double inner_radius, double outer_radius, double length, int segments) {
  if (inner_radius <= 0.0) return cylinder(outer_radius, length, segments);
  const double h = 0.5 * length;
  return revolve({{inner_radius, h}, {outer_radius, h}, {outer_radius, -h}, {inner_radius, -h}},
                 true,
                 segments);
}

TriangleMesh sphere(double radius, int segments) {
  const int stacks = sphere_stacks(segments);
  std::vector<ProfilePoint> profile;
  profile.reserve(stacks + 1);
  profile.push_back({0.0, radius});
  for (int k = 1; k < stacks; ++k) {
    const double theta = std::numbers::pi * k / stacks;  // polar angle from +z
    profile.push_back({radius * std::sin(theta), radius * std::cos(theta)});
  }
  profile.push_back({0.0, -radius});
  return revolve(profile, false, segments);
}

TriangleMesh hemisphere(double radius, int segments) {
  const int stacks = std::max(1, sphere_stacks(segments) / 2);
  std::vector<ProfilePoint> profile;
  profile.reserve(stacks + 2);
  profile.push_back({0.0, 0.0});  // centre of the closing disc
  profile.push_back({radius, 0.0});
  for (int k = 1; k < stacks; ++k) {
    const double theta = 0.5 * std::numbers::pi * (1.0 + static_cast<double>(k) / stacks);
    profile.push_back({radius * std::sin(theta), radius * std::cos(theta)});
  }
  profile.push_back({0.0, -radius});
  return revolve(profile, false, segments);
}

TriangleMesh torus_arc(
    double arc_radius, double wire_radius, double angle_deg, int segments, int wire_segments) {
  TriangleMesh mesh;
  if (!(angle_deg > 0.0)) return mesh;
  const bool closed = angle_deg >= 360.0;
  const double sweep = (closed ? 360.0 : angle_deg) * kDegToRad;
  // `segments` divides the swept arc itself (a full turn for the closed torus).
  const int n = std::max(closed ? 3 : 1, segments);
  const int m = std::max(3, wire_segments);  // segments around the wire
  const int rings = closed ? n : n + 1;

  // Centreline c(a) = R·u(a) with u(a) = (0, -sin a, -cos a); the wire circle at a lies in the
  // plane spanned by u(a) and x. (u, x, tangent) is right-handed, so ordering the quads as
  // (wire direction) × (sweep direction) gives outward normals.
  auto ring_vertex = [&](int i, int j) { return i % rings * m + j % m; };
  for (int i = 0; i < rings; ++i) {
    const double a = sweep * i / n;
    const Vec3 u(0.0, -std::sin(a), -std::cos(a));
    for (int j = 0; j < m; ++j) {
      const double phi = kTwoPi * j / m;
      mesh.vertices.push_back((arc_radius + wire_radius * std::cos(phi)) * u +
                              wire_radius * std::sin(phi) * Vec3::UnitX());
    }
  }
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      const int v00 = ring_vertex(i, j);
      const int v01 = ring_vertex(i, j + 1);
      const int v10 = ring_vertex(i + 1, j);
      const int v11 = ring_vertex(i + 1, j + 1);
      mesh.faces.emplace_back(v00, v01, v11);
      mesh.faces.emplace_back(v00, v11, v10);
    }
  }
  if (!closed) {
    // Start cap faces -tangent, end cap +tangent.
    const int c0 = static_cast<int>(mesh.vertices.size());
    mesh.vertices.emplace_back(0.0, 0.0, -arc_radius);
    const int c1 = c0 + 1;
    mesh.vertices.emplace_back(0.0, -arc_radius * std::sin(sweep), -arc_radius * std::cos(sweep));
    for (int j = 0; j < m; ++j) {
      mesh.faces.emplace_back(c0, ring_vertex(0, j + 1), ring_vertex(0, j));
      mesh.faces.emplace_back(c1, ring_vertex(n, j), ring_vertex(n, j + 1));
    }
  }
  return mesh;
}

}  // namespace shapes

}  // namespace fabkit

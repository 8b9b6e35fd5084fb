#include "convex_pieces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

namespace fabkit::hacks::detail {
namespace {

// The convex hexahedron with corners c[0..7] ordered as a box's: bit 0 chooses along the
// first edge, bit 1 along the second, bit 2 along the third; outward faces for a
// right-handed ordering.
TriangleMesh hexahedron(const std::array<Vec3, 8>& c) {
  TriangleMesh m;
  m.vertices.assign(c.begin(), c.end());
  const int quads[6][4] = {
      {0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    m.faces.emplace_back(q[0], q[1], q[2]);
    m.faces.emplace_back(q[0], q[2], q[3]);
  }
  // Left-handed corner orders turn every face inward: flip them all.
  if (m.volume() < 0) {
    for (Eigen::Vector3i& f : m.faces) std::swap(f[1], f[2]);
  }
  return m;
}

}  // namespace

std::vector<TriangleMesh> arc_pieces(double arc_radius,
                                     double wire_radius,
                                     double angle_deg,
                                     double max_segment_deg) {
  std::vector<TriangleMesh> out;
  if (!(angle_deg > 0) || !(arc_radius > 0) || !(wire_radius > 0)) return out;
  const double sweep = std::min(angle_deg, 360.0) * kDegToRad;
  const int n = std::max(
      1, static_cast<int>(std::ceil(std::min(angle_deg, 360.0) / std::max(1.0, max_segment_deg))));
  auto centre = [&](double a) {
    return Vec3(0.0, -arc_radius * std::sin(a), -arc_radius * std::cos(a));
  };
  for (int i = 0; i < n; ++i) {
    const Vec3 a = centre(sweep * i / n);
    const Vec3 b = centre(sweep * (i + 1) / n);
    const Vec3 d = b - a;
    // An octagonal prism around the chord, reaching the wire's outer surface at the ends.
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() =
        Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).normalized().toRotationMatrix();
    m.topRightCorner<3, 1>() = 0.5 * (a + b);
    out.push_back(shapes::cylinder(wire_radius, d.norm(), 8).transformed(m));
  }
  return out;
}

namespace {
constexpr int kTubeSectors = 12;
}  // namespace

std::vector<TriangleMesh> tube_pieces(double inner_radius, double outer_radius, double length) {
  std::vector<TriangleMesh> out;
  if (!(outer_radius > inner_radius) || !(inner_radius >= 0) || !(length > 0)) return out;
  constexpr int kSectors = kTubeSectors;
  for (int i = 0; i < kSectors; ++i) {
    const double a0 = 2 * std::numbers::pi * i / kSectors;
    const double a1 = 2 * std::numbers::pi * (i + 1) / kSectors;
    std::array<Vec3, 8> c;
    for (int k = 0; k < 8; ++k) {
      const double r = (k & 1) ? outer_radius : inner_radius;
      const double a = (k & 2) ? a1 : a0;
      const double z = (k & 4) ? length / 2 : -length / 2;
      c[static_cast<std::size_t>(k)] = Vec3(r * std::cos(a), r * std::sin(a), z);
    }
    out.push_back(hexahedron(c));
  }
  return out;
}

std::vector<std::vector<collision::Arc>> tube_piece_rims(double inner_radius,
                                                         double outer_radius,
                                                         double length) {
  std::vector<std::vector<collision::Arc>> out;
  if (!(outer_radius > inner_radius) || !(inner_radius >= 0) || !(length > 0)) return out;
  for (int i = 0; i < kTubeSectors; ++i) {
    std::vector<collision::Arc> rims;
    for (const double z : {-length / 2, length / 2}) {
      collision::Arc rim;
      rim.centre = Vec3(0, 0, z);
      rim.radius = outer_radius;
      rim.from = 2 * std::numbers::pi * i / kTubeSectors;
      rim.to = 2 * std::numbers::pi * (i + 1) / kTubeSectors;
      rims.push_back(rim);
    }
    out.push_back(std::move(rims));
  }
  return out;
}

std::vector<collision::Arc> cylinder_rims(double radius, double length) {
  std::vector<collision::Arc> out;
  if (!(radius > 0) || !(length > 0)) return out;
  for (const double z : {-length / 2, length / 2}) {
    collision::Arc rim;
    rim.centre = Vec3(0, 0, z);
    rim.radius = radius;
    out.push_back(rim);
  }
  return out;
}

void transform_pieces(std::vector<TriangleMesh>& pieces, const Mat4& m) {
  for (TriangleMesh& p : pieces) p.transform(m);
}

void transform_rims(std::vector<std::vector<collision::Arc>>& rims, const Mat4& m) {
  for (std::vector<collision::Arc>& piece : rims) {
    for (collision::Arc& rim : piece) rim = rim.transformed(m);
  }
}

}  // namespace fabkit::hacks::detail

#include "fabkit/rods/layout.h"

#include <algorithm>
#include <cmath>

namespace fabkit::rods {

double safe_offset(double max_cosine, double radius_plus_tolerance) {
  const double c = std::clamp(max_cosine, -1.0, 1.0);
  if (c >= 1.0) return std::numeric_limits<double>::infinity();
  return radius_plus_tolerance * std::sqrt((1 + c) / (1 - c));
}

Mat3 rotation_to(const Vec3& w) {
  const Vec3 ez = Vec3::UnitZ();
  const double cz = ez.dot(w);
  if (cz < 0) {
    // Eq. (1) divides by 1 + e_z·w, which vanishes as w nears −e_z: turn half about x first
    // (mapping w into the upper half) and apply Eq. (1) there. Same direction, stable twist.
    const Mat3 half = Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()).toRotationMatrix();
    return half * rotation_to(half.transpose() * w);
  }
  const Vec3 v = ez.cross(w);
  Mat3 vx;
  vx << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return Mat3::Identity() + vx + vx * vx / (1 + cz);
}

std::vector<const RodEnd*> Layout::ends_at(int node) const {
  std::vector<const RodEnd*> out;
  for (const int rod : rods_at[static_cast<std::size_t>(node)]) out.push_back(&end_at(rod, node));
  return out;
}

const RodEnd& Layout::end_at(int rod, int node) const {
  const auto& e = ends[static_cast<std::size_t>(rod)];
  return e[0].node == node ? e[0] : e[1];
}

Layout compute_layout(const Structure& s, const Parameters& p) {
  Layout l;
  const std::size_t m = s.rods.size();
  l.ends.resize(m);
  l.edge_length.resize(m);
  l.rod_length.resize(m);
  l.rotation.resize(m);
  l.rods_at = s.rods_at_nodes();
  // A half turn about the profile's x axis: z reverses, and the regular polygon (vertices at
  // angles 2πk/p, symmetric about x) maps onto itself, so the far end sees the same profile.
  const Mat3 flip = Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()).toRotationMatrix();
  for (std::size_t e = 0; e < m; ++e) {
    const Rod& rod = s.rods[e];
    const Vec3 d = s.nodes[static_cast<std::size_t>(rod.b)].position -
                   s.nodes[static_cast<std::size_t>(rod.a)].position;
    l.edge_length[e] = d.norm();
    const Vec3 w = d / l.edge_length[e];
    l.rotation[e] = rotation_to(w);
    for (int k = 0; k < 2; ++k) {
      RodEnd& end = l.ends[e][static_cast<std::size_t>(k)];
      end.rod = static_cast<int>(e);
      end.end = k;
      end.node = k == 0 ? rod.a : rod.b;
      end.direction = k == 0 ? w : Vec3(-w);
      end.frame = k == 0 ? l.rotation[e] : Mat3(l.rotation[e] * flip);
    }
  }
  const double rt = p.radius + p.tolerance;
  for (std::size_t i = 0; i < s.nodes.size(); ++i) {
    const auto& at = l.rods_at[i];
    for (const int e : at) {
      RodEnd& end =
          l.ends[static_cast<std::size_t>(e)]
                [l.ends[static_cast<std::size_t>(e)][0].node == static_cast<int>(i) ? 0 : 1];
      end.max_cosine = -2;
      for (const int f : at) {
        if (f == e) continue;
        const RodEnd& other = l.end_at(f, static_cast<int>(i));
        const double c = end.direction.dot(other.direction);
        if (c > end.max_cosine) {
          end.max_cosine = c;
          end.closest_rod = f;
        }
      }
      end.offset = end.closest_rod < 0 ? p.leaf_offset : safe_offset(end.max_cosine, rt);
    }
  }
  for (std::size_t e = 0; e < m; ++e) {
    l.rod_length[e] = l.edge_length[e] - l.ends[e][0].offset - l.ends[e][1].offset;
  }
  return l;
}

}  // namespace fabkit::rods

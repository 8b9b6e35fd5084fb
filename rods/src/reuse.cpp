#include "fabkit/rods/reuse.h"

#include <algorithm>
#include <cmath>

#include "fabkit/rods/joint_geometry.h"

namespace fabkit::rods {
namespace {

bool same_parameters(const Parameters& a, const Parameters& b, double tol) {
  return std::abs(a.radius - b.radius) <= tol && a.sides == b.sides &&
         (a.sides != 0 || a.circle_sides == b.circle_sides) && std::abs(a.wall - b.wall) <= tol &&
         std::abs(a.socket - b.socket) <= tol && std::abs(a.tolerance - b.tolerance) <= tol &&
         std::abs(a.leaf_offset - b.leaf_offset) <= tol;
}

struct EndShape {
  Mat3 frame;
  double offset;
  double socket_length;
};

std::vector<EndShape> shape_of(const Structure& s, const Parameters& p, const Layout& l, int node) {
  const JointPieces pieces = joint_pieces(s, p, l, node);
  std::vector<EndShape> out;
  const auto ends = l.ends_at(node);
  for (std::size_t k = 0; k < ends.size(); ++k) {
    out.push_back({ends[k]->frame, ends[k]->offset, pieces.socket_length[k]});
  }
  return out;
}

bool same_shape(const std::vector<EndShape>& x, const std::vector<EndShape>& y, double tol) {
  if (x.size() != y.size()) return false;
  // Ends in the same order (k-th rod at the joint) make the same primitives.
  for (std::size_t k = 0; k < x.size(); ++k) {
    if ((x[k].frame - y[k].frame).cwiseAbs().maxCoeff() > tol / 1000) return false;
    if (std::abs(x[k].offset - y[k].offset) > tol) return false;
    if (std::abs(x[k].socket_length - y[k].socket_length) > tol) return false;
  }
  return true;
}

}  // namespace

std::vector<JointMatch> matching_joints(const Structure& a,
                                        const Parameters& pa,
                                        const Structure& b,
                                        const Parameters& pb,
                                        double tolerance) {
  std::vector<JointMatch> out;
  if (!same_parameters(pa, pb, tolerance)) return out;
  const Layout la = compute_layout(a, pa), lb = compute_layout(b, pb);
  std::vector<std::vector<EndShape>> shapes_a;
  for (std::size_t i = 0; i < a.nodes.size(); ++i)
    shapes_a.push_back(shape_of(a, pa, la, static_cast<int>(i)));
  std::vector<bool> used(a.nodes.size(), false);
  for (std::size_t j = 0; j < b.nodes.size(); ++j) {
    const auto shape = shape_of(b, pb, lb, static_cast<int>(j));
    int found = -1;
    for (std::size_t i = 0; i < a.nodes.size(); ++i) {
      if (!used[i] && a.nodes[i].id == b.nodes[j].id && same_shape(shapes_a[i], shape, tolerance)) {
        found = static_cast<int>(i);
        break;
      }
    }
    for (std::size_t i = 0; i < a.nodes.size() && found < 0; ++i) {
      if (!used[i] && same_shape(shapes_a[i], shape, tolerance)) found = static_cast<int>(i);
    }
    if (found >= 0) {
      used[static_cast<std::size_t>(found)] = true;
      out.push_back(JointMatch{static_cast<int>(j), found});
    }
  }
  return out;
}

std::optional<double> uniform_scale_between(const Structure& a, const Structure& b) {
  if (a.nodes.size() != b.nodes.size() || a.rods.size() != b.rods.size() || a.nodes.empty())
    return std::nullopt;
  for (std::size_t e = 0; e < a.rods.size(); ++e) {
    if (a.rods[e].a != b.rods[e].a || a.rods[e].b != b.rods[e].b) return std::nullopt;
  }
  double num = 0, den = 0;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    num += a.nodes[i].position.dot(b.nodes[i].position);
    den += a.nodes[i].position.squaredNorm();
  }
  if (den <= 0) return std::nullopt;
  const double f = num / den;
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    if ((b.nodes[i].position - f * a.nodes[i].position).norm() >
        1e-6 * (1 + b.nodes[i].position.norm())) {
      return std::nullopt;
    }
  }
  return f;
}

}  // namespace fabkit::rods

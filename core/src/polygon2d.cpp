// 2D booleans and offsets on Clipper 1; cap triangulation with the GLU tessellator. Both stay
// in this translation unit: the public header speaks plain Eigen vectors.
#include "fabkit/core/polygon2d.h"

#include <GL/glu.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <polyclipping/clipper.hpp>

namespace fabkit {
namespace {

namespace cl = ClipperLib;

constexpr double kScale = 1.0 / kPolygonResolutionMm;

cl::Path to_path(const Ring& ring) {
  cl::Path path;
  path.reserve(ring.size());
  for (const Vec2& p : ring) {
    path.emplace_back(static_cast<cl::cInt>(std::llround(p.x() * kScale)),
                      static_cast<cl::cInt>(std::llround(p.y() * kScale)));
  }
  return path;
}

Ring to_ring(const cl::Path& path) {
  Ring ring;
  ring.reserve(path.size());
  for (const cl::IntPoint& p : path) {
    ring.emplace_back(static_cast<double>(p.X) / kScale, static_cast<double>(p.Y) / kScale);
  }
  return ring;
}

cl::Paths to_paths(const Region2d& region) {
  cl::Paths paths;
  for (const Polygon2d& polygon : region) {
    if (polygon.empty()) continue;
    // Non-zero filling needs the holes opposite to their outer ring.
    const Polygon2d o = oriented(polygon);
    paths.push_back(to_path(o.outer));
    for (const Ring& hole : o.holes) paths.push_back(to_path(hole));
  }
  return paths;
}

void collect(const cl::PolyNode& node, Region2d& out) {
  // `node` is an outer contour; its children are holes, their children outer contours again.
  Polygon2d polygon;
  polygon.outer = to_ring(node.Contour);
  for (const cl::PolyNode* hole : node.Childs) {
    polygon.holes.push_back(to_ring(hole->Contour));
    for (const cl::PolyNode* island : hole->Childs) collect(*island, out);
  }
  out.push_back(oriented(std::move(polygon)));
}

Region2d from_tree(const cl::PolyTree& tree) {
  Region2d out;
  for (const cl::PolyNode* node : tree.Childs) collect(*node, out);
  return out;
}

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

double segment_distance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

// Even-odd crossing test of one ring.
bool inside_ring(const Ring& ring, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Vec2& a = ring[i];
    const Vec2& b = ring[j];
    if ((a.y() > p.y()) != (b.y() > p.y())) {
      const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (p.x() < x) in = !in;
    }
  }
  return in;
}

template <class F>
void for_each_edge(const Polygon2d& polygon, F&& f) {
  auto ring_edges = [&](const Ring& ring) {
    for (std::size_t i = 0; i < ring.size(); ++i) f(ring[i], ring[(i + 1) % ring.size()]);
  };
  ring_edges(polygon.outer);
  for (const Ring& hole : polygon.holes) ring_edges(hole);
}

}  // namespace

double signed_area(const Ring& ring) {
  double a = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) a += cross(ring[i], ring[(i + 1) % ring.size()]);
  return a / 2;
}

double Polygon2d::area() const {
  double a = std::abs(signed_area(outer));
  for (const Ring& hole : holes) a -= std::abs(signed_area(hole));
  return a;
}

double area(const Region2d& region) {
  double a = 0;
  for (const Polygon2d& p : region) a += p.area();
  return a;
}

Box2d bounds(const Ring& ring) {
  Box2d box;
  for (const Vec2& p : ring) box.extend(p);
  return box;
}

Box2d bounds(const Region2d& region) {
  Box2d box;
  for (const Polygon2d& polygon : region) {
    for (const Vec2& p : polygon.outer) box.extend(p);
  }
  return box;
}

Polygon2d rectangle(double x0, double y0, double x1, double y1) {
  Polygon2d p;
  p.outer = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  return oriented(std::move(p));
}

Polygon2d circle(const Vec2& centre, double radius, int segments) {
  Polygon2d p;
  segments = std::max(segments, 3);
  for (int i = 0; i < segments; ++i) {
    const double a = 2 * M_PI * i / segments;
    p.outer.emplace_back(centre.x() + radius * std::cos(a), centre.y() + radius * std::sin(a));
  }
  return p;
}

Polygon2d oriented(Polygon2d polygon) {
  if (signed_area(polygon.outer) < 0) std::reverse(polygon.outer.begin(), polygon.outer.end());
  for (Ring& hole : polygon.holes) {
    if (signed_area(hole) > 0) std::reverse(hole.begin(), hole.end());
  }
  return polygon;
}

Region2d boolean(const Region2d& a, const Region2d& b, BooleanOp op) {
  cl::Clipper clipper;
  clipper.AddPaths(to_paths(a), cl::ptSubject, true);
  clipper.AddPaths(to_paths(b), cl::ptClip, true);
  const cl::ClipType type = op == BooleanOp::kUnion          ? cl::ctUnion
                            : op == BooleanOp::kIntersection ? cl::ctIntersection
                            : op == BooleanOp::kDifference   ? cl::ctDifference
                                                             : cl::ctXor;
  cl::PolyTree tree;
  clipper.Execute(type, tree, cl::pftNonZero, cl::pftNonZero);
  return from_tree(tree);
}

Region2d unite(const Region2d& a, const Region2d& b) {
  return boolean(a, b, BooleanOp::kUnion);
}
Region2d intersect(const Region2d& a, const Region2d& b) {
  return boolean(a, b, BooleanOp::kIntersection);
}
Region2d subtract(const Region2d& a, const Region2d& b) {
  return boolean(a, b, BooleanOp::kDifference);
}
Region2d unite_all(const Region2d& a) {
  return boolean(a, {}, BooleanOp::kUnion);
}

Region2d offset(const Region2d& region, double delta, OffsetJoin join) {
  cl::ClipperOffset clipper(2.0, 0.01 * kScale);  // round joins within 0.01 mm
  const cl::JoinType type = join == OffsetJoin::kMiter   ? cl::jtMiter
                            : join == OffsetJoin::kRound ? cl::jtRound
                                                         : cl::jtSquare;
  clipper.AddPaths(to_paths(region), type, cl::etClosedPolygon);
  cl::PolyTree tree;
  clipper.Execute(tree, delta * kScale);
  return from_tree(tree);
}

PointLocation locate(const Polygon2d& polygon, const Vec2& p, double tolerance) {
  bool near = false;
  for_each_edge(polygon, [&](const Vec2& a, const Vec2& b) {
    if (!near && segment_distance(p, a, b) <= tolerance) near = true;
  });
  if (near) return PointLocation::kBoundary;
  if (!inside_ring(polygon.outer, p)) return PointLocation::kOutside;
  for (const Ring& hole : polygon.holes) {
    if (inside_ring(hole, p)) return PointLocation::kOutside;
  }
  return PointLocation::kInside;
}

double boundary_distance(const Polygon2d& polygon, const Vec2& p) {
  double best = 1e300;
  for_each_edge(polygon, [&](const Vec2& a, const Vec2& b) {
    best = std::min(best, segment_distance(p, a, b));
  });
  return best;
}

std::vector<LineStretch> classify_line(const Polygon2d& polygon,
                                       const Vec2& o,
                                       const Vec2& direction,
                                       double tolerance) {
  std::vector<LineStretch> out;
  if (polygon.empty() || direction.norm() == 0) return out;
  const Vec2 d = direction.normalized();
  const Vec2 n(-d.y(), d.x());
  std::vector<double> cuts;
  for_each_edge(polygon, [&](const Vec2& a, const Vec2& b) {
    const double da = n.dot(a - o);
    const double db = n.dot(b - o);
    if (std::abs(da) <= tolerance) cuts.push_back(d.dot(a - o));
    if (std::abs(db) <= tolerance) cuts.push_back(d.dot(b - o));
    if ((da > tolerance && db < -tolerance) || (da < -tolerance && db > tolerance)) {
      const Vec2 p = a + (da / (da - db)) * (b - a);
      cuts.push_back(d.dot(p - o));
    }
  });
  std::sort(cuts.begin(), cuts.end());
  // Side probes sit just off the line: far enough to leave a tolerance band, near enough not
  // to jump over thin features.
  const double probe = std::max(50 * tolerance, 1e-4);
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double s0 = cuts[k];
    const double s1 = cuts[k + 1];
    if (s1 - s0 <= tolerance) continue;
    const Vec2 m = o + d * ((s0 + s1) / 2);
    if (locate(polygon, m, tolerance) == PointLocation::kOutside) continue;
    const bool left = locate(polygon, m + probe * n, 0) == PointLocation::kInside;
    const bool right = locate(polygon, m - probe * n, 0) == PointLocation::kInside;
    if (!left && !right) continue;
    const PointLocation where = left && right ? PointLocation::kInside : PointLocation::kBoundary;
    if (!out.empty() && out.back().where == where && std::abs(out.back().s1 - s0) <= tolerance) {
      out.back().s1 = s1;
    } else {
      out.push_back({s0, s1, where});
    }
  }
  return out;
}

namespace {

struct Tessellation {
  std::vector<std::array<double, 3>> coords;
  std::vector<int> triangle_indices;
  bool failed = false;
};

void tess_vertex(void* vertex, void* data) {
  static_cast<Tessellation*>(data)->triangle_indices.push_back(
      static_cast<int>(reinterpret_cast<std::intptr_t>(vertex)));
}
void tess_begin(GLenum, void*) {}
// Registering an edge-flag callback makes GLU emit plain triangles (no fans or strips).
void tess_edge_flag(GLboolean, void*) {}
void tess_combine(GLdouble[3], void* [4], GLfloat[4], void** out, void* data) {
  // Clipper's output is simple; a combine means the input was not, which the caller sees.
  static_cast<Tessellation*>(data)->failed = true;
  *out = nullptr;
}
void tess_error(GLenum, void* data) {
  static_cast<Tessellation*>(data)->failed = true;
}

}  // namespace

TriangleMesh extrude(const Polygon2d& input, double z0, double z1) {
  TriangleMesh mesh;
  if (input.empty()) return mesh;
  const Polygon2d polygon = oriented(input);
  std::vector<const Ring*> rings{&polygon.outer};
  for (const Ring& hole : polygon.holes) {
    if (hole.size() >= 3) rings.push_back(&hole);
  }
  std::vector<Vec2> flat;
  std::vector<std::pair<int, int>> ring_ranges;
  for (const Ring* ring : rings) {
    ring_ranges.emplace_back(static_cast<int>(flat.size()), static_cast<int>(ring->size()));
    flat.insert(flat.end(), ring->begin(), ring->end());
  }
  const int n = static_cast<int>(flat.size());
  for (const Vec2& p : flat) mesh.vertices.emplace_back(p.x(), p.y(), z0);
  for (const Vec2& p : flat) mesh.vertices.emplace_back(p.x(), p.y(), z1);

  Tessellation t;
  t.coords.reserve(flat.size());
  GLUtesselator* tess = gluNewTess();
  gluTessProperty(tess, GLU_TESS_WINDING_RULE, GLU_TESS_WINDING_ODD);
  gluTessCallback(tess, GLU_TESS_BEGIN_DATA, reinterpret_cast<_GLUfuncptr>(tess_begin));
  gluTessCallback(tess, GLU_TESS_VERTEX_DATA, reinterpret_cast<_GLUfuncptr>(tess_vertex));
  gluTessCallback(tess, GLU_TESS_EDGE_FLAG_DATA, reinterpret_cast<_GLUfuncptr>(tess_edge_flag));
  gluTessCallback(tess, GLU_TESS_COMBINE_DATA, reinterpret_cast<_GLUfuncptr>(tess_combine));
  gluTessCallback(tess, GLU_TESS_ERROR_DATA, reinterpret_cast<_GLUfuncptr>(tess_error));
  gluTessNormal(tess, 0, 0, 1);
  gluTessBeginPolygon(tess, &t);
  for (const auto& [start, count] : ring_ranges) {
    gluTessBeginContour(tess);
    for (int i = 0; i < count; ++i) {
      t.coords.push_back({flat[start + i].x(), flat[start + i].y(), 0.0});
      gluTessVertex(tess,
                    t.coords.back().data(),
                    reinterpret_cast<void*>(static_cast<std::intptr_t>(start + i)));
    }
    gluTessEndContour(tess);
  }
  gluTessEndPolygon(tess);
  gluDeleteTess(tess);
  if (t.failed) return {};

  for (std::size_t k = 0; k + 2 < t.triangle_indices.size(); k += 3) {
    int a = t.triangle_indices[k], b = t.triangle_indices[k + 1], c = t.triangle_indices[k + 2];
    if (cross(flat[b] - flat[a], flat[c] - flat[a]) < 0) std::swap(b, c);
    mesh.faces.emplace_back(n + a, n + b, n + c);  // top, facing +z
    mesh.faces.emplace_back(a, c, b);              // bottom, facing -z
  }
  for (const auto& [start, count] : ring_ranges) {
    for (int i = 0; i < count; ++i) {
      const int p = start + i;
      const int q = start + (i + 1) % count;
      mesh.faces.emplace_back(p, q, n + q);
      mesh.faces.emplace_back(p, n + q, n + p);
    }
  }
  return mesh;
}

Vec2 interior_point(const Polygon2d& polygon) {
  if (polygon.empty()) return Vec2::Zero();
  Vec2 centroid = Vec2::Zero();
  for (const Vec2& p : polygon.outer) centroid += p;
  centroid /= static_cast<double>(polygon.outer.size());
  Vec2 best = centroid;
  double best_clearance = locate(polygon, centroid, 0) == PointLocation::kInside
                              ? boundary_distance(polygon, centroid)
                              : -1;
  const Box2d box = bounds(polygon.outer);
  constexpr int kGrid = 16;
  for (int i = 1; i < kGrid; ++i) {
    for (int j = 1; j < kGrid; ++j) {
      const Vec2 p(box.min.x() + box.size().x() * i / kGrid,
                   box.min.y() + box.size().y() * j / kGrid);
      if (locate(polygon, p, 0) != PointLocation::kInside) continue;
      // Prefer the centre a little: labels read better there.
      const double clearance = boundary_distance(polygon, p);
      if (clearance > best_clearance * 1.25) {
        best = p;
        best_clearance = clearance;
      }
    }
  }
  return best;
}

Ring transformed(const Ring& ring, double degrees, const Vec2& t) {
  const double r = degrees * M_PI / 180;
  const double c = std::cos(r), s = std::sin(r);
  Ring out;
  out.reserve(ring.size());
  for (const Vec2& p : ring)
    out.emplace_back(c * p.x() - s * p.y() + t.x(), s * p.x() + c * p.y() + t.y());
  return out;
}

Polygon2d transformed(const Polygon2d& polygon, double degrees, const Vec2& t) {
  Polygon2d out;
  out.outer = transformed(polygon.outer, degrees, t);
  for (const Ring& hole : polygon.holes) out.holes.push_back(transformed(hole, degrees, t));
  return out;
}

}  // namespace fabkit

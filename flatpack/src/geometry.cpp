// Placement (Alg. 1), coplanar merging and intersection detection (Alg. 2), joints (App. A)
// and the press-fit order.
#include "geometry.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "fabkit/flatpack/diagnostic_codes.h"
#include "fabkit/flatpack/joint_widths.h"

namespace fabkit::flatpack::detail {
namespace {

Vec3 apply(const Mat4& m, const Vec3& p) {
  return m.topLeftCorner<3, 3>() * p + m.topRightCorner<3, 1>();
}
Vec3 to3(const Vec2& p) {
  return Vec3(p.x(), p.y(), 0);
}

double rotation_angle_deg(const Mat3& r) {
  return std::acos(std::clamp((r.trace() - 1) / 2, -1.0, 1.0)) * kRadToDeg;
}

}  // namespace

Mat4 edge_frame(const ComponentShape& shape, const std::string& edge, bool* found) {
  if (found) *found = false;
  for (const NamedEdge& e : shape.edges) {
    if (e.name != edge) continue;
    const Ring& r = shape.polygon.outer;
    const Vec2 p0 = r[static_cast<std::size_t>(e.vertex)];
    const Vec2 p1 = r[static_cast<std::size_t>(e.vertex + 1) % r.size()];
    const Vec2 x = (p1 - p0).normalized();
    Mat4 m = Mat4::Identity();
    m.block<3, 1>(0, 0) = Vec3(x.x(), x.y(), 0);
    m.block<3, 1>(0, 1) = Vec3(-x.y(), x.x(), 0);
    m.block<3, 1>(0, 2) = Vec3(0, 0, 1);
    m.block<3, 1>(0, 3) = to3((p0 + p1) / 2);
    if (found) *found = true;
    return m;
  }
  return Mat4::Identity();
}

Mat4 relative_transform(const ComponentShape& a,
                        const std::string& a_edge,
                        const ComponentShape& b,
                        const std::string& b_edge,
                        Alignment alignment,
                        const Vec3& offset,
                        const Vec3& rotation_deg) {
  const Mat4 flip = alignment == Alignment::kFrontFront ? rot_z(180.0) : rot_x(180.0);
  // Intrinsic rotations about A's own x, then y, then z.
  const Mat4 turn = rot_x(rotation_deg.x()) * rot_y(rotation_deg.y()) * rot_z(rotation_deg.z());
  return edge_frame(b, b_edge) * translation(offset.x(), offset.y(), offset.z()) * flip * turn *
         rigid_inverse(edge_frame(a, a_edge));
}

void place(std::vector<PlacedComponent>& components,
           const std::vector<ResolvedConnection>& connections,
           const CheckOptions& options,
           Diagnostics& diags,
           std::vector<CycleResidual>* residuals) {
  const int n = static_cast<int>(components.size());
  std::vector<std::vector<int>> incident(static_cast<std::size_t>(n));
  for (int k = 0; k < static_cast<int>(connections.size()); ++k) {
    incident[static_cast<std::size_t>(connections[static_cast<std::size_t>(k)].a)].push_back(k);
    incident[static_cast<std::size_t>(connections[static_cast<std::size_t>(k)].b)].push_back(k);
  }
  std::vector<char> placed(static_cast<std::size_t>(n), 0);
  std::vector<int> parent_connection(static_cast<std::size_t>(n), -1);
  std::vector<char> tree(connections.size(), 0);
  std::vector<std::string> stray;
  // With separate_groups_mm, the right end (world x) of the groups placed so far.
  std::optional<double> groups_max_x;
  for (int root = 0; root < n; ++root) {
    if (placed[static_cast<std::size_t>(root)]) continue;
    if (root > 0) stray.push_back(components[static_cast<std::size_t>(root)].name);
    components[static_cast<std::size_t>(root)].frame = Mat4::Identity();
    placed[static_cast<std::size_t>(root)] = 1;
    std::vector<int> group{root};
    // Breadth first, so a component is placed from the shortest chain of connections.
    std::deque<int> queue{root};
    while (!queue.empty()) {
      const int c = queue.front();
      queue.pop_front();
      for (int k : incident[static_cast<std::size_t>(c)]) {
        const ResolvedConnection& rc = connections[static_cast<std::size_t>(k)];
        const Mat4& tc = components[static_cast<std::size_t>(c)].frame;
        // Alg. 1: C_i is B → A = T·T_rel; C_i is A → B = T·T_rel⁻¹.
        const int other = rc.b == c ? rc.a : rc.b;
        const Mat4 predicted =
            rc.b == c ? Mat4(tc * rc.relative) : Mat4(tc * rigid_inverse(rc.relative));
        if (!placed[static_cast<std::size_t>(other)]) {
          components[static_cast<std::size_t>(other)].frame = predicted;
          placed[static_cast<std::size_t>(other)] = 1;
          parent_connection[static_cast<std::size_t>(other)] = k;
          tree[static_cast<std::size_t>(k)] = 1;
          queue.push_back(other);
          group.push_back(other);
        } else if (!tree[static_cast<std::size_t>(k)] && rc.b == c) {
          // A connection that closes a cycle: does it agree with the placement already made?
          const Mat4& actual = components[static_cast<std::size_t>(other)].frame;
          double position = 0;
          for (const Vec2& p : components[static_cast<std::size_t>(other)].shape.polygon.outer) {
            position =
                std::max(position, (apply(actual, to3(p)) - apply(predicted, to3(p))).norm());
          }
          const double angle = rotation_angle_deg(actual.topLeftCorner<3, 3>().transpose() *
                                                  predicted.topLeftCorner<3, 3>());
          const bool closes =
              position <= options.cycle_tolerance_mm && angle <= options.cycle_tolerance_deg;
          if (residuals) {
            residuals->push_back({k,
                                  rc.name,
                                  components[static_cast<std::size_t>(other)].name,
                                  position,
                                  angle,
                                  closes,
                                  predicted});
          }
          if (!closes) {
            // The cycle: this connection and the tree paths of its two ends.
            std::vector<std::string> path;
            auto climb = [&](int x) {
              std::vector<std::string> names;
              while (parent_connection[static_cast<std::size_t>(x)] >= 0) {
                const ResolvedConnection& p = connections[static_cast<std::size_t>(
                    parent_connection[static_cast<std::size_t>(x)])];
                names.push_back(p.name);
                x = p.a == x ? p.b : p.a;
              }
              return names;
            };
            std::vector<std::string> pa = climb(rc.a), pb = climb(rc.b);
            while (!pa.empty() && !pb.empty() && pa.back() == pb.back()) {
              pa.pop_back();
              pb.pop_back();
            }
            path.push_back(rc.name);
            path.insert(path.end(), pa.begin(), pa.end());
            path.insert(path.end(), pb.rbegin(), pb.rend());
            diags.error(
                codes::kCycleMismatch,
                fmt::format("{} ({}) disagrees with the placement the other connections give {} by "
                            "{:.2f} mm and {:.2f}°: the cycle {} does not close",
                            rc.name,
                            rc.text,
                            components[static_cast<std::size_t>(other)].name,
                            position,
                            angle,
                            fmt::join(path, " – ")),
                rc.where);
          }
          tree[static_cast<std::size_t>(k)] = 1;  // checked once
        }
      }
    }
    if (options.separate_groups_mm > 0) {
      // Lay this group beside the ones before it (along +x), so unconnected groups neither
      // overlap nor merge while a design is being put together.
      double lo = std::numeric_limits<double>::infinity();
      double hi = -lo;
      for (int c : group) {
        const PlacedComponent& pc = components[static_cast<std::size_t>(c)];
        for (const Vec2& p : pc.shape.polygon.outer) {
          const double x = apply(pc.frame, to3(p)).x();
          lo = std::min(lo, x);
          hi = std::max(hi, x);
        }
      }
      if (std::isfinite(lo)) {
        const double shift = groups_max_x ? *groups_max_x + options.separate_groups_mm - lo : 0.0;
        for (int c : group) {
          Mat4& frame = components[static_cast<std::size_t>(c)].frame;
          frame(0, 3) += shift;
        }
        groups_max_x = hi + shift;
      }
    }
  }
  if (!stray.empty()) {
    diags.warning(
        codes::kNotConnected,
        fmt::format("not connected to {}: {}; each group is placed on its own ({})",
                    components.front().name,
                    fmt::join(stray, ", "),
                    options.separate_groups_mm > 0 ? "beside the others" : "at the origin"));
  }
}

namespace {

struct PieceGeo {
  Vec3 origin, normal;
  Mat4 inverse;
  double thickness = 0;
  Region2d grown;  // outline grown by the end margin, for exclusion zones
  Vec3 box_min, box_max;
};

PieceGeo piece_geo(const Piece& p, double margin) {
  PieceGeo g;
  g.origin = p.frame.topRightCorner<3, 1>();
  g.normal = p.frame.block<3, 1>(0, 2);
  g.inverse = rigid_inverse(p.frame);
  g.thickness = p.material.thickness_mm;
  g.grown = offset({p.outline}, margin);
  g.box_min = Vec3::Constant(1e300);
  g.box_max = Vec3::Constant(-1e300);
  for (const Vec2& v : p.outline.outer) {
    const Vec3 w = apply(p.frame, to3(v));
    g.box_min = g.box_min.cwiseMin(w);
    g.box_max = g.box_max.cwiseMax(w);
  }
  return g;
}

// A line p + s·u in a piece's 2D frame: origin and unit direction (s keeps its meaning).
struct Line2 {
  Vec2 o, d;
  bool valid = true;
};
Line2 line_in(const PieceGeo& g, const Vec3& p, const Vec3& u) {
  const Vec3 o = apply(g.inverse, p);
  const Vec3 d = g.inverse.topLeftCorner<3, 3>() * u;
  Line2 l{Vec2(o.x(), o.y()), Vec2(d.x(), d.y())};
  l.valid = l.d.norm() > 1 - 1e-6;
  return l;
}

using Intervals = std::vector<std::pair<double, double>>;

Intervals subtract_intervals(Intervals base, const Intervals& cut) {
  for (const auto& [c0, c1] : cut) {
    Intervals next;
    for (const auto& [b0, b1] : base) {
      if (c1 <= b0 || c0 >= b1) {
        next.emplace_back(b0, b1);
        continue;
      }
      if (c0 > b0) next.emplace_back(b0, c0);
      if (c1 < b1) next.emplace_back(c1, b1);
    }
    base = std::move(next);
  }
  return base;
}

// The stretch of the line p + s·u inside piece k's board grown by `margin`.
Intervals slab_interval(
    const Piece& piece, const PieceGeo& g, const Vec3& p, const Vec3& u, double margin) {
  const double half = g.thickness / 2 + margin;
  const double h0 = g.normal.dot(p - g.origin);
  const double c = g.normal.dot(u);
  double lo = -1e300, hi = 1e300;
  if (std::abs(c) < 1e-9) {
    if (std::abs(h0) > half) return {};
  } else {
    lo = (-half - h0) / c;
    hi = (half - h0) / c;
    if (lo > hi) std::swap(lo, hi);
  }
  // Within the (grown) outline: the line projected onto the piece's plane.
  const Vec3 o3 = apply(g.inverse, p);
  const Vec3 d3 = g.inverse.topLeftCorner<3, 3>() * u;
  const Vec2 o(o3.x(), o3.y()), d(d3.x(), d3.y());
  Intervals out;
  if (d.norm() < 1e-9) {
    for (const Polygon2d& poly : g.grown) {
      if (locate(poly, o) != PointLocation::kOutside) return {{lo, hi}};
    }
    return {};
  }
  const double scale = d.norm();
  for (const Polygon2d& poly : g.grown) {
    for (const LineStretch& st : classify_line(poly, o, d)) {
      const double a = std::max(lo, st.s0 / scale), b = std::min(hi, st.s1 / scale);
      if (b > a) out.emplace_back(a, b);
    }
  }
  (void)piece;
  return out;
}

// A rectangle in a piece's frame along the line: s in [s0, s1], across in [w0, w1] (along n).
Polygon2d band(const Line2& l, double s0, double s1, double w0, double w1) {
  const Vec2 n(-l.d.y(), l.d.x());
  Polygon2d p;
  p.outer = {l.o + s0 * l.d + w0 * n,
             l.o + s1 * l.d + w0 * n,
             l.o + s1 * l.d + w1 * n,
             l.o + s0 * l.d + w1 * n};
  return oriented(std::move(p));
}

struct PieceCuts {
  Region2d remove_band, add, remove;
};

double upright(double deg) {
  while (deg > 90) deg -= 180;
  while (deg <= -90) deg += 180;
  return deg;
}

void add_dogbones(Region2d& region, double tool_diameter) {
  const double r = tool_diameter / 2;
  Region2d bites;
  auto ring_corners = [&](const Ring& ring) {
    const std::size_t n = ring.size();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 a = (ring[i] - ring[(i + n - 1) % n]).normalized();
      const Vec2 b = (ring[(i + 1) % n] - ring[i]).normalized();
      const double turn = a.x() * b.y() - a.y() * b.x();
      if (turn > -0.7) continue;  // only sharp inner corners of the material (~90°)
      const Vec2 right_a(a.y(), -a.x()), right_b(b.y(), -b.x());
      const Vec2 empty_side = (right_a + right_b).normalized();
      bites.push_back(circle(ring[i] + r * empty_side, r, 24));
    }
  };
  for (const Polygon2d& p : region) {
    ring_corners(p.outer);
    for (const Ring& h : p.holes) ring_corners(h);
  }
  if (!bites.empty()) region = subtract(region, bites);
}

}  // namespace

void detect_and_cut(Analysis& analysis,
                    const std::vector<ResolvedConnection>& connections,
                    const JointOptions& jopt,
                    const LabelOptions& labels,
                    const CheckOptions& options) {
  std::vector<PlacedComponent>& comps = analysis.components;
  // Pieces start as components; coplanar touching ones of one material merge (Alg. 2, 1–7).
  std::vector<Piece> pieces;
  for (int i = 0; i < static_cast<int>(comps.size()); ++i) {
    Piece p;
    p.name = comps[static_cast<std::size_t>(i)].name;
    p.components = {i};
    p.frame = comps[static_cast<std::size_t>(i)].frame;
    p.material = comps[static_cast<std::size_t>(i)].material;
    p.outline = comps[static_cast<std::size_t>(i)].shape.polygon;
    pieces.push_back(std::move(p));
  }
  const double eps = options.coplanar_tolerance_mm;
  bool merged = true;
  while (merged) {
    merged = false;
    for (std::size_t i = 0; i < pieces.size() && !merged; ++i) {
      for (std::size_t j = i + 1; j < pieces.size() && !merged; ++j) {
        const Vec3 ni = pieces[i].frame.block<3, 1>(0, 2), nj = pieces[j].frame.block<3, 1>(0, 2);
        if (ni.cross(nj).norm() > 1e-6) continue;
        const Mat4 rel = rigid_inverse(pieces[i].frame) * pieces[j].frame;
        if (std::abs(rel(2, 3)) > eps) continue;
        Polygon2d pj;
        for (const Vec2& v : pieces[j].outline.outer) {
          const Vec3 w = apply(rel, to3(v));
          pj.outer.emplace_back(w.x(), w.y());
        }
        for (const Ring& h : pieces[j].outline.holes) {
          Ring hr;
          for (const Vec2& v : h) {
            const Vec3 w = apply(rel, to3(v));
            hr.emplace_back(w.x(), w.y());
          }
          pj.holes.push_back(hr);
        }
        pj = oriented(pj);
        const Region2d joined = unite(offset({pieces[i].outline}, eps), offset({pj}, eps));
        if (joined.size() != 1) continue;  // coplanar but apart
        if (pieces[i].material.thickness_mm != pieces[j].material.thickness_mm ||
            pieces[i].material.name != pieces[j].material.name) {
          analysis.diagnostics.warning(codes::kOverlap,
                                       fmt::format("{} and {} are coplanar and touch but are of "
                                                   "different materials ({} {:g} mm, {} {:g} mm); "
                                                   "they are not merged and no joint joins them",
                                                   pieces[i].name,
                                                   pieces[j].name,
                                                   pieces[i].material.name,
                                                   pieces[i].material.thickness_mm,
                                                   pieces[j].material.name,
                                                   pieces[j].material.thickness_mm));
          continue;
        }
        const Region2d shrunk = offset(joined, -eps);
        if (shrunk.size() != 1) continue;
        pieces[i].outline = shrunk[0];
        pieces[i].components.insert(
            pieces[i].components.end(), pieces[j].components.begin(), pieces[j].components.end());
        pieces.erase(pieces.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
      }
    }
  }
  std::vector<int> piece_of(comps.size(), -1);
  for (int p = 0; p < static_cast<int>(pieces.size()); ++p) {
    for (int c : pieces[static_cast<std::size_t>(p)].components)
      piece_of[static_cast<std::size_t>(c)] = p;
  }
  for (std::size_t c = 0; c < comps.size(); ++c) comps[c].piece = piece_of[c];
  for (int k = 0; k < static_cast<int>(connections.size()); ++k) {
    const ResolvedConnection& rc = connections[static_cast<std::size_t>(k)];
    if (piece_of[static_cast<std::size_t>(rc.a)] == piece_of[static_cast<std::size_t>(rc.b)]) {
      analysis.merging_connections.push_back(k);
    }
  }
  if (pieces.size() > 1) {
    // Report merges so a user sees why two components became one piece.
    for (const Piece& p : pieces) {
      if (p.components.size() < 2) continue;
      std::vector<std::string> names;
      for (int c : p.components) names.push_back(comps[static_cast<std::size_t>(c)].name);
      analysis.diagnostics.note(
          codes::kOverlap,
          fmt::format("coplanar components merged into one piece: {}", fmt::join(names, ", ")));
    }
  }

  double max_thickness = 0;
  for (const Piece& p : pieces) max_thickness = std::max(max_thickness, p.material.thickness_mm);
  const double end_margin = jopt.end_margin_mm > 0 ? jopt.end_margin_mm : max_thickness;
  std::vector<PieceGeo> geo;
  for (const Piece& p : pieces) geo.push_back(piece_geo(p, end_margin));
  std::vector<PieceCuts> cuts(pieces.size());

  auto connection_between = [&](int pa, int pb) {
    for (int k = 0; k < static_cast<int>(connections.size()); ++k) {
      const int a = piece_of[static_cast<std::size_t>(connections[static_cast<std::size_t>(k)].a)];
      const int b = piece_of[static_cast<std::size_t>(connections[static_cast<std::size_t>(k)].b)];
      if ((a == pa && b == pb) || (a == pb && b == pa)) return k;
    }
    return -1;
  };

  int next_id = 1;
  std::vector<Joint> joints;
  for (int i = 0; i < static_cast<int>(pieces.size()); ++i) {
    for (int j = i + 1; j < static_cast<int>(pieces.size()); ++j) {
      const PieceGeo& gi = geo[static_cast<std::size_t>(i)];
      const PieceGeo& gj = geo[static_cast<std::size_t>(j)];
      const double reach = max_thickness;
      if ((gi.box_min.array() > gj.box_max.array() + reach).any() ||
          (gj.box_min.array() > gi.box_max.array() + reach).any())
        continue;
      Vec3 u = gi.normal.cross(gj.normal);
      if (u.norm() < 1e-6) continue;  // parallel (coplanar ones were merged)
      u.normalize();
      Eigen::Matrix3d M;
      M.row(0) = gi.normal.transpose();
      M.row(1) = gj.normal.transpose();
      M.row(2) = u.transpose();
      const Vec3 p = M.colPivHouseholderQr().solve(
          Vec3(gi.normal.dot(gi.origin), gj.normal.dot(gj.origin), 0));
      const Line2 li = line_in(gi, p, u), lj = line_in(gj, p, u);
      const auto si = classify_line(pieces[static_cast<std::size_t>(i)].outline, li.o, li.d, 1e-4);
      const auto sj = classify_line(pieces[static_cast<std::size_t>(j)].outline, lj.o, lj.d, 1e-4);
      for (const LineStretch& a : si) {
        for (const LineStretch& b : sj) {
          const double s0 = std::max(a.s0, b.s0), s1 = std::min(a.s1, b.s1);
          if (s1 - s0 < options.min_joint_length_mm) continue;
          Joint jt;
          jt.id = next_id++;
          const bool edge_i = a.where == PointLocation::kBoundary,
                     edge_j = b.where == PointLocation::kBoundary;
          jt.kind = edge_i && edge_j   ? JointKind::kFingerFinger
                    : edge_i || edge_j ? JointKind::kFingerHole
                                       : JointKind::kSlotSlot;
          // Finger–hole: piece_a carries the fingers.
          const bool swap = jt.kind == JointKind::kFingerHole && !edge_i;
          const int pa = swap ? j : i, pb = swap ? i : j;
          jt.piece_a = pa;
          jt.piece_b = pb;
          jt.start = p + s0 * u;
          jt.end = p + s1 * u;
          jt.length_mm = s1 - s0;
          jt.angle_deg =
              std::acos(std::clamp(std::abs(gi.normal.dot(gj.normal)), 0.0, 1.0)) * kRadToDeg;
          jt.connection = connection_between(i, j);
          joints.push_back(jt);
        }
      }
    }
  }

  // Cut each joint into its pieces.
  for (Joint& jt : joints) {
    const int pa = jt.piece_a, pb = jt.piece_b;
    const Piece& A = pieces[static_cast<std::size_t>(pa)];
    const Piece& B = pieces[static_cast<std::size_t>(pb)];
    const PieceGeo& ga = geo[static_cast<std::size_t>(pa)];
    const PieceGeo& gb = geo[static_cast<std::size_t>(pb)];
    const Vec3 u = (jt.end - jt.start).normalized();
    const Vec3 p = jt.start;
    const double len = jt.length_mm;
    const Line2 la = line_in(ga, p, u), lb = line_in(gb, p, u);
    auto inward = [&](const Piece& piece, const Line2& l, const PieceGeo& g) {
      const Vec2 n(-l.d.y(), l.d.x());
      const Vec2 mid = l.o + (len / 2) * l.d;
      const bool plus = locate(piece.outline, mid + 0.05 * n, 0) == PointLocation::kInside;
      const Vec2 v2 = plus ? n : Vec2(-n);
      jt.angle_deg += 0;  // (kept for clarity: the angle is already set)
      return std::pair<double, Vec3>(plus ? 1.0 : -1.0,
                                     g.inverse.topLeftCorner<3, 3>().transpose() * to3(v2));
    };
    const auto [sign_a, in_a] = inward(A, la, ga);
    const auto [sign_b, in_b] = inward(B, lb, gb);
    jt.inward_a = in_a;
    jt.inward_b = in_b;
    if (std::abs(jt.angle_deg - 90) > jopt.angle_tolerance_deg) {
      analysis.diagnostics.warning(
          codes::kNotPerpendicular,
          fmt::format("joint {} ({} between {} and {}) meets at {:.1f}°, not 90°: finger, hole and "
                      "slot joints only "
                      "hold at 90°; it is cut as if square and will not fit as a press fit",
                      jt.id,
                      to_string(jt.kind),
                      A.name,
                      B.name,
                      jt.angle_deg));
    }
    const double ta = A.material.thickness_mm, tb = B.material.thickness_mm;
    const double delta = (A.material.interference_mm + B.material.interference_mm) / 2;
    PieceCuts& ca = cuts[static_cast<std::size_t>(pa)];
    PieceCuts& cb = cuts[static_cast<std::size_t>(pb)];
    const double target = jopt.finger_width_mm > 0 ? jopt.finger_width_mm : 3 * std::max(ta, tb);

    if (jt.kind == JointKind::kSlotSlot) {
      auto on_boundary = [&](const Piece& piece, const Line2& l, double s) {
        return locate(piece.outline, l.o + s * l.d, 1e-3) == PointLocation::kBoundary;
      };
      const bool a0 = on_boundary(A, la, 0), a1 = on_boundary(A, la, len);
      const bool b0 = on_boundary(B, lb, 0), b1 = on_boundary(B, lb, len);
      const double wa = slot_width(tb, A.material.kerf_mm, delta);  // slot in A takes B's board
      const double wb = slot_width(ta, B.material.kerf_mm, delta);
      const double open = 1.0;  // run the slot past the edge so it opens cleanly
      if (a0 && a1 && !b0 && !b1) {
        cb.remove.push_back(
            band(lb, 0, len, -wb / 2, wb / 2));  // A goes through a closed slot in B
        jt.slot_open_b = 2;
      } else if (b0 && b1 && !a0 && !a1) {
        ca.remove.push_back(band(la, 0, len, -wa / 2, wa / 2));
        jt.slot_open_a = 2;
      } else {
        const bool a_from_start = a0 || !b0;
        jt.slot_open_a = a_from_start ? 1 : -1;
        jt.slot_open_b = -jt.slot_open_a;
        if (a_from_start) {
          ca.remove.push_back(band(la, -open, len / 2, -wa / 2, wa / 2));
          cb.remove.push_back(band(lb, len / 2, len + open, -wb / 2, wb / 2));
        } else {
          ca.remove.push_back(band(la, len / 2, len + open, -wa / 2, wa / 2));
          cb.remove.push_back(band(lb, -open, len / 2, -wb / 2, wb / 2));
        }
      }
      jt.fingers = (std::abs(jt.slot_open_a) == 1 ? 2 : 1);
      jt.finger_width_mm = 0;
      continue;
    }

    // Finger joints: usable stretches avoid the ends and every other board crossing the line.
    Intervals usable{{end_margin, len - end_margin}};
    if (usable[0].second <= usable[0].first) usable.clear();
    for (int k = 0; k < static_cast<int>(pieces.size()); ++k) {
      if (k == pa || k == pb) continue;
      usable = subtract_intervals(usable,
                                  slab_interval(pieces[static_cast<std::size_t>(k)],
                                                geo[static_cast<std::size_t>(k)],
                                                p,
                                                u,
                                                end_margin / 2));
    }
    const double min_finger = std::max(ta, tb);
    Intervals fingers_a, fingers_b;  // nominal [s0, s1] per finger
    double unit_width = 0;
    for (const auto& [u0, u1] : usable) {
      const double span = u1 - u0;
      if (span < min_finger) continue;
      int n = std::max(1, static_cast<int>(std::lround(span / target)));
      if (n % 2 == 0) n = n + 1 <= span / min_finger ? n + 1 : n - 1;
      n = std::max(n, 1);
      // Two boards meeting edge to edge interlock only with a finger from each: a short corner
      // (a lid's rim) gets the narrowest fingers that fit rather than none.
      if (jt.kind == JointKind::kFingerFinger && n < 2) {
        n = span >= 3 * min_finger ? 3 : span >= 2 * min_finger ? 2 : 1;
      }
      const double w = span / n;
      unit_width = w;
      for (int q = 0; q < n; ++q) {
        const double f0 = u0 + q * w, f1 = f0 + w;
        if (q % 2 == 0)
          fingers_a.emplace_back(f0, f1);
        else if (jt.kind == JointKind::kFingerFinger)
          fingers_b.emplace_back(f0, f1);
      }
    }
    jt.fingers = static_cast<int>(fingers_a.size() + fingers_b.size());
    jt.finger_width_mm = unit_width;
    if (fingers_a.empty() || (jt.kind == JointKind::kFingerFinger && fingers_b.empty())) {
      analysis.diagnostics.warning(
          codes::kJointFit,
          fmt::format(
              "joint {} ({} between {} and {}) is {:.1f} mm long with {:.1f} mm usable: too short "
              "for {} "
              "(fingers at least {:g} mm wide, {:g} mm clear of each end); the pieces meet without "
              "interlocking there",
              jt.id,
              to_string(jt.kind),
              A.name,
              B.name,
              len,
              [&] {
                double t = 0;
                for (const auto& [a0, a1] : usable) t += a1 - a0;
                return t;
              }(),
              jt.kind == JointKind::kFingerFinger ? "two interlocking fingers" : "a finger",
              min_finger,
              end_margin));
    }
    // Depth: the other board must leave material behind the joint band.
    auto depth_check = [&](const Piece& piece, const Line2& l, double sign, double other_t) {
      const Vec2 n = sign * Vec2(-l.d.y(), l.d.x());
      const Vec2 mid = l.o + (len / 2) * l.d;
      double depth = 0;
      for (const LineStretch& st : classify_line(piece.outline, mid, n)) {
        if (st.s0 <= 1e-6 && st.s1 > depth) depth = st.s1;
      }
      if (depth < other_t / 2 + 1.0) {
        analysis.diagnostics.warning(
            codes::kJointFit,
            fmt::format("joint {}: {} is only {:.1f} mm deep behind the joint, less than half the "
                        "{:g} mm board it meets plus 1 mm; the finger cut-back would cut it off",
                        jt.id,
                        piece.name,
                        depth,
                        other_t));
      }
    };
    depth_check(A, la, sign_a, tb);
    // Piece A (edge): cut back the band to the far face of B, add its fingers through B.
    const double wide_a = A.material.kerf_mm + delta / 4;  // per side
    const double wide_b = B.material.kerf_mm + delta / 4;
    const double far_a = sign_a * (tb / 2), near_a = -sign_a * (tb / 2 + 1.0);
    ca.remove_band.push_back(band(la, 0, len, std::min(far_a, near_a), std::max(far_a, near_a)));
    // A finger reaches a little into the cut-back body so the union joins them even where
    // rounding leaves the two edges a few nanometres apart (the overlap is material anyway).
    constexpr double kRoot = 0.05;
    auto finger_band = [&](const Line2& l, double f0, double f1, double sign, double t) {
      return band(l, f0, f1, sign > 0 ? -t / 2 : -t / 2 - kRoot, sign > 0 ? t / 2 + kRoot : t / 2);
    };
    for (const auto& [f0, f1] : fingers_a) {
      ca.add.push_back(finger_band(la, f0 - wide_a, f1 + wide_a, sign_a, tb));
    }
    if (jt.kind == JointKind::kFingerFinger) {
      depth_check(B, lb, sign_b, ta);
      const double far_b = sign_b * (ta / 2), near_b = -sign_b * (ta / 2 + 1.0);
      cb.remove_band.push_back(band(lb, 0, len, std::min(far_b, near_b), std::max(far_b, near_b)));
      for (const auto& [f0, f1] : fingers_b) {
        cb.add.push_back(finger_band(lb, f0 - wide_b, f1 + wide_b, sign_b, ta));
      }
    } else {
      // Piece B (face): a hole under each of A's fingers, narrower by the press fit.
      for (const auto& [f0, f1] : fingers_a) {
        cb.remove.push_back(band(lb, f0 + wide_b, f1 - wide_b, -ta / 2, ta / 2));
      }
    }
  }

  // Final outlines and marks.
  const double label_h =
      labels.height_mm > 0 ? labels.height_mm : std::max(3.0, 1.5 * max_thickness);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    Piece& piece = pieces[k];
    Region2d r{piece.outline};
    if (!cuts[k].remove_band.empty()) r = subtract(r, cuts[k].remove_band);
    if (!cuts[k].add.empty()) r = unite(r, cuts[k].add);
    if (!cuts[k].remove.empty()) r = subtract(r, cuts[k].remove);
    if (jopt.dogbone_tool_mm > 0) add_dogbones(r, jopt.dogbone_tool_mm);
    if (r.size() > 1) {
      // Keep the largest part; tiny slivers cut off by joints are reported.
      std::sort(r.begin(), r.end(), [](const Polygon2d& a, const Polygon2d& b) {
        return a.area() > b.area();
      });
      std::vector<std::string> dropped;
      for (std::size_t q = 1; q < r.size(); ++q) {
        const Box2d box = bounds(r[q].outer);
        dropped.push_back(fmt::format("{:.1f} mm² at ({:.1f}, {:.1f}) mm",
                                      r[q].area(),
                                      (box.min.x() + box.max.x()) / 2,
                                      (box.min.y() + box.max.y()) / 2));
      }
      analysis.diagnostics.warning(
          codes::kJointFit,
          fmt::format("{}: its joints cut it into {} parts; only the largest ({:.0f} mm²) is "
                      "kept, dropping {} (in the piece's frame)",
                      piece.name,
                      r.size(),
                      r[0].area(),
                      fmt::join(dropped, ", ")));
      r.resize(1);
    }
    piece.cut = r;
  }
  if (labels.assembly_marks) {
    for (const Joint& jt : joints) {
      for (int side = 0; side < 2; ++side) {
        const int self = side == 0 ? jt.piece_a : jt.piece_b;
        const int other = side == 0 ? jt.piece_b : jt.piece_a;
        Piece& piece = pieces[static_cast<std::size_t>(self)];
        const PieceGeo& g = geo[static_cast<std::size_t>(self)];
        const Vec3 u = (jt.end - jt.start).normalized();
        const Line2 l = line_in(g, jt.start, u);
        const Vec3 in3 = g.inverse.topLeftCorner<3, 3>() * (side == 0 ? jt.inward_a : jt.inward_b);
        Vec2 in2(in3.x(), in3.y());
        const double ot = pieces[static_cast<std::size_t>(other)].material.thickness_mm;
        const bool face =
            (jt.kind == JointKind::kFingerHole && side == 1) || jt.kind == JointKind::kSlotSlot;
        if (face) in2 = Vec2(-l.d.y(), l.d.x());
        const double along = jt.kind == JointKind::kSlotSlot
                                 ? jt.length_mm * (side == 0 ? 0.25 : 0.75)
                                 : jt.length_mm / 2;
        const Vec2 at = l.o + along * l.d + in2 * (ot / 2 + 0.9 * label_h);
        piece.marks.push_back({pieces[static_cast<std::size_t>(other)].name,
                               at,
                               upright(std::atan2(l.d.y(), l.d.x()) * kRadToDeg)});
      }
    }
  }
  analysis.pieces = std::move(pieces);
  analysis.joints = std::move(joints);
  // Connections the pieces do not honour.
  for (int k = 0; k < static_cast<int>(connections.size()); ++k) {
    const ResolvedConnection& rc = connections[static_cast<std::size_t>(k)];
    if (std::find(analysis.merging_connections.begin(), analysis.merging_connections.end(), k) !=
        analysis.merging_connections.end()) {
      continue;
    }
    const bool made = std::any_of(analysis.joints.begin(),
                                  analysis.joints.end(),
                                  [&](const Joint& j) { return j.connection == k; });
    if (made && rc.places_only) {
      analysis.diagnostics.warning(
          codes::kConnectionMakesNoJoint,
          fmt::format("{} ({}) says joint: none, but its pieces meet, so a joint is cut there; "
                      "move them apart or drop 'joint: none'",
                      rc.name,
                      rc.text),
          rc.where);
    } else if (!made && !rc.places_only) {
      analysis.diagnostics.warning(
          codes::kConnectionMakesNoJoint,
          fmt::format(
              "{} ({}): the two pieces do not meet, so no joint is cut there; check its offset "
              "and rotation",
              rc.name,
              rc.text),
          rc.where);
    }
  }
}

// ---- Press-fit order -------------------------------------------------------------------------

namespace {

// The directions a piece may leave a joint along, in the world.
struct Freedom {
  enum Kind { kCone, kRay, kLine } kind = kRay;
  Vec3 g1 = Vec3::Zero(), g2 = Vec3::Zero();
  Vec3 along = Vec3::Zero();  // cone: directions must be perpendicular to this
  bool allows(const Vec3& d) const {
    constexpr double tol = 1e-6;
    switch (kind) {
      case kRay:
        return d.dot(g1) > 1 - tol;
      case kLine:
        return std::abs(d.dot(g1)) > 1 - tol;
      case kCone: {
        if (std::abs(d.dot(along)) > tol) return false;
        Eigen::Matrix<double, 3, 2> G;
        G.col(0) = g1;
        G.col(1) = g2;
        const Eigen::Vector2d ab = G.colPivHouseholderQr().solve(d);
        return (G * ab - d).norm() < 1e-6 && ab.minCoeff() > -tol;
      }
    }
    return false;
  }
};

Freedom freedom_of(const Joint& j, bool for_a, const std::vector<Piece>& pieces) {
  Freedom f;
  const Vec3 u = (j.end - j.start).normalized();
  const Vec3 self_in = for_a ? j.inward_a : j.inward_b;
  const Vec3 other_in = for_a ? j.inward_b : j.inward_a;
  switch (j.kind) {
    case JointKind::kFingerFinger:
      f.kind = Freedom::kCone;
      f.g1 = self_in;
      f.g2 = -other_in;
      f.along = u;
      break;
    case JointKind::kFingerHole:
      f.kind = Freedom::kRay;
      f.g1 = for_a ? j.inward_a : Vec3(-j.inward_a);
      break;
    case JointKind::kSlotSlot: {
      const int open = for_a ? j.slot_open_a : j.slot_open_b;
      if (open == 1 || open == -1) {
        // Slides off towards its slot's closed end (the other board sits at the open end).
        f.kind = Freedom::kRay;
        f.g1 = open > 0 ? u : Vec3(-u);
      } else {
        // A board through a closed slot moves along the slotted board's normal.
        f.kind = Freedom::kLine;
        const int slotted =
            open == 2 ? (for_a ? j.piece_a : j.piece_b) : (for_a ? j.piece_b : j.piece_a);
        f.g1 = pieces[static_cast<std::size_t>(slotted)].frame.block<3, 1>(0, 2);
      }
      break;
    }
  }
  return f;
}

// A world direction for a maker: "+z", "−y", or the rounded vector.
std::string direction_text(const Vec3& v) {
  static const char* const kAxes[] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    if (std::abs(std::abs(v[k]) - 1) < 1e-6) return std::string(v[k] > 0 ? "+" : "−") + kAxes[k];
  }
  return fmt::format("({:.2f}, {:.2f}, {:.2f})", v.x() + 0.0, v.y() + 0.0, v.z() + 0.0);
}

std::string freedom_text(const Freedom& f) {
  switch (f.kind) {
    case Freedom::kRay:
      return "along " + direction_text(f.g1);
    case Freedom::kLine:
      return "along " + direction_text(f.g1) + " or back";
    case Freedom::kCone:
      return "between " + direction_text(f.g1) + " and " + direction_text(f.g2);
  }
  return "";
}

struct Planner {
  const std::vector<Joint>& joints;
  const std::vector<Piece>& pieces;
  /// The pieces of each sub-design (hierarchical composition), smallest first: tried as units.
  const std::vector<std::vector<int>>& sub_designs;
  int& group_count;
  std::vector<AssemblyStep> removal;  // disassembly order
  std::vector<int> stuck;

  // Can `unit` leave `rest ∪ unit` along some direction? Returns it.
  std::optional<Vec3> free_direction(const std::vector<int>& unit, const std::set<int>& present) {
    std::vector<Freedom> fs;
    std::vector<Vec3> candidates;
    const std::set<int> in_unit(unit.begin(), unit.end());
    for (const Joint& j : joints) {
      const bool a_in = in_unit.count(j.piece_a), b_in = in_unit.count(j.piece_b);
      if (a_in == b_in) continue;
      if (!present.count(a_in ? j.piece_b : j.piece_a)) continue;
      Freedom f = freedom_of(j, a_in, pieces);
      fs.push_back(f);
      candidates.push_back(f.g1);
      if (f.kind == Freedom::kLine) candidates.push_back(-f.g1);
      if (f.kind == Freedom::kCone) {
        candidates.push_back(f.g2);
        candidates.push_back((f.g1 + f.g2).normalized());
      }
    }
    if (fs.empty()) return Vec3(0, 0, 1);
    for (const Vec3& c : candidates) {
      if (c.norm() < 0.5) continue;
      const Vec3 d = c.normalized();
      if (std::all_of(fs.begin(), fs.end(), [&](const Freedom& f) { return f.allows(d); }))
        return d;
    }
    return std::nullopt;
  }

  // Takes `unit` out as a whole if it can leave, then takes it apart in its own order.
  bool take_unit(const std::vector<int>& unit, std::set<int>& present) {
    const auto d = free_direction(unit, present);
    if (!d) return false;
    Planner inner{joints, pieces, sub_designs, group_count, {}, {}};
    inner.plan(std::set<int>(unit.begin(), unit.end()));
    // A unit whose own pieces cannot come apart has no step to carry its direction (found by
    // the fuzzer: the write went past the steps).
    if (inner.removal.empty()) return false;
    const int group = ++group_count;
    for (AssemblyStep s : inner.removal) {
      if (s.group == 0) s.group = group;
      removal.push_back(s);
    }
    removal[removal.size() - inner.removal.size()].direction = *d;
    for (int q : unit) present.erase(q);
    stuck.insert(stuck.end(), inner.stuck.begin(), inner.stuck.end());
    return true;
  }

  void plan(std::set<int> present) {
    while (present.size() > 1) {
      bool done = false;
      // Single pieces first (last piece first, so the first component is assembled first).
      for (auto it = present.rbegin(); it != present.rend() && !done; ++it) {
        if (auto d = free_direction({*it}, present)) {
          removal.push_back({*it, *d, {}});
          present.erase(*it);
          done = true;
        }
      }
      // Then a sub-design as a whole (a design used as a component is built first, as its
      // maker would: the bunk bed's ladder goes in as one), smallest first.
      for (const std::vector<int>& unit : sub_designs) {
        if (done) break;
        if (unit.size() < 2 || unit.size() >= present.size()) continue;
        if (!std::all_of(unit.begin(), unit.end(), [&](int p) { return present.count(p) > 0; }))
          continue;
        done = take_unit(unit, present);
      }
      // Then connected sub-assemblies of two or three pieces, put together first.
      for (int size = 2; size <= 3 && !done; ++size) {
        const std::vector<int> list(present.begin(), present.end());
        std::vector<int> pick(static_cast<std::size_t>(size));
        std::function<bool(int, int)> choose = [&](int from, int depth) -> bool {
          if (depth == size) return take_unit(pick, present);
          for (int k = from; k < static_cast<int>(list.size()); ++k) {
            pick[static_cast<std::size_t>(depth)] = list[static_cast<std::size_t>(k)];
            if (choose(k + 1, depth + 1)) return true;
          }
          return false;
        };
        if (static_cast<int>(list.size()) > size && list.size() <= 40) done = choose(0, 0);
      }
      if (!done) {
        stuck.assign(present.begin(), present.end());
        return;
      }
    }
    if (present.size() == 1) removal.push_back({*present.begin(), Vec3::Zero(), {}});
  }
};

// The pieces of each sub-design instance ("desk." holds every piece whose components all
// have names starting so), smallest first; nested instances give nested units.
std::vector<std::vector<int>> sub_design_units(const Analysis& analysis) {
  std::map<std::string, std::vector<int>> by_scope;
  for (int p = 0; p < static_cast<int>(analysis.pieces.size()); ++p) {
    const Piece& piece = analysis.pieces[static_cast<std::size_t>(p)];
    const std::string& first =
        analysis.components[static_cast<std::size_t>(piece.components.front())].name;
    for (std::size_t dot = first.find('.'); dot != std::string::npos;
         dot = first.find('.', dot + 1)) {
      const std::string scope = first.substr(0, dot + 1);
      const bool all_inside =
          std::all_of(piece.components.begin(), piece.components.end(), [&](int c) {
            return analysis.components[static_cast<std::size_t>(c)].name.rfind(scope, 0) == 0;
          });
      if (all_inside) by_scope[scope].push_back(p);
    }
  }
  std::vector<std::vector<int>> units;
  for (auto& [scope, pieces] : by_scope) units.push_back(std::move(pieces));
  std::stable_sort(
      units.begin(), units.end(), [](const auto& a, const auto& b) { return a.size() < b.size(); });
  return units;
}

}  // namespace

void plan_assembly(Analysis& analysis) {
  const std::vector<std::vector<int>> units = sub_design_units(analysis);
  int group_count = 0;
  Planner planner{analysis.joints, analysis.pieces, units, group_count, {}, {}};
  std::set<int> all;
  for (int i = 0; i < static_cast<int>(analysis.pieces.size()); ++i) all.insert(i);
  planner.plan(all);
  std::sort(planner.stuck.begin(), planner.stuck.end());
  analysis.not_insertable = planner.stuck;
  if (!planner.stuck.empty()) {
    std::vector<std::string> names;
    for (int p : planner.stuck) names.push_back(analysis.pieces[static_cast<std::size_t>(p)].name);
    analysis.diagnostics.error(
        codes::kNotAssemblable,
        fmt::format("not assemblable: {} lock each other: none of them (nor any two or three "
                    "together, nor a sub-design as a whole) slides out along a direction all its "
                    "joints allow; remove one of the connections between them or change a joint",
                    fmt::join(names, ", ")));
    // Why, piece by piece: the ways out its joints with the others leave it (a few of them).
    const std::set<int> stuck(planner.stuck.begin(), planner.stuck.end());
    int explained = 0;
    for (int p : planner.stuck) {
      if (explained++ == 4) break;
      std::vector<std::string> ways;
      for (const Joint& j : analysis.joints) {
        const bool is_a = j.piece_a == p;
        if (!is_a && j.piece_b != p) continue;
        const int other = is_a ? j.piece_b : j.piece_a;
        if (!stuck.count(other) || ways.size() == 3) continue;
        ways.push_back(fmt::format("joint {} ({} with {}) lets it out only {}",
                                   j.id,
                                   to_string(j.kind),
                                   analysis.pieces[static_cast<std::size_t>(other)].name,
                                   freedom_text(freedom_of(j, is_a, analysis.pieces))));
      }
      if (ways.empty()) continue;
      analysis.diagnostics.note(
          codes::kNotAssemblable,
          fmt::format(
              "{}: {}", analysis.pieces[static_cast<std::size_t>(p)].name, fmt::join(ways, "; ")));
    }
    return;
  }
  // Assembly is disassembly reversed; a piece goes in against its way out.
  std::vector<AssemblyStep> steps(planner.removal.rbegin(), planner.removal.rend());
  for (AssemblyStep& s : steps) {
    s.direction = -s.direction;
    s.joints.clear();
    for (const Joint& j : analysis.joints) {
      if (j.piece_a == s.piece || j.piece_b == s.piece) s.joints.push_back(j.id);
    }
  }
  analysis.assembly = std::move(steps);
}

}  // namespace fabkit::flatpack::detail

#include "distance_bounds.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace fabkit::hacks::detail {
namespace {

struct PointSet {
  std::vector<ParamSpec> specs;
  std::vector<int> moving;             // parameters that move the connector point
  std::vector<std::vector<double>> q;  // parameters of each sample
  std::vector<Vec3> points;            // connector origins in part coordinates
  double margin = 0;                   // every reachable point lies within `margin` of some sample
};

// A primitive's connector origins (part coordinates) for parameters q: connector_frame's
// translation, from the primitive's base frame turned into a transform once, not per point (its
// Euler angles' sines and cosines were a third of sampling a connector).
class ConnectorOrigins {
 public:
  explicit ConnectorOrigins(const Primitive& p)
      : p_(p), base_(Rigid<double>::from_matrix(p.frame.matrix())) {}
  Vec3 operator()(const std::vector<double>& q) const {
    Rigid<double> m = base_;
    apply_connector<double>(p_.connector_kind(), p_.shape, q.data(), m);
    return m.t;
  }

 private:
  const Primitive& p_;
  Rigid<double> base_;
};

// Samples the connector origins of `p` over its whole parameter box, in part coordinates.
PointSet sample_connector_points(const Primitive& p) {
  PointSet out;
  out.specs = p.connector_params();
  const std::vector<ParamSpec>& specs = out.specs;
  const ConnectorOrigins connector_position(p);
  std::vector<double> q0;
  for (const auto& s : specs) q0.push_back(s.init);
  const Vec3 p0 = connector_position(q0);

  // Only parameters that move the point matter (spins and tilts do not).
  for (std::size_t i = 0; i < specs.size(); ++i) {
    std::vector<double> q = q0;
    q[i] = specs[i].lo + 0.37 * (specs[i].hi - specs[i].lo);
    if ((connector_position(q) - p0).norm() > 1e-9) out.moving.push_back(static_cast<int>(i));
  }
  const int dims = static_cast<int>(out.moving.size());
  const int n = dims <= 1 ? 97 : (dims == 2 ? 25 : 11);

  struct Axis {
    double lo, step;
    int count;
  };
  std::vector<Axis> axes;
  for (int i : out.moving) {
    const ParamSpec& s = specs[static_cast<std::size_t>(i)];
    if (s.tag == ParamTag::kUnbounded) {
      axes.push_back({0.0, 360.0 / n, n});
    } else {
      axes.push_back({s.lo, (s.hi - s.lo) / (n - 1), n});
    }
  }

  std::vector<double> max_rate(axes.size(), 0.0);
  std::vector<int> idx(axes.size(), 0);
  while (true) {
    std::vector<double> q = q0;
    for (std::size_t d = 0; d < axes.size(); ++d) {
      q[static_cast<std::size_t>(out.moving[d])] = axes[d].lo + axes[d].step * idx[d];
    }
    out.points.push_back(connector_position(q));
    // Rate of change along each axis, for the covering margin.
    for (std::size_t d = 0; d < axes.size(); ++d) {
      const double h = std::max(axes[d].step * 1e-3, 1e-7);
      std::vector<double> qp = q;
      qp[static_cast<std::size_t>(out.moving[d])] += h;
      max_rate[d] = std::max(max_rate[d], (connector_position(qp) - out.points.back()).norm() / h);
    }
    out.q.push_back(std::move(q));
    std::size_t d = 0;
    for (; d < axes.size(); ++d) {
      if (++idx[d] < axes[d].count) break;
      idx[d] = 0;
    }
    if (d == axes.size()) break;
  }
  for (std::size_t d = 0; d < axes.size(); ++d) out.margin += 0.5 * max_rate[d] * axes[d].step;
  out.margin *= 1.1;  // curvature between samples
  return out;
}

// Compass search from the best sample pair: sharpens the extreme distance so messages quote
// the real number; the sampling margin still guards the reject decision.
double refine_extreme(const Primitive& pa,
                      const PointSet& a,
                      const Mat4& fa,
                      std::vector<double> qa,
                      const Primitive& pb,
                      const PointSet& b,
                      const Mat4& fb,
                      std::vector<double> qb,
                      double sign) {
  const ConnectorOrigins origin_a(pa), origin_b(pb);
  auto dist = [&](const std::vector<double>& x, const std::vector<double>& y) {
    const Vec3 u = fa.topLeftCorner<3, 3>() * origin_a(x) + fa.topRightCorner<3, 1>();
    const Vec3 v = fb.topLeftCorner<3, 3>() * origin_b(y) + fb.topRightCorner<3, 1>();
    return sign * (u - v).norm();
  };
  struct Var {
    std::vector<double>* q;
    const ParamSpec* spec;
    std::size_t index;
  };
  std::vector<Var> vars;
  for (int i : a.moving)
    vars.push_back({&qa, &a.specs[static_cast<std::size_t>(i)], static_cast<std::size_t>(i)});
  for (int i : b.moving)
    vars.push_back({&qb, &b.specs[static_cast<std::size_t>(i)], static_cast<std::size_t>(i)});
  double best = dist(qa, qb);
  std::vector<double> step;
  for (const Var& v : vars) {
    step.push_back(v.spec->tag == ParamTag::kUnbounded ? 15.0 : (v.spec->hi - v.spec->lo) / 16);
  }
  for (int round = 0; round < 60; ++round) {
    bool improved = false;
    for (std::size_t k = 0; k < vars.size(); ++k) {
      for (double dir : {-1.0, 1.0}) {
        double& x = (*vars[k].q)[vars[k].index];
        const double old = x;
        x = old + dir * step[k];
        if (vars[k].spec->tag != ParamTag::kUnbounded) {
          x = std::clamp(x, vars[k].spec->lo, vars[k].spec->hi);
        }
        const double d = dist(qa, qb);
        if (d < best - 1e-12) {
          best = d;
          improved = true;
        } else {
          x = old;
        }
      }
    }
    if (!improved) {
      bool any = false;
      for (double& s : step) {
        s *= 0.5;
        any |= s > 1e-7;
      }
      if (!any) break;
    }
  }
  return sign * best;
}

}  // namespace

namespace {

// Every number a connector's points depend on, appended to `key`: its kind, shape, frame in
// its body and parameter box.
void append_primitive_key(const Primitive& p, std::vector<double>& key) {
  const PrimitiveShape& s = p.shape;
  key.push_back(static_cast<double>(p.connector_kind()));
  key.insert(key.end(),
             {s.radius,
              s.length,
              s.arc_radius,
              s.arc_angle,
              s.thickness,
              s.inner_radius,
              s.width,
              s.height,
              s.dist,
              s.open_gap});
  const Mat4 f = p.frame.matrix();
  key.insert(key.end(), f.data(), f.data() + 16);
  for (const ParamSpec& spec : p.connector_params()) {
    key.insert(key.end(), {spec.init, spec.lo, spec.hi, static_cast<double>(spec.tag)});
  }
}

// Every number a distance range depends on: the two connectors (above), where their bodies
// are, and whether they are one point set.
std::vector<double> range_key(const Primitive& a,
                              const Mat4& frame_a,
                              const Primitive& b,
                              const Mat4& frame_b,
                              bool same_point_set) {
  std::vector<double> key{same_point_set ? 1.0 : 0.0};
  for (const auto& [p, m] : {std::pair{&a, &frame_a}, std::pair{&b, &frame_b}}) {
    append_primitive_key(*p, key);
    key.insert(key.end(), m->data(), m->data() + 16);
  }
  return key;
}

// What was computed so far in this process, by every number it depends on (compared exactly;
// emptied when full). The value is computed outside the lock: two threads may both compute a
// missing one, which is the same value.
template <class Value>
class ProcessMemo {
 public:
  explicit ProcessMemo(std::size_t capacity) : capacity_(capacity) {}
  template <class Compute>
  Value get(std::vector<double> key, Compute compute) {
    {
      const std::lock_guard lock(mutex_);
      const auto it = values_.find(key);
      if (it != values_.end()) return it->second;
    }
    Value value = compute();
    const std::lock_guard lock(mutex_);
    if (values_.size() >= capacity_) values_.clear();
    values_.emplace(std::move(key), value);
    return value;
  }

 private:
  std::size_t capacity_;
  std::mutex mutex_;
  std::map<std::vector<double>, Value> values_;
};

// A connector's samples: one connector is in many ranges (a clip's hemisphere against each
// thing it holds; the toothbrush holder sampled one 625-point set four times, a third of
// verifying it).
std::shared_ptr<const PointSet> connector_samples(const Primitive& p) {
  static ProcessMemo<std::shared_ptr<const PointSet>> memo(256);
  std::vector<double> key;
  append_primitive_key(p, key);
  return memo.get(std::move(key),
                  [&] { return std::make_shared<const PointSet>(sample_connector_points(p)); });
}

DistanceRange measure_distance_range(const Primitive& a,
                                     const Mat4& frame_a,
                                     const Primitive& b,
                                     const Mat4& frame_b,
                                     bool same_point_set);

}  // namespace

DistanceRange connector_distance_range(const Primitive& a,
                                       const Mat4& frame_a,
                                       const Primitive& b,
                                       const Mat4& frame_b,
                                       bool same_point_set) {
  // A design's copies of one part (the S-hooks of a chain) span the same range, and each costs
  // thousands of samples and a local search (a fifth of verifying 8 independent cycles).
  static ProcessMemo<DistanceRange> memo(1024);
  return memo.get(range_key(a, frame_a, b, frame_b, same_point_set),
                  [&] { return measure_distance_range(a, frame_a, b, frame_b, same_point_set); });
}

namespace {

DistanceRange measure_distance_range(const Primitive& a,
                                     const Mat4& frame_a,
                                     const Primitive& b,
                                     const Mat4& frame_b,
                                     bool same_point_set) {
  const std::shared_ptr<const PointSet> samples_a = connector_samples(a);
  const std::shared_ptr<const PointSet> samples_b =
      same_point_set ? samples_a : connector_samples(b);
  const PointSet& sa = *samples_a;
  const PointSet& sb = *samples_b;
  auto place = [](const Vec3& v, const Mat4& m) {
    return Vec3(m.topLeftCorner<3, 3>() * v + m.topRightCorner<3, 1>());
  };
  // Every pair of samples (thousands × thousands) that could hold an extreme: the second set by
  // coordinate in blocks of consecutive samples (neighbours on the parameter grid, so near in
  // space), each with its bounding box. A block whose box is no nearer than the nearest pair so
  // far and no farther than the farthest cannot change either, and is skipped: the same extremes
  // and pairs as comparing all of them (a skipped block holds no value that would have replaced
  // one), in a fraction of the time. Compared by squared distance, so the inner loop is plain
  // arithmetic the compiler vectorises; the square root of the extremes only (it is monotonic).
  const std::size_t nb = sb.points.size();
  constexpr std::size_t kBlock = 32;
  std::vector<double> bx(nb), by(nb), bz(nb), d2(kBlock);
  for (std::size_t j = 0; j < nb; ++j) {
    const Vec3 v = place(sb.points[j], frame_b);
    bx[j] = v.x();
    by[j] = v.y();
    bz[j] = v.z();
  }
  struct Box {
    Vec3 lo, hi;
  };
  std::vector<Box> boxes;
  for (std::size_t start = 0; start < nb; start += kBlock) {
    Box box{Vec3::Constant(std::numeric_limits<double>::infinity()),
            Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (std::size_t j = start; j < std::min(nb, start + kBlock); ++j) {
      box.lo = box.lo.cwiseMin(Vec3(bx[j], by[j], bz[j]));
      box.hi = box.hi.cwiseMax(Vec3(bx[j], by[j], bz[j]));
    }
    boxes.push_back(box);
  }
  double lo2 = std::numeric_limits<double>::infinity();
  double hi2 = -1;
  std::size_t lo_i = 0, lo_j = 0, hi_i = 0, hi_j = 0;
  for (std::size_t i = 0; i < sa.points.size(); ++i) {
    const Vec3 u = place(sa.points[i], frame_a);
    const double ux = u.x(), uy = u.y(), uz = u.z();
    double row_lo = std::numeric_limits<double>::infinity();
    double row_hi = -1;
    std::size_t row_lo_j = 0, row_hi_j = 0;
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      const Box& box = boxes[k];
      const Vec3 below = (box.lo - u).cwiseMax(u - box.hi).cwiseMax(0.0);
      const Vec3 across = (u - box.lo).cwiseAbs().cwiseMax((box.hi - u).cwiseAbs());
      // Summed in the order the pairs' distances are, so that a bound equal to a pair's
      // distance is the same double.
      const double nearest = below.x() * below.x() + below.y() * below.y() + below.z() * below.z();
      const double farthest =
          across.x() * across.x() + across.y() * across.y() + across.z() * across.z();
      if (nearest >= lo2 && farthest <= hi2) continue;
      const std::size_t start = k * kBlock;
      const std::size_t count = std::min(kBlock, nb - start);
      double block_lo = std::numeric_limits<double>::infinity();
      double block_hi = -1;
      for (std::size_t j = 0; j < count; ++j) {
        const double dx = ux - bx[start + j], dy = uy - by[start + j], dz = uz - bz[start + j];
        d2[j] = dx * dx + dy * dy + dz * dz;
        block_lo = std::min(block_lo, d2[j]);
        block_hi = std::max(block_hi, d2[j]);
      }
      // The first pair attaining a new extreme, as a scan in order would keep.
      auto first_at = [&](double value) {
        return start + static_cast<std::size_t>(
                           std::find(d2.begin(), d2.begin() + static_cast<long>(count), value) -
                           d2.begin());
      };
      if (block_lo < row_lo) {
        row_lo = block_lo;
        row_lo_j = first_at(block_lo);
      }
      if (block_hi > row_hi) {
        row_hi = block_hi;
        row_hi_j = first_at(block_hi);
      }
    }
    if (row_lo < lo2) {
      lo2 = row_lo;
      lo_i = i;
      lo_j = row_lo_j;
    }
    if (row_hi > hi2) {
      hi2 = row_hi;
      hi_i = i;
      hi_j = row_hi_j;
    }
  }
  const double lo = std::sqrt(lo2);
  const double hi = hi2 < 0 ? -1.0 : std::sqrt(hi2);
  DistanceRange r;
  r.margin = sa.margin + sb.margin;
  r.hi = std::max(hi, refine_extreme(a, sa, frame_a, sa.q[hi_i], b, sb, frame_b, sb.q[hi_j], -1.0));
  r.lo = same_point_set
             ? 0.0
             : std::min(
                   lo, refine_extreme(a, sa, frame_a, sa.q[lo_i], b, sb, frame_b, sb.q[lo_j], 1.0));
  return r;
}

}  // namespace

PolygonVerdict check_cycle_polygon(const Assembly& assembly, ConnectionId closing) {
  const Connection& c = assembly.connection(closing);

  const Assembly::CyclePath loop = assembly.cycle_path(closing);
  const std::vector<PartId>& path_a = loop.first_side;
  const std::vector<PartId>& path_b = loop.second_side;
  const bool common_ancestor = loop.common_ancestor;

  // The primitive of part path[k] that connects towards the closing connection.
  auto down_primitive =
      [&](const std::vector<PartId>& path, std::size_t k, PrimitiveId closing_prim) {
        if (k == 0) return closing_prim;
        return assembly.connection(assembly.parent(path[k - 1])).first.primitive;
      };
  auto up_primitive = [&](PartId p) {
    return assembly.connection(assembly.parent(p)).second.primitive;
  };

  PolygonVerdict verdict;
  const Mat4 identity = Mat4::Identity();
  auto add_segment = [&](PartId part, PrimitiveId pa, PrimitiveId pb) {
    const Part& body = *assembly.node(part).part;
    CycleSegment seg;
    if (pa == pb) {
      seg.description = fmt::format("across {}", assembly.label(part, pa));
    } else {
      seg.description =
          fmt::format("between {} and {}", assembly.label(part, pa), assembly.label(part, pb));
    }
    seg.range = connector_distance_range(
        body.primitive(pa), identity, body.primitive(pb), identity, pa == pb);
    verdict.segments.push_back(seg);
  };

  // Parts strictly below the common top on each side.
  const std::size_t below_a = path_a.size() - 1;
  const std::size_t below_b = path_b.size() - 1;
  for (std::size_t k = 0; k < below_a; ++k) {
    add_segment(path_a[k], down_primitive(path_a, k, c.first.primitive), up_primitive(path_a[k]));
  }
  for (std::size_t k = 0; k < below_b; ++k) {
    add_segment(path_b[k], down_primitive(path_b, k, c.second.primitive), up_primitive(path_b[k]));
  }
  const PrimitiveId top_a = down_primitive(path_a, below_a, c.first.primitive);
  const PrimitiveId top_b = down_primitive(path_b, below_b, c.second.primitive);
  if (common_ancestor) {
    add_segment(path_a.back(), top_a, top_b);
  } else {
    // Two environments: both are fixed in the world, so measure between them, in the first
    // one's frame: the range depends on where one stands relative to the other only, and the
    // same pair anywhere in the world (a row of rod pairs) is measured once.
    const PartNode& ea = assembly.node(path_a.back());
    const PartNode& eb = assembly.node(path_b.back());
    const Mat4 b_from_a = rigid_inverse(ea.frame.matrix()) * eb.frame.matrix();
    CycleSegment seg;
    seg.description = fmt::format("between {} and {}",
                                  assembly.label(path_a.back(), top_a),
                                  assembly.label(path_b.back(), top_b));
    seg.range = connector_distance_range(
        ea.part->primitive(top_a), identity, eb.part->primitive(top_b), b_from_a, false);
    verdict.segments.push_back(seg);
  }

  double total_hi = 0;
  double total_margin = 0;
  for (const auto& s : verdict.segments) {
    total_hi += s.range.hi;
    total_margin += s.range.margin;
  }
  verdict.margin = total_margin;
  for (std::size_t k = 0; k < verdict.segments.size(); ++k) {
    const double others = total_hi - verdict.segments[k].range.hi;
    const double excess = verdict.segments[k].range.lo - others;
    if (verdict.tightest < 0 ||
        excess > verdict.segments[static_cast<std::size_t>(verdict.tightest)].range.lo -
                     verdict.tightest_others_span) {
      verdict.tightest = static_cast<int>(k);
      verdict.tightest_others_span = others;
    }
    // Reject only beyond what sampling could have missed.
    if (verdict.segments[k].range.lo - total_margin > others) {
      verdict.feasible = false;
      verdict.failing = static_cast<int>(k);
      verdict.others_span = others;
      break;
    }
  }
  return verdict;
}

}  // namespace fabkit::hacks::detail

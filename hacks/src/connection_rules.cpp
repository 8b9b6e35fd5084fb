#include "fabkit/hacks/connection_rules.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <numbers>

#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {
namespace {

using PT = PrimitiveType;

bool is_pair(PT a, PT b, PT x, PT y) {
  return (a == x && b == y) || (a == y && b == x);
}

struct AlignmentRow {
  std::string_view key;  // "<first>_<second>"
  std::array<double, 3> rot;
  std::vector<int> flip_axes;
};

// Reference §3.3, keyed by ctype (Flex / Ctl suffixes) or by class.
const std::vector<AlignmentRow>& alignment_table() {
  static const std::vector<AlignmentRow> rows = [] {
    std::vector<AlignmentRow> r;
    auto add = [&r](std::initializer_list<std::string_view> keys,
                    std::array<double, 3> rot,
                    std::vector<int> axes) {
      for (std::string_view k : keys) r.push_back({k, rot, axes});
    };
    const std::array<double, 3> hang{180, 0, 90};
    add({"Rod_Hook", "Rod_HookFlex", "Hook_Rod", "HookFlex_Rod"}, hang, {2});
    add({"Rod_Ring", "Rod_RingFlex", "Ring_Rod", "RingFlex_Rod", "Rod_RingCtl", "RingCtl_Rod"},
        hang,
        {2});
    add({"RodCtl_Hook", "RodCtl_HookFlex", "Hook_RodCtl", "HookFlex_RodCtl"}, hang, {2});
    add({"RodCtl_Ring", "RodCtl_RingFlex", "Ring_RodCtl", "RingFlex_RodCtl"}, hang, {2});
    add({"RodCtl_RingCtl", "RingCtl_RodCtl"}, {0, 0, 90}, {2});
    add({"Rod_Tube", "Tube_Rod"}, {0, 90, 0}, {});
    add({"Rod_TubeCtl", "TubeCtl_Rod"}, {0, 0, 0}, {});
    add({"Tube_Hook", "Tube_HookFlex", "Hook_Tube", "HookFlex_Tube"}, {0, 0, 90}, {2});
    add({"Tube_Ring", "Tube_RingFlex", "Ring_Tube", "RingFlex_Tube"}, {0, 0, 90}, {2});
    add({"Hook_Hook", "Hook_HookFlex", "HookFlex_Hook", "HookFlex_HookFlex"}, hang, {2});
    add({"Hook_Ring",
         "Hook_RingFlex",
         "Ring_Hook",
         "RingFlex_Hook",
         "HookFlex_Ring",
         "HookFlex_RingFlex",
         "Ring_HookFlex",
         "RingFlex_HookFlex"},
        hang,
        {2});
    add({"Hook_RingCtl", "HookFlex_RingCtl", "RingCtl_Hook", "RingCtl_HookFlex"}, hang, {2});
    add({"Hook_Edge", "HookFlex_Edge"}, {90, 0, -90}, {2});
    add({"Edge_Hook", "Edge_HookFlex"}, {-90, 0, 90}, {2});
    add({"Edge_Clip"}, {0, -90, -90}, {1, 2});
    add({"Clip_Edge"}, {0, 90, 90}, {1, 2});
    add({"Clip_Rod", "Rod_Clip", "Clip_RodCtl", "RodCtl_Clip"}, {0, 180, 0}, {1});
    add({"Surface_Surface"}, {0, 0, 0}, {0});
    return r;
  }();
  return rows;
}

std::string_view class_name(ConnectorKind k) {
  switch (k) {
    case ConnectorKind::kRod:
    case ConnectorKind::kRodCenterline:
      return "Rod";
    case ConnectorKind::kHook:
    case ConnectorKind::kHookFlex:
      return "Hook";
    case ConnectorKind::kRing:
    case ConnectorKind::kRingFlex:
    case ConnectorKind::kRingCenterline:
      return "Ring";
    case ConnectorKind::kTube:
    case ConnectorKind::kTubeCenterline:
      return "Tube";
    default:
      return to_string(k);
  }
}

const AlignmentRow* find_row(const std::string& key) {
  for (const auto& row : alignment_table()) {
    if (row.key == key) return &row;
  }
  return nullptr;
}

std::string mm(double v) {
  return fmt::format("{:.1f} mm", v);
}

}  // namespace

bool pair_allowed(PrimitiveType a, PrimitiveType b) {
  return is_pair(a, b, PT::kRod, PT::kHook) || is_pair(a, b, PT::kRod, PT::kRing) ||
         is_pair(a, b, PT::kRod, PT::kClip) || is_pair(a, b, PT::kRod, PT::kTube) ||
         is_pair(a, b, PT::kHook, PT::kHook) || is_pair(a, b, PT::kHook, PT::kRing) ||
         is_pair(a, b, PT::kHook, PT::kTube) || is_pair(a, b, PT::kRing, PT::kTube) ||
         is_pair(a, b, PT::kClip, PT::kTube) || is_pair(a, b, PT::kClip, PT::kEdge) ||
         is_pair(a, b, PT::kTube, PT::kTube) || is_pair(a, b, PT::kSurface, PT::kSurface) ||
         is_pair(a, b, PT::kSurface, PT::kHemisphere);
}

std::vector<PrimitiveType> allowed_partners(PrimitiveType t) {
  std::vector<PrimitiveType> out;
  for (PT other : {PT::kRod,
                   PT::kHook,
                   PT::kRing,
                   PT::kClip,
                   PT::kTube,
                   PT::kEdge,
                   PT::kSurface,
                   PT::kHemisphere}) {
    if (pair_allowed(t, other)) out.push_back(other);
  }
  return out;
}

std::string_view to_string(AlignmentChoice a) {
  return a == AlignmentChoice::kFlip ? "flip" : "default";
}

std::optional<AlignmentChoice> alignment_choice_from_string(std::string_view s) {
  if (s == "default") return AlignmentChoice::kDefault;
  if (s == "flip") return AlignmentChoice::kFlip;
  return std::nullopt;
}

Vec3 AlignmentOffset::rotation(AlignmentChoice choice) const {
  Vec3 r = rot;
  if (choice == AlignmentChoice::kFlip) {
    for (int axis : flip_axes) {
      if (r[axis] == 0) {
        r[axis] = 180;
      } else if (r[axis] == 180) {
        r[axis] = 0;
      } else {
        r[axis] = -r[axis];
      }
    }
  }
  return r;
}

AlignmentOffset alignment_offset(ConnectorKind first, ConnectorKind second) {
  const AlignmentRow* row = find_row(fmt::format("{}_{}", to_string(first), to_string(second)));
  if (!row) row = find_row(fmt::format("{}_{}", class_name(first), class_name(second)));
  AlignmentOffset out;
  if (row) {
    out.rot = Vec3(row->rot[0], row->rot[1], row->rot[2]);
    out.flip_axes = row->flip_axes;
  }
  return out;
}

namespace {
// The order in which a pair of kinds reads the alignment table (alignment_matrix), by class:
// kinds of one class (a hook and a flexible hook) share a rank, their rows being half turns or
// the identity, the same read either way.
std::size_t host_rank(ConnectorKind k) {
  static constexpr std::array<std::string_view, 8> kHostFirst = {
      "Edge", "Surface", "Ring", "Hook", "Rod", "Tube", "Clip", "Hemisphere"};
  return static_cast<std::size_t>(std::find(kHostFirst.begin(), kHostFirst.end(), class_name(k)) -
                                  kHostFirst.begin());
}
}  // namespace

Mat4 alignment_matrix(ConnectorKind first, ConnectorKind second, AlignmentChoice choice) {
  const Mat4 forward = alignment_offset(first, second).matrix(choice);
  if (host_rank(second) >= host_rank(first)) return forward;
  // Read the other way: C_second · A' = C_first, so C_first · A'⁻¹ = C_second. Where the two
  // directions of the table agree (A·A' = I: the half turns and the identity, most pairs) the
  // forward row is kept as it is, to the last bit.
  const Mat4 reverse = alignment_offset(second, first).matrix(choice);
  if ((forward * reverse - Mat4::Identity()).cwiseAbs().maxCoeff() < 1e-12) return forward;
  Mat4 inverse = Mat4::Identity();
  inverse.topLeftCorner<3, 3>() = reverse.topLeftCorner<3, 3>().transpose();
  return inverse;
}

namespace {
// The free radius inside a hook's or ring's wire: its arc radius (to the wire's centre line)
// less the wire's radius. What passes through must fit in this.
double opening(const Primitive& p) {
  return p.shape.arc_radius - p.shape.thickness;
}
}  // namespace

bool check_compatibility(const PrimitiveInUse& a,
                         const PrimitiveInUse& b,
                         Diagnostics& diags,
                         const SourceLocation& where) {
  const std::size_t before = diags.size();
  const Primitive& pa = *a.primitive;
  const Primitive& pb = *b.primitive;
  // Order the pair so each rule below reads one way: x is the "first" type of the rule.
  auto ordered = [&](PT x) -> std::pair<const PrimitiveInUse*, const PrimitiveInUse*> {
    if (pa.type == x) return {&a, &b};
    return {&b, &a};
  };
  auto fail = [&](DiagnosticCode code, std::string msg) {
    diags.error(code, std::move(msg), where);
  };
  auto avail = [](const PrimitiveInUse& u, std::size_t i = 0) {
    if (u.available.size() > i) return u.available[i];
    const std::vector<double> cd = u.primitive->critical_dim();
    return cd.size() > i ? cd[i] : 0.0;
  };
  auto no_space = [&](const PrimitiveInUse& host,
                      double need,
                      const PrimitiveInUse& guest,
                      const std::string& why) {
    const std::vector<double> total = host.primitive->critical_dim();
    fail(codes::kNoSpaceLeft,
         fmt::format("{}: only {} of its {} {} is still free, but {} needs {} ({})",
                     host.label,
                     mm(avail(host)),
                     mm(total.empty() ? 0.0 : total[0]),
                     host.primitive->type == PT::kRing ? "arc radius" : "length",
                     guest.label,
                     mm(need),
                     why));
  };
  auto both_closed = [&](const PrimitiveInUse& x, const PrimitiveInUse& y) {
    fail(codes::kBothClosed,
         fmt::format(
             "{} and {} are both closed: neither can be slid onto the other", x.label, y.label));
  };
  auto must_be_open = [&](const PrimitiveInUse& closed, const PrimitiveInUse& ring) {
    fail(codes::kBothClosed,
         fmt::format("{} is closed at its ends, so {} ({}) cannot be slid onto it",
                     closed.label,
                     ring.label,
                     to_string(ring.primitive->type)));
  };
  auto too_small = [&](const std::string& who,
                       const std::string& what,
                       double have,
                       const std::string& other_what,
                       double need,
                       const std::string& other) {
    fail(codes::kDimensionMismatch,
         fmt::format("{}: {} {} is {} {} {} ({})",
                     who,
                     what,
                     mm(have),
                     have < need ? "smaller than" : "no larger than",
                     other_what,
                     mm(need),
                     other));
  };

  if (is_pair(pa.type, pb.type, PT::kRod, PT::kHook)) {
    auto [rod, hook] = ordered(PT::kRod);
    const Primitive& r = *rod->primitive;
    const Primitive& h = *hook->primitive;
    if (r.closed_for_connect() && h.closed_for_connect()) both_closed(*rod, *hook);
    if (!(r.shape.radius < opening(h))) {
      too_small(hook->label, "hook opening", opening(h), "rod radius", r.shape.radius, rod->label);
    }
    if (!(avail(*rod) > 2 * h.shape.thickness)) {
      no_space(*rod, 2 * h.shape.thickness, *hook, "twice its wire radius");
    }
  } else if (is_pair(pa.type, pb.type, PT::kRod, PT::kRing)) {
    auto [rod, ring] = ordered(PT::kRod);
    const Primitive& r = *rod->primitive;
    if (r.closed_for_connect()) must_be_open(*rod, *ring);
    if (!(r.shape.radius < opening(*ring->primitive))) {
      too_small(ring->label,
                "ring opening",
                opening(*ring->primitive),
                "rod radius",
                r.shape.radius,
                rod->label);
    }
  } else if (is_pair(pa.type, pb.type, PT::kRod, PT::kClip)) {
    auto [rod, clip] = ordered(PT::kRod);
    const double d = 2 * rod->primitive->shape.radius;
    if (!(d < clip->primitive->shape.open_gap)) {
      too_small(clip->label,
                "clip opening",
                clip->primitive->shape.open_gap,
                "rod diameter",
                d,
                rod->label);
    }
  } else if (is_pair(pa.type, pb.type, PT::kRod, PT::kTube)) {
    auto [rod, tube] = ordered(PT::kRod);
    const Primitive& t = *tube->primitive;
    if (rod->primitive->closed_for_connect()) must_be_open(*rod, *tube);
    if (!(rod->primitive->shape.radius < t.shape.inner_radius)) {
      too_small(tube->label,
                "tube inner radius",
                t.shape.inner_radius,
                "rod radius",
                rod->primitive->shape.radius,
                rod->label);
    }
    if (!(avail(*rod) > t.shape.length)) no_space(*rod, t.shape.length, *tube, "its length");
  } else if (pa.type == PT::kHook && pb.type == PT::kHook) {
    if (pa.closed_for_connect() && pb.closed_for_connect()) both_closed(a, b);
    if (!(pa.shape.thickness < opening(pb))) {
      too_small(b.label, "hook opening", opening(pb), "wire radius", pa.shape.thickness, a.label);
    }
    if (!(pb.shape.thickness < opening(pa))) {
      too_small(a.label, "hook opening", opening(pa), "wire radius", pb.shape.thickness, b.label);
    }
  } else if (is_pair(pa.type, pb.type, PT::kHook, PT::kRing)) {
    auto [hook, ring] = ordered(PT::kHook);
    const Primitive& h = *hook->primitive;
    const Primitive& g = *ring->primitive;
    if (h.closed_for_connect()) both_closed(*hook, *ring);
    if (!(h.shape.thickness < opening(g))) {
      too_small(ring->label,
                "ring opening",
                opening(g),
                "hook wire radius",
                h.shape.thickness,
                hook->label);
    }
    if (!(g.shape.thickness < opening(h))) {
      too_small(hook->label,
                "hook opening",
                opening(h),
                "ring wire radius",
                g.shape.thickness,
                ring->label);
    }
  } else if (is_pair(pa.type, pb.type, PT::kHook, PT::kTube)) {
    auto [hook, tube] = ordered(PT::kHook);
    const Primitive& h = *hook->primitive;
    const Primitive& t = *tube->primitive;
    if (t.closed_for_connect() && h.closed_for_connect()) both_closed(*hook, *tube);
    const double outer = t.shape.inner_radius + t.shape.thickness;
    if (!(opening(h) > outer)) {
      too_small(hook->label, "hook opening", opening(h), "tube outer radius", outer, tube->label);
    }
    if (!(avail(*tube) > 2 * h.shape.thickness)) {
      no_space(*tube, 2 * h.shape.thickness, *hook, "twice its wire radius");
    }
  } else if (is_pair(pa.type, pb.type, PT::kRing, PT::kTube)) {
    auto [ring, tube] = ordered(PT::kRing);
    const Primitive& t = *tube->primitive;
    const double outer = t.shape.inner_radius + t.shape.thickness;
    if (t.closed_for_connect()) must_be_open(*tube, *ring);
    if (!(opening(*ring->primitive) > outer)) {
      too_small(ring->label,
                "ring opening",
                opening(*ring->primitive),
                "tube outer radius",
                outer,
                tube->label);
    }
  } else if (is_pair(pa.type, pb.type, PT::kClip, PT::kTube)) {
    auto [clip, tube] = ordered(PT::kClip);
    const Primitive& t = *tube->primitive;
    const double outer = t.shape.inner_radius + t.shape.thickness;
    if (!(clip->primitive->shape.open_gap > outer)) {
      too_small(clip->label,
                "clip opening",
                clip->primitive->shape.open_gap,
                "tube outer radius",
                outer,
                tube->label);
    }
    if (!(avail(*tube) > clip->primitive->shape.width)) {
      no_space(*tube, clip->primitive->shape.width, *clip, "its jaw width");
    }
  } else if (is_pair(pa.type, pb.type, PT::kClip, PT::kEdge)) {
    auto [clip, edge] = ordered(PT::kClip);
    if (!(clip->primitive->shape.open_gap > edge->primitive->shape.height)) {
      too_small(clip->label,
                "clip opening",
                clip->primitive->shape.open_gap,
                "edge thickness",
                edge->primitive->shape.height,
                edge->label);
    }
    if (!(avail(*edge) > clip->primitive->shape.width)) {
      no_space(*edge, clip->primitive->shape.width, *clip, "its jaw width");
    }
  } else if (pa.type == PT::kTube && pb.type == PT::kTube) {
    auto fits_inside = [&](const PrimitiveInUse& in, const PrimitiveInUse& out) {
      const Primitive& i = *in.primitive;
      const Primitive& o = *out.primitive;
      return i.is_open && i.shape.inner_radius + i.shape.thickness < o.shape.inner_radius &&
             avail(in) > o.shape.length;
    };
    if (!fits_inside(a, b) && !fits_inside(b, a)) {
      fail(codes::kDimensionMismatch,
           fmt::format("{} and {}: neither tube fits inside the other (outer radii {} and {}, "
                       "inner radii {} and {})",
                       a.label,
                       b.label,
                       mm(pa.shape.inner_radius + pa.shape.thickness),
                       mm(pb.shape.inner_radius + pb.shape.thickness),
                       mm(pa.shape.inner_radius),
                       mm(pb.shape.inner_radius)));
    }
  } else if (pa.type == PT::kSurface && pb.type == PT::kSurface) {
    const bool a_smaller = pa.shape.width < pb.shape.width && pa.shape.length < pb.shape.length;
    const bool b_smaller = pb.shape.width < pa.shape.width && pb.shape.length < pa.shape.length;
    if (!a_smaller && !b_smaller) {
      fail(codes::kDimensionMismatch,
           fmt::format("{} ({} × {}) and {} ({} × {}): one surface must be smaller than the other "
                       "in both width and length to rest on it",
                       a.label,
                       mm(pa.shape.width),
                       mm(pa.shape.length),
                       b.label,
                       mm(pb.shape.width),
                       mm(pb.shape.length)));
    } else {
      const PrimitiveInUse& small = a_smaller ? a : b;
      const PrimitiveInUse& large = a_smaller ? b : a;
      if (!(avail(small, 0) < avail(large, 0) && avail(small, 1) < avail(large, 1))) {
        fail(codes::kNoSpaceLeft,
             fmt::format("{}: only {} × {} of it is still free, not enough for {} ({} × {})",
                         large.label,
                         mm(avail(large, 0)),
                         mm(avail(large, 1)),
                         small.label,
                         mm(avail(small, 0)),
                         mm(avail(small, 1))));
      }
    }
  } else if (is_pair(pa.type, pb.type, PT::kSurface, PT::kHemisphere)) {
    auto [surf, hemi] = ordered(PT::kSurface);
    const double r = hemi->primitive->shape.radius;
    const Primitive& s = *surf->primitive;
    const double need = std::numbers::pi * r;
    if (!(s.shape.width > need && s.shape.length > need)) {
      fail(codes::kDimensionMismatch,
           fmt::format("{}: surface {} × {} is too small for {} (needs more than {} each way)",
                       surf->label,
                       mm(s.shape.width),
                       mm(s.shape.length),
                       hemi->label,
                       mm(need)));
    } else if (!(avail(*surf, 0) > 2 * r && avail(*surf, 1) > r)) {
      fail(codes::kNoSpaceLeft,
           fmt::format("{}: only {} × {} of it is still free, not enough for {} (radius {})",
                       surf->label,
                       mm(avail(*surf, 0)),
                       mm(avail(*surf, 1)),
                       hemi->label,
                       mm(r)));
    }
  }
  return diags.size() == before;
}

std::vector<double> consume_critical_dim(const Primitive& self,
                                         std::vector<double> available,
                                         const Primitive& other,
                                         const std::vector<double>& other_available) {
  if (available.empty()) return available;
  switch (self.type) {
    case PT::kEdge:
      if (other.type == PT::kClip) available[0] -= other.shape.width;
      break;
    case PT::kRod:
    case PT::kTube:
      if (other.type == PT::kHook || other.type == PT::kRing) {
        available[0] -= 2 * other.shape.thickness;
      } else if (other.type == PT::kClip) {
        available[0] -= other.shape.width;
      } else if (other.type == PT::kTube && !other_available.empty() &&
                 available[0] - other_available[0] > 0) {
        available[0] -= other_available[0];
      }
      break;
    case PT::kSurface:
      if (other.type == PT::kSurface && other_available.size() == 2 &&
          available[0] - other_available[0] > 0 && available[1] - other_available[1] > 0) {
        available[0] -= other_available[0];
        available[1] -= other_available[1];
      } else if (other.type == PT::kHemisphere) {
        available[0] -= 2 * other.shape.radius;
        available[1] -= 2 * other.shape.radius;
      }
      break;
    default:
      break;
  }
  return available;
}

}  // namespace fabkit::hacks

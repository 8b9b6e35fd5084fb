#include "fabkit/hacks/primitive.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "fabkit/core/text.h"
#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {
namespace {

// Largest size we accept anywhere: 100 m. Anything bigger is a unit mistake.
constexpr double kMaxSizeMm = 1e5;

}  // namespace

std::string_view to_string(PrimitiveType t) {
  switch (t) {
    case PrimitiveType::kRod:
      return "rod";
    case PrimitiveType::kHook:
      return "hook";
    case PrimitiveType::kRing:
      return "ring";
    case PrimitiveType::kClip:
      return "clip";
    case PrimitiveType::kTube:
      return "tube";
    case PrimitiveType::kEdge:
      return "edge";
    case PrimitiveType::kSurface:
      return "surface";
    case PrimitiveType::kHemisphere:
      return "hemisphere";
  }
  return "rod";
}

std::optional<PrimitiveType> primitive_type_from_string(std::string_view s) {
  const std::string l = ascii_lower(s);
  if (l == "rod") return PrimitiveType::kRod;
  if (l == "hook") return PrimitiveType::kHook;
  if (l == "ring" || l == "hole") return PrimitiveType::kRing;
  if (l == "clip") return PrimitiveType::kClip;
  if (l == "tube") return PrimitiveType::kTube;
  if (l == "edge") return PrimitiveType::kEdge;
  if (l == "surface" || l == "surf") return PrimitiveType::kSurface;
  if (l == "hemisphere" || l == "hemi") return PrimitiveType::kHemisphere;
  return std::nullopt;
}

std::string_view to_string(ConnectorKind k) {
  switch (k) {
    case ConnectorKind::kRod:
      return "Rod";
    case ConnectorKind::kRodCenterline:
      return "RodCtl";
    case ConnectorKind::kHook:
      return "Hook";
    case ConnectorKind::kHookFlex:
      return "HookFlex";
    case ConnectorKind::kRing:
      return "Ring";
    case ConnectorKind::kRingFlex:
      return "RingFlex";
    case ConnectorKind::kRingCenterline:
      return "RingCtl";
    case ConnectorKind::kTube:
      return "Tube";
    case ConnectorKind::kTubeCenterline:
      return "TubeCtl";
    case ConnectorKind::kClip:
      return "Clip";
    case ConnectorKind::kEdge:
      return "Edge";
    case ConnectorKind::kSurface:
      return "Surface";
    case ConnectorKind::kHemisphere:
      return "Hemisphere";
  }
  return "Rod";
}

int connector_dof(ConnectorKind k) {
  switch (k) {
    case ConnectorKind::kRodCenterline:
    case ConnectorKind::kHook:
    case ConnectorKind::kRing:
    case ConnectorKind::kClip:
    case ConnectorKind::kEdge:
      return 1;
    case ConnectorKind::kHookFlex:
    case ConnectorKind::kRingFlex:
    case ConnectorKind::kRingCenterline:
    case ConnectorKind::kTube:
    case ConnectorKind::kTubeCenterline:
      return 2;
    case ConnectorKind::kRod:
    case ConnectorKind::kSurface:
    case ConnectorKind::kHemisphere:
      return 3;
  }
  return 0;
}

std::string_view to_string(ParamTag t) {
  switch (t) {
    case ParamTag::kUnbounded:
      return "UNBOUNDED";
    case ParamTag::kBoundedAndClamped:
      return "BOUNDED_AND_CLAMPED";
    case ParamTag::kBoundedAndOpen:
      return "BOUNDED_AND_OPEN";
  }
  return "UNBOUNDED";
}

std::optional<ParamTag> param_tag_from_string(std::string_view s) {
  for (ParamTag t :
       {ParamTag::kUnbounded, ParamTag::kBoundedAndClamped, ParamTag::kBoundedAndOpen}) {
    if (to_string(t) == s) return t;
  }
  return std::nullopt;
}

std::vector<std::string_view> shape_field_names(PrimitiveType t) {
  switch (t) {
    case PrimitiveType::kRod:
      return {"radius", "length"};
    case PrimitiveType::kHook:
      return {"arc_angle", "arc_radius", "thickness"};
    case PrimitiveType::kRing:
      return {"arc_radius", "thickness"};
    case PrimitiveType::kClip:
      return {"width", "height", "dist", "open_gap", "thickness"};
    case PrimitiveType::kTube:
      return {"inner_radius", "thickness", "length"};
    case PrimitiveType::kEdge:
      return {"width", "length", "height"};
    case PrimitiveType::kSurface:
      return {"width", "length"};
    case PrimitiveType::kHemisphere:
      return {"radius"};
  }
  return {};
}

double* shape_field(PrimitiveShape& s, std::string_view name) {
  if (name == "radius") return &s.radius;
  if (name == "length") return &s.length;
  if (name == "arc_radius") return &s.arc_radius;
  if (name == "arc_angle") return &s.arc_angle;
  if (name == "thickness") return &s.thickness;
  if (name == "inner_radius") return &s.inner_radius;
  if (name == "width") return &s.width;
  if (name == "height") return &s.height;
  if (name == "dist") return &s.dist;
  if (name == "open_gap") return &s.open_gap;
  return nullptr;
}

double shape_field_value(const PrimitiveShape& s, std::string_view name) {
  return *shape_field(const_cast<PrimitiveShape&>(s), name);
}

Primitive Primitive::make(std::string name,
                          PrimitiveType type,
                          const PrimitiveShape& shape,
                          const Frame& frame) {
  Primitive p;
  p.name = std::move(name);
  p.type = type;
  p.shape = shape;
  p.frame = frame;
  // A surface is bounded by its own edges; everything else runs off its ends by default.
  p.is_open = type != PrimitiveType::kSurface;
  p.open_for_connect = type != PrimitiveType::kRing;
  return p;
}

ConnectorKind Primitive::connector_kind() const {
  switch (type) {
    case PrimitiveType::kRod:
      return centerline ? ConnectorKind::kRodCenterline : ConnectorKind::kRod;
    case PrimitiveType::kHook:
      return flex ? ConnectorKind::kHookFlex : ConnectorKind::kHook;
    case PrimitiveType::kRing:
      if (centerline) return ConnectorKind::kRingCenterline;
      return flex ? ConnectorKind::kRingFlex : ConnectorKind::kRing;
    case PrimitiveType::kClip:
      return ConnectorKind::kClip;
    case PrimitiveType::kTube:
      return centerline ? ConnectorKind::kTubeCenterline : ConnectorKind::kTube;
    case PrimitiveType::kEdge:
      return ConnectorKind::kEdge;
    case PrimitiveType::kSurface:
      return ConnectorKind::kSurface;
    case PrimitiveType::kHemisphere:
      return ConnectorKind::kHemisphere;
  }
  return ConnectorKind::kRod;
}

bool Primitive::single_connection() const {
  return type == PrimitiveType::kClip || type == PrimitiveType::kHemisphere;
}

bool Primitive::closed_for_connect() const {
  switch (type) {
    case PrimitiveType::kRing:
      return true;
    case PrimitiveType::kRod:
    case PrimitiveType::kHook:
      return !open_for_connect;
    case PrimitiveType::kTube:
      return !is_open;
    default:
      return false;
  }
}

std::vector<ParamSpec> Primitive::connector_params() const {
  // Only rods, hooks, tubes and surfaces carry an is_open flag; a closed one clamps its
  // bounded parameters (reference §2.3 has_bounds).
  const bool has_flag = type == PrimitiveType::kRod || type == PrimitiveType::kHook ||
                        type == PrimitiveType::kTube || type == PrimitiveType::kSurface;
  const ParamTag bounded =
      (has_flag && !is_open) ? ParamTag::kBoundedAndClamped : ParamTag::kBoundedAndOpen;
  auto frac = [&](std::string n) {
    return ParamSpec{std::move(n), 0.5, 0.0, 1.0, bounded, /*critical_dim=*/true};
  };
  auto angle = [&](std::string n, double init, double lo, double hi) {
    return ParamSpec{std::move(n), init, lo, hi, bounded};
  };
  auto spin = [](std::string n, double init) {
    return ParamSpec{std::move(n), init, 0.0, 360.0, ParamTag::kUnbounded};
  };
  const std::array<double, 2> phi = phi_range.value_or(std::array<double, 2>{45.0, 135.0});
  auto hook_theta = [&] {
    const std::array<double, 2> r =
        theta_range.value_or(std::array<double, 2>{0.0, shape.arc_angle});
    if (shape.arc_angle >= 360.0 && !theta_range) return spin("theta", shape.arc_angle / 2);
    return angle("theta", shape.arc_angle / 2, r[0], r[1]);
  };

  std::vector<ParamSpec> out = [&]() -> std::vector<ParamSpec> {
    switch (connector_kind()) {
      case ConnectorKind::kRod:
        // ψ: where around the rod the contact is (the reference fixes it at 0, one line).
        return {frac("t"), angle("phi", 90, phi[0], phi[1]), spin("psi", 0)};
      case ConnectorKind::kRodCenterline:
        return {frac("t")};
      case ConnectorKind::kHook:
        return {hook_theta()};
      case ConnectorKind::kHookFlex:
        return {hook_theta(), angle("phi", 90, phi[0], phi[1])};
      case ConnectorKind::kRing:
        return {spin("theta", 180)};
      case ConnectorKind::kRingFlex: {
        const std::array<double, 2> rp = phi_range.value_or(std::array<double, 2>{30.0, 150.0});
        return {spin("theta", 180), angle("phi", 90, rp[0], rp[1])};
      }
      case ConnectorKind::kRingCenterline:
        return {spin("v0", 0), spin("v1", 180)};
      case ConnectorKind::kTube:
      case ConnectorKind::kTubeCenterline:
        return {frac("t"), spin("theta", 180)};
      case ConnectorKind::kClip: {
        ParamSpec t = frac("t");
        t.critical_dim = false;
        t.fixed_under_physics = true;
        return {t};
      }
      case ConnectorKind::kEdge:
        return {frac("t")};
      case ConnectorKind::kSurface:
        return {frac("t1"), frac("t2"), spin("s", 0)};
      case ConnectorKind::kHemisphere:
        return {angle("theta", 180, 90, 270), angle("phi", 180, 90, 270), spin("s", 0)};
    }
    return {};
  }();
  // Which bounds a connection can run out of: sliding along an open rod, tube, edge or hook
  // arc (per end), rolling off a hemisphere's rim. Clip jaws are pinned under physics.
  for (ParamSpec& p : out) {
    const bool tilt = p.name == "phi" && type != PrimitiveType::kHemisphere;
    if (p.tag != ParamTag::kBoundedAndOpen || tilt) {
      continue;
    }
    if (type == PrimitiveType::kHemisphere || type == PrimitiveType::kClip) {
      p.open_at_lo = p.open_at_hi = true;
    } else {
      p.open_at_lo = open_ends[0];
      p.open_at_hi = open_ends[1];
    }
  }
  return out;
}

std::vector<double> Primitive::critical_dim() const {
  switch (type) {
    case PrimitiveType::kRod:
    case PrimitiveType::kTube:
    case PrimitiveType::kEdge:
      return {shape.length};
    case PrimitiveType::kRing:
      return {shape.arc_radius};
    case PrimitiveType::kSurface:
      return {shape.width, shape.length};
    default:
      return {};
  }
}

std::vector<double> Primitive::connector_critical_dim() const {
  switch (type) {
    case PrimitiveType::kRod:
      return {shape.radius};
    case PrimitiveType::kHook:
    case PrimitiveType::kRing:
      return {shape.thickness};
    case PrimitiveType::kTube:
      return {shape.length / 2};
    case PrimitiveType::kClip:
      return {shape.width / 2};
    case PrimitiveType::kHemisphere:
      return {shape.radius, shape.radius};
    case PrimitiveType::kSurface:
      return {shape.width / 2, shape.length / 2};
    case PrimitiveType::kEdge:
      return {};
  }
  return {};
}

std::string Primitive::describe() const {
  std::string fields;
  for (std::string_view f : shape_field_names(type)) {
    if (!fields.empty()) fields += ", ";
    std::string label(f);
    std::replace(label.begin(), label.end(), '_', ' ');
    const bool is_angle = f == "arc_angle";
    fields += fmt::format("{} {:g}{}", label, shape_field_value(shape, f), is_angle ? "°" : " mm");
  }
  std::string variant;
  if (flex) variant += ", flexible";
  if (centerline) variant += ", centre line";
  if (closed_for_connect() && type != PrimitiveType::kRing) variant += ", closed";
  return fmt::format("{} ({}{})", to_string(type), fields, variant);
}

std::optional<std::string> shape_field_problem(PrimitiveType type,
                                               std::string_view field,
                                               double v,
                                               std::string_view who) {
  if (!std::isfinite(v)) {
    return fmt::format("{}: {} {} is not a finite number", who, to_string(type), field);
  }
  if (field == "arc_angle") {
    if (v <= 0 || v > 360) {
      return fmt::format("{}: hook arc angle {:g}° must be in (0, 360]", who, v);
    }
    return std::nullopt;
  }
  if (v <= 0) {
    return fmt::format("{}: {} {} {:g} mm must be positive", who, to_string(type), field, v);
  }
  if (v > kMaxSizeMm) {
    return fmt::format("{}: {} {} {:g} mm is absurd (more than {:g} m); sizes are in mm",
                       who,
                       to_string(type),
                       field,
                       v,
                       kMaxSizeMm / 1000);
  }
  return std::nullopt;
}

void Primitive::validate(std::string_view who,
                         Diagnostics& diags,
                         const SourceLocation& where) const {
  for (std::string_view f : shape_field_names(type)) {
    if (auto problem = shape_field_problem(type, f, shape_field_value(shape, f), who)) {
      diags.error(codes::kInvalidValue, std::move(*problem), where);
    }
  }
  if ((type == PrimitiveType::kHook || type == PrimitiveType::kRing) &&
      shape.thickness >= shape.arc_radius && shape.thickness > 0) {
    diags.error(
        codes::kInvalidValue,
        fmt::format("{}: {} wire radius {:g} mm must be smaller than its arc radius {:g} mm",
                    who,
                    to_string(type),
                    shape.thickness,
                    shape.arc_radius),
        where);
  }
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(frame.pos[i]) || !std::isfinite(frame.rot[i])) {
      diags.error(
          codes::kInvalidValue, fmt::format("{}: frame has a non-finite value", who), where);
      break;
    }
  }
  for (const auto& range : {theta_range, phi_range}) {
    if (range &&
        (!std::isfinite((*range)[0]) || !std::isfinite((*range)[1]) || (*range)[0] > (*range)[1])) {
      diags.error(
          codes::kInvalidValue,
          fmt::format(
              "{}: angle range [{:g}, {:g}] is not an interval", who, (*range)[0], (*range)[1]),
          where);
    }
  }
}

}  // namespace fabkit::hacks

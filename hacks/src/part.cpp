#include "fabkit/hacks/part.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "convex_pieces.h"
#include "fabkit/core/text.h"

namespace fabkit::hacks {
namespace {

// Surfaces are drawn as thin slabs; the reference renders them as edges of this height.
constexpr double kSurfaceThickness = 0.1;

// The paper calls rings "holes": "hole1" <-> "ring1", "hole" <-> "ring".
std::optional<std::string> hole_ring_alias(std::string_view name) {
  if (name.starts_with("hole")) return "ring" + std::string(name.substr(4));
  if (name.starts_with("ring")) return "hole" + std::string(name.substr(4));
  return std::nullopt;
}

// Enough arc segments for a smooth hook, fewer for short arcs.
int arc_segments(double angle_deg) {
  return std::max(6, static_cast<int>(std::ceil(48.0 * std::min(angle_deg, 360.0) / 360.0)));
}

// Two jaw plates forming a V (reference §2.2): the jaw runs along local z over `height` (the
// ClipMCF slides along z), the plates span `width` along y and face each other across x. The
// gap is open_gap at the mouth (z = -height/2) and dist at the hinge end (z = +height/2).
TriangleMesh clip_local_mesh(const PrimitiveShape& s) {
  const double t = s.thickness;
  const double tilt = std::atan((s.dist - s.open_gap) / 2.0 / s.height);  // radians
  const double plate_length = s.height / std::cos(tilt);
  const double mid = (s.dist + s.open_gap) / 4.0;  // mean half-gap
  const TriangleMesh plate = shapes::box(Vec3(t, s.width, plate_length));
  TriangleMesh m;
  for (double side : {1.0, -1.0}) {
    m.append(plate.transformed(translation(side * (mid + t / 2), 0.0, 0.0) *
                               rot_y(side * tilt * kRadToDeg)));
  }
  return m;
}

// A primitive whose used shape fields are not finite and positive has no sensible mesh.
bool drawable(const Primitive& p) {
  for (std::string_view f : shape_field_names(p.type)) {
    const double v = shape_field_value(p.shape, f);
    if (!std::isfinite(v) || v <= 0) return false;
  }
  return true;
}

}  // namespace

std::string_view to_string(PartCategory c) {
  switch (c) {
    case PartCategory::kEnvironment:
      return "environment";
    case PartCategory::kHack:
      return "hack";
    case PartCategory::kBoth:
      return "both";
    case PartCategory::kOther:
      return "other";
  }
  return "other";
}

std::optional<PartCategory> category_named(std::string_view name) {
  const std::string lower = ascii_lower(name);
  for (PartCategory c : {PartCategory::kEnvironment,
                         PartCategory::kHack,
                         PartCategory::kBoth,
                         PartCategory::kOther}) {
    if (lower == to_string(c)) return c;
  }
  return std::nullopt;
}

PrimitiveId Part::find_primitive(std::string_view name) const {
  for (std::size_t i = 0; i < primitives.size(); ++i) {
    if (primitives[i].name == name) return PrimitiveId{static_cast<int>(i)};
  }
  if (const auto alias = hole_ring_alias(name)) {
    for (std::size_t i = 0; i < primitives.size(); ++i) {
      if (primitives[i].name == *alias) return PrimitiveId{static_cast<int>(i)};
    }
  }
  return PrimitiveId{};
}

std::string Part::primitive_list() const {
  std::string out;
  for (const Primitive& p : primitives) {
    if (!out.empty()) out += ", ";
    out += p.name;
  }
  return out;
}

TriangleMesh primitive_mesh(const Primitive& p) {
  if (!drawable(p)) return {};
  const PrimitiveShape& s = p.shape;
  TriangleMesh local;
  switch (p.type) {
    case PrimitiveType::kRod:
      local = shapes::cylinder(s.radius, s.length);
      break;
    case PrimitiveType::kHook:
      local = shapes::torus_arc(s.arc_radius, s.thickness, s.arc_angle, arc_segments(s.arc_angle));
      break;
    case PrimitiveType::kRing:
      local = shapes::torus_arc(s.arc_radius, s.thickness, 360.0, arc_segments(360.0));
      break;
    case PrimitiveType::kTube:
      local = shapes::tube(s.inner_radius, s.inner_radius + s.thickness, s.length);
      break;
    case PrimitiveType::kEdge:
      local = shapes::box(Vec3(s.length, s.width, s.height));
      break;
    case PrimitiveType::kSurface:
      local = shapes::box(Vec3(s.length, s.width, kSurfaceThickness));
      break;
    case PrimitiveType::kHemisphere:
      local = shapes::hemisphere(s.radius);
      break;
    case PrimitiveType::kClip:
      local = clip_local_mesh(s);
      break;
  }
  local.transform(p.frame.matrix());
  return local;
}

std::vector<TriangleMesh> primitive_pieces(const Primitive& p) {
  if (!drawable(p)) return {};
  const PrimitiveShape& s = p.shape;
  std::vector<TriangleMesh> pieces;
  switch (p.type) {
    case PrimitiveType::kHook:
      pieces = detail::arc_pieces(s.arc_radius, s.thickness, s.arc_angle);
      break;
    case PrimitiveType::kRing:
      pieces = detail::arc_pieces(s.arc_radius, s.thickness, 360.0);
      break;
    case PrimitiveType::kTube:
      pieces = detail::tube_pieces(s.inner_radius, s.inner_radius + s.thickness, s.length);
      break;
    case PrimitiveType::kClip: {
      // The two jaw plates are boxes; clip_local_mesh appends them one after the other.
      const TriangleMesh both = clip_local_mesh(s);
      const std::size_t half = both.vertices.size() / 2;
      for (int k = 0; k < 2; ++k) {
        TriangleMesh plate;
        plate.vertices.assign(both.vertices.begin() + static_cast<std::ptrdiff_t>(k * half),
                              both.vertices.begin() + static_cast<std::ptrdiff_t>((k + 1) * half));
        for (const Eigen::Vector3i& f : both.faces) {
          if (static_cast<std::size_t>(f.minCoeff()) / half == static_cast<std::size_t>(k)) {
            plate.faces.push_back(f.array() - static_cast<int>(k * half));
          }
        }
        pieces.push_back(std::move(plate));
      }
      break;
    }
    case PrimitiveType::kRod:
    case PrimitiveType::kEdge:
    case PrimitiveType::kSurface:
    case PrimitiveType::kHemisphere: {
      // Convex already (the mesh, in part coordinates).
      return {primitive_mesh(p)};
    }
  }
  detail::transform_pieces(pieces, p.frame.matrix());
  return pieces;
}

std::vector<std::vector<collision::Arc>> primitive_piece_rims(const Primitive& p) {
  if (!drawable(p)) return {};
  const PrimitiveShape& s = p.shape;
  std::vector<std::vector<collision::Arc>> rims;
  switch (p.type) {
    case PrimitiveType::kRod:
      rims.push_back(detail::cylinder_rims(s.radius, s.length));
      break;
    case PrimitiveType::kTube:
      rims = detail::tube_piece_rims(s.inner_radius, s.inner_radius + s.thickness, s.length);
      break;
    case PrimitiveType::kHook:
    case PrimitiveType::kRing:
    case PrimitiveType::kEdge:
    case PrimitiveType::kSurface:
    case PrimitiveType::kHemisphere:
    case PrimitiveType::kClip:
      return {};
  }
  detail::transform_rims(rims, p.frame.matrix());
  return rims;
}

void add_primitive_pieces(Part& part, int index) {
  const Primitive& primitive = part.primitives.at(static_cast<std::size_t>(index));
  std::vector<std::vector<collision::Arc>> rims = primitive_piece_rims(primitive);
  std::vector<TriangleMesh> pieces = primitive_pieces(primitive);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    part.collision_rims.resize(part.collision_pieces.size());
    part.collision_pieces.push_back(std::move(pieces[k]));
    part.collision_tags.push_back(index);
    part.collision_rims.push_back(k < rims.size() ? std::move(rims[k])
                                                  : std::vector<collision::Arc>{});
  }
}

Part make_primitive_part(std::vector<Primitive> primitives) {
  Part part;
  part.type_name = "Environment";
  part.description = "loose primitives";
  part.category = PartCategory::kEnvironment;
  part.primitives = std::move(primitives);
  part.mass = 0;
  for (std::size_t i = 0; i < part.primitives.size(); ++i) {
    part.mesh.append(primitive_mesh(part.primitives[i]));
    add_primitive_pieces(part, static_cast<int>(i));
  }
  part.center_of_mass = part.mesh.empty() ? Vec3::Zero() : part.mesh.centroid();
  return part;
}

}  // namespace fabkit::hacks

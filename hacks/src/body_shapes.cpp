#include "fabkit/hacks/body_shapes.h"

#include <fmt/format.h>

#include "convex_pieces.h"
#include "fabkit/core/text.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "fabkit/hacks/part.h"
#include "fabkit/hacks/primitive_spec.h"

namespace fabkit::hacks {
namespace {

constexpr NumberRange kSize{0, 1e5, "mm", true};
constexpr NumberRange kCoordinate{-kMaxCoordinateMm, kMaxCoordinateMm, "mm"};

struct ShapeReader {
  YamlReader& in;
  std::string who;
  // Where the shapes' convex pieces go (contact queries), if anywhere.
  std::vector<TriangleMesh>* pieces = nullptr;
  void piece(const TriangleMesh& m) {
    if (pieces) pieces->push_back(m);
  }

  std::optional<int> segments(const YAML::Node& n, const char* key, int fallback) {
    const YAML::Node s = n[key];
    if (!s) return fallback;
    auto v = in.integer(s, fmt::format("{} {}", who, key), 3, 512);
    if (!v) return std::nullopt;
    return static_cast<int>(*v);
  }
  Mat4 frame_of(const YAML::Node& n, bool& ok) {
    const YAML::Node f = n["frame"];
    if (!f) return Mat4::Identity();
    auto frame = in.frame(f, fmt::format("{} frame", who));
    ok = ok && frame.has_value();
    return frame ? frame->matrix() : Mat4::Identity();
  }
  std::optional<double> size(const YAML::Node& n, const char* key) {
    const YAML::Node v = n[key];
    if (!v) {
      in.error(codes::kMalformedInput, fmt::format("{} needs '{}'", who, key), in.at(n));
      return std::nullopt;
    }
    return in.number(v, fmt::format("{} {}", who, key), kSize);
  }
  std::optional<Vec3> point(const YAML::Node& n, const char* key) {
    const YAML::Node v = n[key];
    if (!v) {
      in.error(codes::kMalformedInput, fmt::format("{} needs '{}'", who, key), in.at(n));
      return std::nullopt;
    }
    return in.vec3(v, fmt::format("{} {}", who, key), kCoordinate);
  }

  // Axis-aligned box between two corners.
  std::optional<TriangleMesh> box(const YAML::Node& n) {
    if (n["size"]) {
      in.check_keys(n, {"size", "frame"}, who);
      auto s = in.vec3(n["size"], fmt::format("{} size", who), kSize);
      bool ok = s.has_value();
      const Mat4 m = frame_of(n, ok);
      if (!ok) return std::nullopt;
      TriangleMesh out = shapes::box(*s).transformed(m);
      piece(out);
      return out;
    }
    in.check_keys(n, {"min", "max"}, who);
    auto lo = point(n, "min");
    auto hi = point(n, "max");
    if (!lo || !hi) return std::nullopt;
    if (((*hi - *lo).array() <= 0).any()) {
      in.error(codes::kInvalidValue,
               fmt::format("{}: max must exceed min in x, y and z", who),
               in.at(n));
      return std::nullopt;
    }
    const Vec3 c = 0.5 * (*lo + *hi);
    TriangleMesh out = shapes::box(*hi - *lo).transformed(translation(c.x(), c.y(), c.z()));
    piece(out);
    return out;
  }

  std::optional<TriangleMesh> cylinder(const YAML::Node& n) {
    in.check_keys(n, {"from", "to", "radius", "segments"}, who);
    auto a = point(n, "from");
    auto b = point(n, "to");
    auto r = size(n, "radius");
    auto seg = segments(n, "segments", 16);
    if (!a || !b || !r || !seg) return std::nullopt;
    const Vec3 d = *b - *a;
    if (d.norm() <= 0) {
      in.error(
          codes::kInvalidValue, fmt::format("{}: from and to are the same point", who), in.at(n));
      return std::nullopt;
    }
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() =
        Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).normalized().toRotationMatrix();
    m.topRightCorner<3, 1>() = 0.5 * (*a + *b);
    TriangleMesh out = shapes::cylinder(*r, d.norm(), *seg).transformed(m);
    piece(out);
    return out;
  }

  // Open-topped box (basket, tray, caddy): a floor of `floor` thickness and four walls.
  std::optional<TriangleMesh> open_box(const YAML::Node& n) {
    in.check_keys(n, {"min", "max", "wall", "floor"}, who);
    auto lo = point(n, "min");
    auto hi = point(n, "max");
    auto wall = size(n, "wall");
    auto floor = size(n, "floor");
    if (!lo || !hi || !wall || !floor) return std::nullopt;
    const Vec3 span = *hi - *lo;
    if ((span.array() <= 0).any() || 2 * *wall >= std::min(span.x(), span.y()) ||
        *floor >= span.z()) {
      in.error(codes::kInvalidValue,
               fmt::format(
                   "{}: walls {:g} mm and floor {:g} mm do not fit in the box", who, *wall, *floor),
               in.at(n));
      return std::nullopt;
    }
    auto between = [&](const Vec3& a, const Vec3& b) {
      const Vec3 c = 0.5 * (a + b);
      TriangleMesh out = shapes::box(b - a).transformed(translation(c.x(), c.y(), c.z()));
      piece(out);
      return out;
    };
    const Vec3& l = *lo;
    const Vec3& h = *hi;
    const double w = *wall;
    const double z0 = l.z() + *floor;
    TriangleMesh m = between(l, Vec3(h.x(), h.y(), z0));
    m.append(between(Vec3(l.x(), l.y(), z0), Vec3(l.x() + w, h.y(), h.z())));
    m.append(between(Vec3(h.x() - w, l.y(), z0), Vec3(h.x(), h.y(), h.z())));
    m.append(between(Vec3(l.x() + w, l.y(), z0), Vec3(h.x() - w, l.y() + w, h.z())));
    m.append(between(Vec3(l.x() + w, h.y() - w, z0), Vec3(h.x() - w, h.y(), h.z())));
    return m;
  }

  std::optional<TriangleMesh> sphere(const YAML::Node& n) {
    in.check_keys(n, {"radius", "segments", "frame"}, who);
    auto r = size(n, "radius");
    auto seg = segments(n, "segments", 16);
    bool ok = r && seg;
    const Mat4 m = frame_of(n, ok);
    if (!ok) return std::nullopt;
    TriangleMesh out = shapes::sphere(*r, *seg).transformed(m);
    piece(out);
    return out;
  }

  std::optional<TriangleMesh> torus_arc(const YAML::Node& n) {
    in.check_keys(
        n, {"arc_radius", "wire_radius", "angle", "segments", "wire_segments", "frame"}, who);
    auto arc = size(n, "arc_radius");
    auto wire = size(n, "wire_radius");
    std::optional<double> angle;
    if (const YAML::Node a = n["angle"]) {
      angle = in.number(a, fmt::format("{} angle", who), {0, 360, "degrees", true});
    } else {
      in.error(codes::kMalformedInput, fmt::format("{} needs 'angle'", who), in.at(n));
    }
    auto seg = segments(n, "segments", 32);
    auto wseg = segments(n, "wire_segments", 10);
    bool ok = arc && wire && angle && seg && wseg;
    const Mat4 m = frame_of(n, ok);
    if (!ok) return std::nullopt;
    if (*wire >= *arc) {
      in.error(codes::kInvalidValue,
               fmt::format("{}: wire radius {:g} mm must be smaller than the arc radius {:g} mm",
                           who,
                           *wire,
                           *arc),
               in.at(n));
      return std::nullopt;
    }
    if (pieces) {
      std::vector<TriangleMesh> arc_parts = detail::arc_pieces(*arc, *wire, *angle);
      detail::transform_pieces(arc_parts, m);
      for (const TriangleMesh& a : arc_parts) piece(a);
    }
    return shapes::torus_arc(*arc, *wire, *angle, *seg, *wseg).transformed(m);
  }

  std::optional<TriangleMesh> primitive(const YAML::Node& n) {
    auto p = read_primitive_spec(in, n, "", who);
    if (!p) return std::nullopt;
    for (const TriangleMesh& m : primitive_pieces(*p)) piece(m);
    return primitive_mesh(*p);
  }
};

}  // namespace

std::optional<TriangleMesh> read_body(YamlReader& in,
                                      const YAML::Node& body,
                                      std::string_view owner,
                                      std::vector<TriangleMesh>* pieces) {
  if (!in.is_list(body, fmt::format("body of part {}", owner))) return std::nullopt;
  const int before = in.errors();
  TriangleMesh mesh;
  int index = 0;
  for (const YAML::Node& item : body) {
    ++index;
    if (!item.IsMap() || item.size() != 1) {
      in.error(codes::kMalformedInput,
               fmt::format("body item {} of part {} must be one shape, like {{box: {{min: [...], "
                           "max: [...]}}}}",
                           index,
                           owner),
               in.at(item));
      continue;
    }
    const auto kv = *item.begin();
    const std::string kind = kv.first.Scalar();
    ShapeReader r{in, fmt::format("{} body {} ({})", owner, index, kind), pieces};
    std::optional<TriangleMesh> m;
    if (!kv.second.IsMap()) {
      in.error(
          codes::kMalformedInput, fmt::format("{} must be a mapping", r.who), in.at(kv.second));
      continue;
    }
    if (kind == "box") {
      m = r.box(kv.second);
    } else if (kind == "cylinder") {
      m = r.cylinder(kv.second);
    } else if (kind == "open_box") {
      m = r.open_box(kv.second);
    } else if (kind == "sphere") {
      m = r.sphere(kv.second);
    } else if (kind == "torus_arc") {
      m = r.torus_arc(kv.second);
    } else if (kind == "primitive") {
      m = r.primitive(kv.second);
    } else {
      const std::vector<std::string> kinds{
          "box", "cylinder", "open_box", "sphere", "torus_arc", "primitive"};
      in.error(codes::kUnknownName,
               fmt::format("unknown body shape '{}' in part {}{} (shapes: box, cylinder, open_box, "
                           "sphere, torus_arc, primitive)",
                           excerpt(kind, 40),
                           owner,
                           did_you_mean(kind, kinds)),
               in.at(kv.first));
      continue;
    }
    if (m) mesh.append(*m);
  }
  if (in.errors() > before) return std::nullopt;
  return mesh;
}

}  // namespace fabkit::hacks

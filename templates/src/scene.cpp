#include "fabkit/templates/scene.h"

#include <algorithm>
#include <cmath>

namespace fabkit::templates {

namespace {

TriangleMesh box_at(const Vec3& lo, const Vec3& hi) {
  TriangleMesh m = shapes::box(hi - lo);
  m.transform(
      translation(0.5 * (lo.x() + hi.x()), 0.5 * (lo.y() + hi.y()), 0.5 * (lo.z() + hi.z())));
  return m;
}

// A z-axis shape turned onto `axis` and moved to `center`.
TriangleMesh along(TriangleMesh m, int axis, const Vec3& center) {
  Mat4 r = Mat4::Identity();
  if (axis == 0) r = rot_y(90.0);
  if (axis == 1) r = rot_x(-90.0);
  m.transform(translation(center.x(), center.y(), center.z()) * r);
  return m;
}

int longest_axis(const Vec3& s) {
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (s[i] > s[k]) k = i;
  }
  return k;
}

int shortest_axis(const Vec3& s) {
  int k = 0;
  for (int i = 1; i < 3; ++i) {
    if (s[i] < s[k]) k = i;
  }
  return k;
}

std::array<float, 4> material_color(const Item* it) {
  if (!it) return {0.7f, 0.7f, 0.7f, 1.0f};
  const std::string& m = it->material;
  auto has = [&](const char* w) { return m.find(w) != std::string::npos; };
  if (has("oak")) return {0.72f, 0.53f, 0.33f, 1.0f};
  if (has("maple") || has("birch")) return {0.88f, 0.78f, 0.6f, 1.0f};
  if (has("MDF") || has("hardboard")) return {0.62f, 0.5f, 0.38f, 1.0f};
  if (has("melamine")) return {0.95f, 0.95f, 0.93f, 1.0f};
  if (has("cedar")) return {0.7f, 0.42f, 0.28f, 1.0f};
  if (has("OSB")) return {0.8f, 0.67f, 0.42f, 1.0f};
  if (has("steel") || has("iron") || has("zinc") || has("alumin"))
    return {0.55f, 0.57f, 0.6f, 1.0f};
  if (has("rubber")) return {0.15f, 0.15f, 0.15f, 1.0f};
  if (has("acrylic")) return {0.8f, 0.9f, 0.95f, 0.5f};
  return {0.85f, 0.72f, 0.52f, 1.0f};  // pine, poplar, spruce
}

}  // namespace

TriangleMesh part_mesh(const Template& t, const PlacedPart& part, const Item* item) {
  const Box& b = part.box;
  const std::string kind = item ? item->mesh : "box";
  if (kind == "cylinder" || kind == "tube") {
    const int a = longest_axis(b.size);
    const double r = 0.5 * std::min(b.size[(a + 1) % 3], b.size[(a + 2) % 3]);
    return along(kind == "tube" ? shapes::tube(0.8 * r, r, b.size[a], 20)
                                : shapes::cylinder(r, b.size[a], 16),
                 a,
                 b.center);
  }
  if (kind == "wheel") {
    const int a = shortest_axis(b.size);
    const double r = 0.5 * std::min(b.size[(a + 1) % 3], b.size[(a + 2) % 3]);
    return along(shapes::cylinder(r, b.size[a], 32), a, b.center);
  }
  if (kind == "caster") {
    // Mount plate on top, a fork below it and the wheel in the fork (axle along x or y).
    const int up = longest_axis(b.size);
    if (up == 2) {
      const Vec3 lo = b.min(), hi = b.max();
      const double plate = std::min(6.0, 0.1 * b.size.z());
      TriangleMesh m = box_at(Vec3(lo.x(), lo.y(), hi.z() - plate), hi);
      const double r = 0.35 * b.size.z();
      m.append(box_at(Vec3(b.center.x() - 0.3 * b.size.x(), b.center.y() - 4, lo.z() + r),
                      Vec3(b.center.x() + 0.3 * b.size.x(), b.center.y() + 4, hi.z() - plate)));
      m.append(along(shapes::cylinder(r, 0.4 * b.size.y(), 24),
                     1,
                     Vec3(b.center.x(), b.center.y(), lo.z() + r)));
      return m;
    }
  }
  if (kind == "l-bracket") {
    // Two plates on the faces of the box that touch principal parts.
    std::vector<std::pair<int, int>> faces;  // (axis, side −1/+1)
    for (const PlacedPart& other : t.placed_parts()) {
      if (other.role != PartRole::kPrincipal) continue;
      for (int k = 0; k < 3 && faces.size() < 2; ++k) {
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        if (b.overlap(other.box, u) <= 0 || b.overlap(other.box, v) <= 0) continue;
        for (int side : {-1, 1}) {
          const double face = side < 0 ? b.min()[k] : b.max()[k];
          const double touch = side < 0 ? other.box.max()[k] : other.box.min()[k];
          const bool same_axis =
              std::any_of(faces.begin(), faces.end(), [&](auto f) { return f.first == k; });
          if (std::abs(face - touch) < 0.6 && !same_axis) faces.emplace_back(k, side);
        }
      }
    }
    if (faces.size() == 2) {
      TriangleMesh m;
      const double thick = 3;
      for (const auto& [k, side] : faces) {
        Vec3 lo = b.min(), hi = b.max();
        if (side < 0)
          hi[k] = lo[k] + thick;
        else
          lo[k] = hi[k] - thick;
        m.append(box_at(lo, hi));
      }
      return m;
    }
  }
  if (kind == "plate" || kind == "hinge") {
    // The thinnest sensible plate on the face that touches a principal part.
    for (const PlacedPart& other : t.placed_parts()) {
      if (other.role != PartRole::kPrincipal) continue;
      for (int k = 0; k < 3; ++k) {
        const int u = (k + 1) % 3, v = (k + 2) % 3;
        if (b.overlap(other.box, u) <= 0 || b.overlap(other.box, v) <= 0) continue;
        Vec3 lo = b.min(), hi = b.max();
        if (std::abs(b.min()[k] - other.box.max()[k]) < 0.6) {
          hi[k] = lo[k] + std::min(3.0, b.size[k]);
          return box_at(lo, hi);
        }
        if (std::abs(b.max()[k] - other.box.min()[k]) < 0.6) {
          lo[k] = hi[k] - std::min(3.0, b.size[k]);
          return box_at(lo, hi);
        }
      }
    }
  }
  return box_at(b.min(), b.max());
}

std::vector<SceneObject> model_scene(const Template& t,
                                     const ItemCatalog& catalog,
                                     const SceneOptions& o) {
  std::vector<SceneObject> out;
  for (const PlacedPart& p : t.placed_parts()) {
    SceneObject obj;
    obj.name = p.name;
    const Item* it = catalog.find(p.item);
    obj.mesh = part_mesh(t, p, it);
    obj.transform = translation(0.0, 0.0, o.lift);
    const bool stable =
        o.element_stable.empty() || (p.element.value < static_cast<int>(o.element_stable.size()) &&
                                     o.element_stable[p.element.value]);
    const bool connecting = p.role == PartRole::kConnecting;
    if (o.colors == SceneColors::kStability) {
      obj.color = connecting ? std::array<float, 4>{0.6f, 0.6f, 0.6f, 1.0f}
                  : stable   ? std::array<float, 4>{0.2f, 0.7f, 0.25f, 1.0f}
                             : std::array<float, 4>{0.85f, 0.1f, 0.1f, 1.0f};
    } else if (!stable && !connecting) {
      obj.color = {0.85f, 0.1f, 0.1f, 1.0f};
    } else if (connecting) {
      obj.color = {0.2f, 0.4f, 0.85f, 1.0f};
    } else {
      obj.color = material_color(it);
    }
    out.push_back(std::move(obj));
  }
  return out;
}

}  // namespace fabkit::templates

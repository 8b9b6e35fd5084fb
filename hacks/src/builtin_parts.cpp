/// The built-in parts. The fixed ones (every row of reference §10.2) are data: the part file
/// hacks/data/parts.yaml, in the format users write (docs/parts.md), embedded in the library
/// and read by the same parser. The two parametric parts, ParamTurnbuckle and ParamHanger, are
/// generators here: their primitives and bodies follow formulas of their parameters.

#include <cassert>
#include <cmath>
#include <memory>

#include "builtin_parts_data.h"
#include "convex_pieces.h"
#include "fabkit/hacks/parts_library.h"

namespace fabkit::hacks {
namespace {

using PT = PrimitiveType;
using PC = PartCategory;

Primitive make_prim(std::string name, PT type, const PrimitiveShape& s, Vec3 pos, Vec3 rot) {
  return Primitive::make(std::move(name), type, s, Frame(pos, rot));
}

Primitive rod(std::string name, double radius, double length, Vec3 pos, Vec3 rot) {
  PrimitiveShape s;
  s.radius = radius;
  s.length = length;
  return make_prim(std::move(name), PT::kRod, s, pos, rot);
}

Primitive hook(
    std::string name, double arc_radius, double arc_angle, double thickness, Vec3 pos, Vec3 rot) {
  PrimitiveShape s;
  s.arc_radius = arc_radius;
  s.arc_angle = arc_angle;
  s.thickness = thickness;
  return make_prim(std::move(name), PT::kHook, s, pos, rot);
}

// Table flags.
Primitive flex(Primitive p) {  // [HookFlex] / [RingFlex]
  p.flex = true;
  return p;
}
Primitive closed(Primitive p) {  // [is_open=False]: also closed for connecting
  p.is_open = false;
  p.open_for_connect = false;
  return p;
}
// ---------------------------------------------------------------------------------------------
// Mesh helpers.

// A body being drawn: its display mesh and its convex pieces (contact queries).
struct Shaped {
  TriangleMesh mesh;
  std::vector<TriangleMesh> pieces;
  void add_convex(const TriangleMesh& m) {
    mesh.append(m);
    pieces.push_back(m);
  }
  void add(const TriangleMesh& m, std::vector<TriangleMesh> convex_parts) {
    mesh.append(m);
    for (TriangleMesh& c : convex_parts) pieces.push_back(std::move(c));
  }
};

// Cylinder of `radius` whose axis runs from a to b.
TriangleMesh cylinder_between(const Vec3& a, const Vec3& b, double radius, int segments = 16) {
  const Vec3 d = b - a;
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() =
      Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).normalized().toRotationMatrix();
  m.topRightCorner<3, 1>() = 0.5 * (a + b);
  return shapes::cylinder(radius, d.norm(), segments).transformed(m);
}

// Point on a hook's (or ring's) wire centreline at angle θ, in part coordinates
// (the HookMCF parameterisation with r = arc_radius).
Vec3 hook_point(const Primitive& h, double theta_deg) {
  const double r = h.shape.arc_radius;
  const double th = theta_deg * kDegToRad;
  return h.frame.apply(Vec3(0, -r * std::sin(th), -r * std::cos(th)));
}

// The end of an open hook nearest to `target`: where a shank or strap joins it.
Vec3 hook_end_near(const Primitive& h, const Vec3& target) {
  const Vec3 a = hook_point(h, 0);
  const Vec3 b = hook_point(h, h.shape.arc_angle);
  return (a - target).norm() <= (b - target).norm() ? a : b;
}

// The wire of a hook continued from θ = from to θ = to (e.g. a hanger hook running into its
// neck): a torus arc in the hook's frame rotated to start at `from`.
void add_hook_extension(Shaped& out, const Primitive& h, double from, double to) {
  const Mat4 m = h.frame.matrix() * rot_x(-from);
  std::vector<TriangleMesh> parts =
      detail::arc_pieces(h.shape.arc_radius, h.shape.thickness, to - from);
  detail::transform_pieces(parts, m);
  out.add(shapes::torus_arc(h.shape.arc_radius, h.shape.thickness, to - from, 16).transformed(m),
          std::move(parts));
}

// The part: primitives at their frames, the body mesh plus the primitives' meshes, the table
// mass and the mesh centroid as the centre of mass.
Part assemble(std::vector<Primitive> prims, Shaped body, double mass) {
  Part p;
  p.primitives = std::move(prims);
  p.mesh = std::move(body.mesh);
  p.collision_pieces = std::move(body.pieces);
  p.collision_tags.assign(p.collision_pieces.size(), -1);
  for (std::size_t i = 0; i < p.primitives.size(); ++i) {
    p.mesh.append(primitive_mesh(p.primitives[i]));
    add_primitive_pieces(p, static_cast<int>(i));
  }
  p.mass = mass;
  p.center_of_mass = p.mesh.centroid();
  return p;
}

// A turnbuckle body along y (55 mm long, two side bars and two threaded bosses) with a screw
// from each boss to its hook's nearer end.
Shaped turnbuckle_body(const Primitive& hook1, const Primitive& hook2) {
  Shaped m;
  for (double x : {-4.5, 4.5}) m.add_convex(cylinder_between({x, -22, 0}, {x, 22, 0}, 1.5, 10));
  for (double s : {-1.0, 1.0}) {
    m.add_convex(cylinder_between({0, s * 21.5, 0}, {0, s * 27.5, 0}, 3.5, 12));  // boss
    const Primitive& h = s > 0 ? hook1 : hook2;
    const Vec3 inside(0, s * 20.0, 0);
    m.add_convex(cylinder_between(inside, hook_end_near(h, inside), 2.0, 10));  // M4 screw
  }
  return m;
}

// Wire coat hanger: the top hook's wire runs on from θ 180 to 270 into a neck that meets the
// shoulders at `apex`; the shoulders end at the upper ends of the two bend hooks.
Shaped hanger_body(const Primitive& top,
                   const Primitive& bend_a,
                   const Primitive& bend_b,
                   const Vec3& apex,
                   double wire_radius) {
  Shaped m;
  add_hook_extension(m, top, 180, 270);
  m.add_convex(cylinder_between(hook_point(top, 270), apex, wire_radius, 10));
  for (const Primitive* b : {&bend_a, &bend_b}) {
    const Vec3 p0 = hook_point(*b, 0);
    const Vec3 p1 = hook_point(*b, b->shape.arc_angle);
    m.add_convex(cylinder_between(apex, p0.z() > p1.z() ? p0 : p1, wire_radius, 10));
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// The parametric parts.

// Reference §10.2: hook_y = 6 + 10 + 27.5 + extended_length / 2 (bolt, hook, half body, and
// half the extension on each side).
Part param_turnbuckle(const ParamValues& v) {
  const double hook_y = 6 + 10 + 27.5 + v.at("extended_length") / 2;
  auto h1 = hook("hook1", 5.75, 220, 1.5, {2, hook_y, 0}, {175, 90, 0});
  auto h2 = flex(hook("hook2", 5.75, 220, 1.5, {-2, -hook_y, 0}, {355, 90, 0}));
  // The θ = 220° ends join the screws: only the tips are open (as Turnbuckle in parts.yaml).
  h1.open_ends = {true, false};
  h2.open_ends = {true, false};
  // The screws slide out of the body, so the mass stays 1699.8 for every extension.
  return assemble({h1, h2}, turnbuckle_body(h1, h2), 1699.8);
}

// ParamHanger (reference §10.2 row): primitives from the formulas; `height` sets the shoulder
// apex (it only affects the mesh).
Part param_hanger_geometry(const ParamValues& v) {
  const double bar_r = v.at("bar_d") / 2;
  const double bend_r = v.at("bend_d") / 2;
  const double plate_h = 2 * v.at("bar_d") + 9;
  double bottom_l = v.at("length") / 2 - bend_r - plate_h / 2;
  double rod_l = 2 * bottom_l;
  if (rod_l > 20) {
    rod_l -= 10;
    bottom_l -= 5;
  }
  const double hook_r = v.at("hook_d") / 2;
  auto h1 = hook("hook1", hook_r, 180, bar_r, {0, 0, v.at("hook_h") - hook_r - bar_r}, {-45, 0, 0});
  h1.open_ends = {true, false};  // its upper end runs into the neck
  auto r = closed(rod("rod", bar_r, rod_l, {0, 0, -110}, {-90, 180, 0}));
  auto h2 = closed(hook("hook2", bend_r, 160, bar_r, {0, bottom_l, -97.5}, {160, 0, 0}));
  auto h3 = closed(hook("hook3", bend_r, 160, bar_r, {0, -bottom_l, -97.5}, {0, 0, 0}));
  Part p;
  p.primitives = {h1, r, h2, h3};
  // Skip the body when the parameters make impossible primitives; make() reports them.
  bool drawable = true;
  for (const Primitive& prim : p.primitives) {
    Diagnostics d;
    prim.validate("", d);
    drawable = drawable && !d.has_errors();
  }
  if (drawable) {
    Shaped body = hanger_body(h1, h2, h3, {0, 0, -110 + v.at("height")}, bar_r);
    // `length` is the hanger's width: the shoulder wire runs on past each bend to a flat tip at
    // ±length/2.
    for (const Primitive* b : {&h2, &h3}) {
      const Vec3 p0 = hook_point(*b, 0);
      const Vec3 p1 = hook_point(*b, b->shape.arc_angle);
      const Vec3 upper = p0.z() > p1.z() ? p0 : p1;
      const double side = b->frame.pos.y() >= 0 ? 1.0 : -1.0;
      const Vec3 tip(0, side * v.at("length") / 2, upper.z());
      if (side * (tip.y() - upper.y()) > 1e-9) {
        body.add_convex(cylinder_between(upper, tip, bar_r, 10));
      }
    }
    p.mesh = std::move(body.mesh);
    p.collision_pieces = std::move(body.pieces);
    p.collision_tags.assign(p.collision_pieces.size(), -1);
    for (std::size_t i = 0; i < p.primitives.size(); ++i) {
      p.mesh.append(primitive_mesh(p.primitives[i]));
      add_primitive_pieces(p, static_cast<int>(i));
    }
    p.center_of_mass = p.mesh.centroid();
  }
  return p;
}

const std::vector<ParamSchema>& param_hanger_schema() {
  static const std::vector<ParamSchema> schema{
      {"length", 435, 100, 1000, "mm", "shoulder-to-shoulder length"},
      {"height", 115, 20, 400, "mm", "bottom bar to shoulder apex (mesh only)"},
      {"bar_d", 6.35, 1, 20, "mm", "wire diameter"},
      {"bend_d", 25, 5, 100, "mm", "diameter of the bends at the bar ends"},
      {"hook_d", 40, 10, 200, "mm", "diameter of the top hook"},
      {"hook_h", 105, 20, 400, "mm", "height of the top of the hook above the origin"},
  };
  return schema;
}

// Mass = the reference mass at the defaults scaled by the mesh volume (density unchanged).
Part param_hanger(const ParamValues& v) {
  static const double default_volume = [] {
    ParamValues d;
    for (const ParamSchema& s : param_hanger_schema()) d[s.name] = s.default_value;
    return param_hanger_geometry(d).mesh.volume();
  }();
  Part p = param_hanger_geometry(v);
  p.mass = p.mesh.empty() ? 33345.3 : 33345.3 * p.mesh.volume() / default_volume;
  return p;
}

}  // namespace

void register_builtin_parts(PartsLibrary& lib) {
  Diagnostics diags;
  // The embedded file is tested to load cleanly (builtin_parts_test); a failure here is a bug.
  // Each part is built when first made: a solve of three parts does not build fifty.
  [[maybe_unused]] const bool ok = lib.load_yaml_text(kBuiltinPartsYaml,
                                                      "hacks/data/parts.yaml",
                                                      {},
                                                      diags,
                                                      PartCategory::kOther,
                                                      PartLoading::kOnFirstUse);
  assert(ok && "hacks/data/parts.yaml must load");

  PartGenerator tb;
  tb.name = "ParamTurnbuckle";
  tb.description = "parametric M4 turnbuckle: the hooks' screws extend symmetrically";
  tb.category = PC::kOther;
  tb.params = {{"extended_length",
                0,
                0,
                100,
                "mm",
                "how far the two screws are unscrewed in total (each hook moves half)"}};
  tb.build = param_turnbuckle;
  lib.add(std::move(tb));

  PartGenerator hg;
  hg.name = "ParamHanger";
  hg.description = "parametric wire hanger";
  hg.category = PC::kOther;
  hg.params = param_hanger_schema();
  hg.build = param_hanger;
  lib.add(std::move(hg));
}

}  // namespace fabkit::hacks

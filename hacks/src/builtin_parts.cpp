/// The built-in parts: every row of reference §10.2 plus the parametric ParamTurnbuckle and
/// ParamHanger. Primitives (names, shapes, frames, flags) and masses are copied from the table;
/// angles are written as the table lists them (mod 360).
///
/// The reference loads scanned meshes; we have none, so each part gets a procedural display
/// mesh: a few boxes, cylinders and torus arcs where the real object's body is, plus the
/// primitives' own meshes. The centre of mass is that mesh's centroid, so the heavy body of
/// each object is placed where it really is relative to its connectors.

#include <algorithm>
#include <cmath>
#include <memory>

#include "fabkit/hacks/parts_library.h"

namespace fabkit::hacks {
namespace {

using PT = PrimitiveType;
using PC = PartCategory;

// ---------------------------------------------------------------------------------------------
// Primitive constructors (shape fields named as in the table).

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

Primitive ring(std::string name, double arc_radius, double thickness, Vec3 pos, Vec3 rot) {
  PrimitiveShape s;
  s.arc_radius = arc_radius;
  s.thickness = thickness;
  return make_prim(std::move(name), PT::kRing, s, pos, rot);
}

Primitive tube(
    std::string name, double length, double thickness, double inner_radius, Vec3 pos, Vec3 rot) {
  PrimitiveShape s;
  s.length = length;
  s.thickness = thickness;
  s.inner_radius = inner_radius;
  return make_prim(std::move(name), PT::kTube, s, pos, rot);
}

Primitive clip(std::string name,
               double thickness,
               double width,
               double height,
               double dist,
               double open_gap,
               Vec3 pos,
               Vec3 rot) {
  PrimitiveShape s;
  s.thickness = thickness;
  s.width = width;
  s.height = height;
  s.dist = dist;
  s.open_gap = open_gap;
  return make_prim(std::move(name), PT::kClip, s, pos, rot);
}

Primitive edge(std::string name, double length, double width, double height, Vec3 pos, Vec3 rot) {
  PrimitiveShape s;
  s.length = length;
  s.width = width;
  s.height = height;
  return make_prim(std::move(name), PT::kEdge, s, pos, rot);
}

Primitive surface(std::string name, double length, double width, Vec3 pos, Vec3 rot) {
  PrimitiveShape s;
  s.length = length;
  s.width = width;
  return make_prim(std::move(name), PT::kSurface, s, pos, rot);
}

Primitive hemisphere(std::string name, double radius, Vec3 pos, Vec3 rot) {
  PrimitiveShape s;
  s.radius = radius;
  return make_prim(std::move(name), PT::kHemisphere, s, pos, rot);
}

// Table flags.
Primitive flex(Primitive p) {  // [HookFlex] / [RingFlex]
  p.flex = true;
  return p;
}
Primitive ctl(Primitive p) {  // [RodCtl] / [RingCtl] / [TubeCtl]
  p.centerline = true;
  return p;
}
Primitive closed(Primitive p) {  // [is_open=False]: also closed for connecting
  p.is_open = false;
  p.open_for_connect = false;
  return p;
}
Primitive closed_ends(Primitive p) {  // [is_open=False, open_for_connect=True]
  p.is_open = false;
  p.open_for_connect = true;
  return p;
}
Primitive theta_range(Primitive p, double lo, double hi) {  // [θ range [lo, hi]]
  p.theta_range = std::array<double, 2>{lo, hi};
  return p;
}

// ---------------------------------------------------------------------------------------------
// Mesh helpers.

// Axis-aligned box between two corners.
TriangleMesh box_between(const Vec3& lo, const Vec3& hi) {
  const Vec3 c = 0.5 * (lo + hi);
  return shapes::box(hi - lo).transformed(translation(c.x(), c.y(), c.z()));
}

// Cylinder of `radius` whose axis runs from a to b.
TriangleMesh cylinder_between(const Vec3& a, const Vec3& b, double radius, int segments = 16) {
  const Vec3 d = b - a;
  Mat4 m = Mat4::Identity();
  m.topLeftCorner<3, 3>() =
      Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), d).normalized().toRotationMatrix();
  m.topRightCorner<3, 1>() = 0.5 * (a + b);
  return shapes::cylinder(radius, d.norm(), segments).transformed(m);
}

// Open-topped box (basket, tray, caddy): a floor of `floor` thickness and four walls.
TriangleMesh open_box(const Vec3& lo, const Vec3& hi, double wall, double floor) {
  TriangleMesh m;
  m.append(box_between(lo, Vec3(hi.x(), hi.y(), lo.z() + floor)));
  const double z0 = lo.z() + floor;
  m.append(box_between(Vec3(lo.x(), lo.y(), z0), Vec3(lo.x() + wall, hi.y(), hi.z())));
  m.append(box_between(Vec3(hi.x() - wall, lo.y(), z0), Vec3(hi.x(), hi.y(), hi.z())));
  m.append(
      box_between(Vec3(lo.x() + wall, lo.y(), z0), Vec3(hi.x() - wall, lo.y() + wall, hi.z())));
  m.append(
      box_between(Vec3(lo.x() + wall, hi.y() - wall, z0), Vec3(hi.x() - wall, hi.y(), hi.z())));
  return m;
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
TriangleMesh hook_extension(const Primitive& h, double from, double to) {
  return shapes::torus_arc(h.shape.arc_radius, h.shape.thickness, to - from, 16)
      .transformed(h.frame.matrix() * rot_x(-from));
}

// The part: primitives at their frames, the body mesh plus the primitives' meshes, the table
// mass and the mesh centroid as the centre of mass.
Part assemble(std::vector<Primitive> prims, TriangleMesh body, double mass) {
  Part p;
  p.primitives = std::move(prims);
  p.mesh = std::move(body);
  for (const Primitive& prim : p.primitives) p.mesh.append(primitive_mesh(prim));
  p.mass = mass;
  p.center_of_mass = p.mesh.centroid();
  return p;
}

// ---------------------------------------------------------------------------------------------
// Shared bodies.

// One car seat centred at x = cx whose headrest posts stand at y = 556.9 between the top of the
// backrest (z 744.5) and the bottom of the headrest (z 781.5). The cushion points to -y.
TriangleMesh car_seat(double cx) {
  constexpr double y = 556.9;
  TriangleMesh m;
  m.append(box_between({cx - 260, y - 60, 320}, {cx + 260, y + 60, 744.5}));  // backrest
  m.append(box_between({cx - 250, y - 560, 250}, {cx + 250, y - 60, 400}));   // cushion
  m.append(box_between({cx - 130, y - 45, 781.5}, {cx + 130, y + 45, 960}));  // headrest
  m.append(box_between({cx - 200, y - 500, 0}, {cx + 200, y - 100, 250}));    // pedestal
  return m;
}

// Adhesive wall hook body in WallHook coordinates (plate in the x-z plane behind y = 0, strip
// down to the hook's near arm at y = -3.5, z = -61), moved by `offset`.
TriangleMesh wall_hook_body(const Vec3& offset) {
  TriangleMesh m;
  m.append(box_between(Vec3(-34, -3, -34) + offset, Vec3(34, 0, 34) + offset));        // plate
  m.append(box_between(Vec3(-4, -4.75, -61) + offset, Vec3(4, -2.25, -30) + offset));  // strip
  return m;
}

// A turnbuckle body along y (55 mm long, two side bars and two threaded bosses) with a screw
// from each boss to its hook's nearer end.
TriangleMesh turnbuckle_body(const Primitive& hook1, const Primitive& hook2) {
  TriangleMesh m;
  for (double x : {-4.5, 4.5}) m.append(cylinder_between({x, -22, 0}, {x, 22, 0}, 1.5, 10));
  for (double s : {-1.0, 1.0}) {
    m.append(cylinder_between({0, s * 21.5, 0}, {0, s * 27.5, 0}, 3.5, 12));  // boss
    const Primitive& h = s > 0 ? hook1 : hook2;
    const Vec3 inside(0, s * 20.0, 0);
    m.append(cylinder_between(inside, hook_end_near(h, inside), 2.0, 10));  // M4 screw
  }
  return m;
}

// Wire coat hanger: the top hook's wire runs on from θ 180 to 270 into a neck that meets the
// shoulders at `apex`; the shoulders end at the upper ends of the two bend hooks.
TriangleMesh hanger_body(const Primitive& top,
                         const Primitive& bend_a,
                         const Primitive& bend_b,
                         const Vec3& apex,
                         double wire_radius) {
  TriangleMesh m;
  m.append(hook_extension(top, 180, 270));
  m.append(cylinder_between(hook_point(top, 270), apex, wire_radius, 10));
  for (const Primitive* b : {&bend_a, &bend_b}) {
    const Vec3 p0 = hook_point(*b, 0);
    const Vec3 p1 = hook_point(*b, b->shape.arc_angle);
    m.append(cylinder_between(apex, p0.z() > p1.z() ? p0 : p1, wire_radius, 10));
  }
  return m;
}

// ---------------------------------------------------------------------------------------------
// Parts, alphabetical as in the table. Comments say what the body approximates.

Part back_seats() {
  auto r1 = closed(rod("rod1", 5.7, 37, {50.8, 556.9, 763}, {0, 0, 90}));
  auto r2 = closed(rod("rod2", 5.7, 37, {677.8, 556.9, 763}, {0, 0, 270}));
  // Two seats 627 mm apart; rod1/rod2 are the +x posts of each headrest, add the other posts.
  TriangleMesh body = car_seat(0);
  body.append(car_seat(627));
  for (double x : {-50.8, 576.2}) {
    body.append(cylinder_between({x, 556.9, 744.5}, {x, 556.9, 781.5}, 5.7));
  }
  return assemble({r1, r2}, body, 64769080.0);
}

Part basket() {
  auto r1 = closed(rod("rod1", 3, 72, {124.5, 0, 252}, {90, 180, 0}));
  auto r2 = closed(rod("rod2", 3, 72, {-124.5, 0, 252}, {90, 180, 180}));
  auto s = surface("surface", 248, 248, {0, 0, 6}, {0, 0, 0});
  // Wire basket: floor top at the surface (z 6), walls to z 238, the two side rods (along y)
  // held above the rim by short posts.
  TriangleMesh body = open_box({-124, -124, 0}, {124, 124, 238}, 3, 5.95);
  for (double x : {-124.5, 124.5}) {
    for (double y : {-36.0, 36.0}) body.append(cylinder_between({x, y, 236}, {x, y, 252}, 3, 10));
  }
  return assemble({r1, r2, s}, body, 1527821.5);
}

Part basket_base() {
  auto r1 = ring("ring1", 3.5, 1, {0, -151.8, 43.1}, {0, 0, 270});
  auto r2 = ring("ring2", 3.5, 1, {0, -0.7, 43.1}, {0, 180, 270});
  auto s = surface("surface", 141, 118, {0, -76, -41}, {0, 0, 90});
  // Basket body below the eyelets: floor top at the surface, walls up to z 38; each eyelet
  // hangs on a tab over its end wall.
  TriangleMesh body = open_box({-59, -146.5, -43}, {59, -5.5, 38}, 2, 1.95);
  body.append(box_between({-1.5, -151.8, 35}, {1.5, -146.5, 40}));
  body.append(box_between({-1.5, -5.5, 35}, {1.5, -0.7, 40}));
  return assemble({r1, r2, s}, body, 446572.8);
}

Part basket_handle() {
  auto r1 = closed(rod("rod1", 3, 153, {12.7, -3, 20.5}, {0, 90, 0}));
  auto r2 = rod("rod2", 2, 6.5, {-60.5, -3.1, -50}, {0, 90, 0});
  auto r3 = rod("rod3", 2, 6.5, {85.8, -3.1, -50}, {0, 270, 0});
  // U-shaped handle: the bar (rod1) and two legs down to the pivot pins (rod2, rod3).
  TriangleMesh body;
  for (double x : {-60.5, 85.8}) body.append(cylinder_between({x, -3, 20.5}, {x, -3, -50}, 3, 12));
  return assemble({r1, r2, r3}, body, 8572.2);
}

Part binder_clip() {
  auto c = clip("clip", 0.1, 19, 11, 8.2, 3.5, {15, 1.2, 3.5}, {90, 0, 90});
  auto r1 = ctl(ring("ring1", 3.6, 0.6, {28, -5.3, 3.5}, {90, 0, 258}));
  auto r2 = ctl(ring("ring2", 3.6, 0.6, {28, 7.8, 3.5}, {90, 0, 102}));
  // Steel body: the jaw plates drawn 0.6 mm thick plus the spine closing the back (clip +z,
  // toward the wire loops); the loops' wires run from the rings to the spine.
  Primitive thick = c;
  thick.shape.thickness = 0.6;
  TriangleMesh body = primitive_mesh(thick);
  body.append(shapes::box(Vec3(c.shape.dist + 1.2, c.shape.width, 0.6))
                  .transformed(c.frame.matrix() * translation(0.0, 0.0, c.shape.height / 2)));
  body.append(cylinder_between({24.4, -5.3, 3.5}, {20.5, -2.9, 3.5}, 0.6, 8));
  body.append(cylinder_between({24.4, 7.8, 3.5}, {20.5, 5.3, 3.5}, 0.6, 8));
  return assemble({c, r1, r2}, body, 322.8);
}

Part bird_feeder() {
  auto r = ring("ring", 20, 1.7, {0, 0, 116}, {0, 0, 90});
  // Feeder under its hanging ring: base tray, seed body and a roof whose top (z 94) meets the
  // bottom of the ring.
  TriangleMesh body;
  body.append(cylinder_between({0, 0, 0}, {0, 0, 8}, 100, 32));
  body.append(cylinder_between({0, 0, 8}, {0, 0, 80}, 70, 32));
  body.append(cylinder_between({0, 0, 80}, {0, 0, 94.5}, 95, 32));
  return assemble({r}, body, 3484629.5);
}

Part bird_feeder_env() {
  auto h1 = hook("hook1", 12.5, 180, 1.25, {0, 16, -61}, {90, 0, 0});
  auto h2 = hook("hook2", 12.5, 180, 1.25, {0, 644, -61}, {90, 0, 0});
  // Two wall hooks (the table mass is exactly twice WallHook's), plates 628 mm apart.
  TriangleMesh body = wall_hook_body({0, 32, 0});
  body.append(wall_hook_body({0, 660, 0}));
  return assemble({h1, h2}, body, 21187.4);
}

Part board() {
  auto s1 = surface("surface1", 280, 180, {0, -10, 0}, {90, 0, 0});
  auto s2 = surface("surface2", 280, 180, {0, 0, 0}, {90, 0, 0});
  // A 10 mm board between its two faces.
  return assemble({s1, s2}, box_between({-140, -10, -90}, {140, 0, 90}), 647135.7);
}

Part broom_rod() {
  auto t = tube("tube", 387, 1.5, 8.5, {0, 0, 197.5}, {0, 0, 0});
  // Hollow handle with a threaded plug at the bottom end.
  TriangleMesh body = cylinder_between({0, 0, -15}, {0, 0, 4}, 7, 16);
  return assemble({t}, body, 17589.7);
}

Part cable() {
  auto r1 = ctl(rod("rod1", 1.2, 100, {0, 0, -76}, {0, 0, 0}));
  // The plug stops the cord from sliding through a loop at its top end (t = 1).
  r1.open_ends = {true, false};
  auto r2 = rod("rod2", 2.5, 11, {0, 0, -20.5}, {0, 0, 0});
  // Cord (rod1), strain relief (rod2), plug housing and metal connector on top.
  TriangleMesh body;
  body.append(box_between({-6, -2.75, -15}, {6, 2.75, -2}));
  body.append(box_between({-4.2, -1.4, -2}, {4.2, 1.4, 8}));
  return assemble({r1, r2}, body, 1874.9);
}

Part car_seat_part() {
  auto r1 = rod("rod1", 5.7, 37, {50.8, 556.9, 763}, {0, 0, 180});
  auto r2 = rod("rod2", 5.7, 37, {-50.8, 556.9, 763}, {0, 0, 180});
  return assemble({r1, r2}, car_seat(0), 32384580.0);
}

Part ceiling_hook() {
  auto h = hook("hook", 25, 300, 2.5, {0, 0, -61.5}, {120, 0, 90});
  // Swag hook: a shank from the hook's upper end to a ceiling rosette at z 0.
  TriangleMesh body = cylinder_between(hook_end_near(h, {0, 0, 0}), {0, 0, -6}, 2.5, 12);
  body.append(cylinder_between({0, 0, -6}, {0, 0, 0}, 15, 24));
  return assemble({h}, body, 8272.5);
}

Part clip_light() {
  auto c = clip("clip", 1, 30, 30, 13.5, 13.5, {23.6, 0, 14.05}, {0, 90, 0});
  // Clip-on reading light: battery housing behind the jaw's hinge end (x < 8.6), a gooseneck
  // and a small lamp head; the housing and head carry most of the mass.
  TriangleMesh body = box_between({-20, -15, 0}, {8.6, 15, 28});
  body.append(cylinder_between({-6, 0, 28}, {55, 0, 160}, 3.5, 12));
  body.append(cylinder_between({68, 0, 160}, {68, 0, 185}, 22, 24));
  return assemble({c}, body, 65453.4);
}

Part closet_rods() {
  auto r1 = closed_ends(rod("rod1", 6.35, 170, {0, -175, 0}, {90, 0, 180}));
  auto r2 = closed_ends(rod("rod2", 6.35, 170, {0, 175, 0}, {90, 0, 180}));
  // Two rod segments on one line (along y) with a bracket cap at every end (closed ends).
  TriangleMesh body;
  for (double y : {-268.0, -90.0, 82.0, 260.0}) {
    body.append(cylinder_between({0, y, 0}, {0, y + 8, 0}, 16, 20));
  }
  return assemble({r1, r2}, body, 42742.6);
}

Part clothes_clip() {
  auto h = hook("hook", 3.8, 360, 1, {0, -4.6, 5}, {0, 90, 0});
  auto c = clip("clip", 1.5, 10, 32, 2.4, 7.8, {0, 16, 5}, {90, 180, 0});
  // Clothes peg: two wooden arms along y (jaws toward +y, levers toward -y) either side of
  // the spring coil (the hook).
  TriangleMesh body;
  body.append(box_between({1.2, -26, 0}, {5.2, 34, 10}));
  body.append(box_between({-5.2, -26, 0}, {-1.2, 34, 10}));
  return assemble({h, c}, body, 7504.1);
}

Part curtain_ring() {
  auto h = closed_ends(hook("hook", 20.8, 342, 2.2, {0, 1.6, 0}, {0, 90, 4.5}));
  // Split ring plus the small eyelet opposite the split that the curtain hangs from.
  const Vec3 radial(std::cos(4.5 * kDegToRad), std::sin(4.5 * kDegToRad), 0);
  const Vec3 c = h.frame.pos + (20.8 + 2.2 + 4.0) * radial;
  TriangleMesh body = shapes::torus_arc(4, 1, 360, 16, 8)
                          .transformed(translation(c.x(), c.y(), c.z()) * rot_z(94.5));
  return assemble({h}, body, 3460.9);
}

Part diaper_caddy() {
  auto h1 = closed(flex(hook("hook1", 16.2, 150, 4, {165, 128.4, 311}, {255, 315, 270})));
  auto h2 = closed(flex(hook("hook2", 16.2, 150, 4, {165, -357, 311}, {255, 315, 90})));
  // Fabric caddy hanging below its hooks (open box, hooks at the top of its back side), each
  // hook sewn on with a strap.
  TriangleMesh body = open_box({0, -350, 0}, {160, 122, 300}, 6, 6);
  for (const Primitive* h : {&h1, &h2}) {
    const Vec3 anchor(155, std::clamp(h->frame.pos.y(), -345.0, 117.0), 295);
    body.append(cylinder_between(hook_end_near(*h, anchor), anchor, 4, 10));
  }
  return assemble({h1, h2}, body, 2798783.0);
}

// S-hooks: the two hooks meet at the origin; the primitives are the whole object.
Part double_hook() {
  auto h1 = flex(hook("hook1", 11.6, 270, 2, {0, 0, 11.6}, {0, 0, 0}));
  auto h2 = flex(hook("hook2", 11.6, 270, 2, {0, 0, -11.6}, {90, 0, 180}));
  return assemble({h1, h2}, {}, 1382.1);
}

Part double_hook_medium() {
  auto h1 = hook("hook1", 16, 270, 2.9, {0, 0, 16}, {0, 0, 0});
  auto h2 = hook("hook2", 16, 270, 2.9, {0, 0, -16}, {90, 0, 180});
  return assemble({h1, h2}, {}, 3979.1);
}

Part fabric_hanger() {
  auto h1 = theta_range(hook("hook1", 25, 180, 6.5, {0, 0, 65}, {270, 0, 90}), 0, 270);
  auto r = closed(rod("rod", 6.5, 385, {0, 0, -110}, {0, 90, 0}));
  auto h2 = closed(hook("hook2", 15, 160, 6.5, {193.5, 0, -95}, {0, 0, 90}));
  auto h3 = closed(hook("hook3", 15, 160, 6.5, {-193.5, 0, -95}, {160, 0, 90}));
  // Padded hanger in the x-z plane: neck below the hook, padded shoulders down to the notches.
  TriangleMesh body = hanger_body(h1, h2, h3, {0, 0, 20}, 8);
  return assemble({h1, r, h2, h3}, body, 137987.0);
}

Part flag_rod() {
  auto r = ctl(rod("rod", 6.35, 280, {0, 0, 140}, {0, 0, 0}));
  // Rod with a finial ball on top.
  return assemble({r}, shapes::sphere(12).transformed(translation(0.0, 0.0, 290.0)), 37410.3);
}

Part handle_basket() {
  auto r = closed(rod("rod", 3, 153, {-31.4, 178, 297.1}, {0, 90, 90}));
  auto s = surface("surface", 141, 118, {-31.3, 177.9, 143}, {0, 0, 90});
  // Basket (floor top at the surface) with the handle bar held by two legs on its end walls.
  TriangleMesh body = open_box({-90.3, 107.4, 141}, {27.7, 248.4, 225}, 2, 1.95);
  body.append(cylinder_between({-31.4, 101.5, 297.1}, {-31.4, 108.4, 225}, 3, 10));
  body.append(cylinder_between({-31.4, 254.5, 297.1}, {-31.4, 247.4, 225}, 3, 10));
  return assemble({r, s}, body, 455143.7);
}

Part hanger() {
  auto h1 = theta_range(hook("hook1", 20, 180, 3.1, {0, 0, 83}, {315, 0, 0}), 0, 270);
  auto r = closed(rod("rod", 3.5, 390, {0, 0, -110}, {270, 180, 0}));
  auto h2 = closed(hook("hook2", 12.5, 160, 3.1, {0, 194.1, -97.5}, {160, 0, 0}));
  auto h3 = closed(hook("hook3", 12.5, 160, 3.1, {0, -194.1, -97.5}, {0, 0, 0}));
  // Wire hanger in the y-z plane: twisted neck and two straight shoulders.
  TriangleMesh body = hanger_body(h1, h2, h3, {0, 0, 5}, 3.1);
  return assemble({h1, r, h2, h3}, body, 33347.5);
}

// Eye hook: a screw eye (the ring, centred at the origin in the x-z plane) and a shank down to
// the hook's end nearest the eye.
Part eye_hook(Primitive hook_prim, Primitive ring_prim) {
  const Vec3 eye_bottom(0, 0, -ring_prim.shape.arc_radius);
  TriangleMesh body = cylinder_between(eye_bottom, hook_end_near(hook_prim, eye_bottom), 4.5, 12);
  return assemble({std::move(hook_prim), std::move(ring_prim)}, body, 17221.8);
}

Part hook_eye_right() {  // also HookEyeConnector (paper Fig. 8)
  return eye_hook(closed_ends(flex(hook("hook", 19, 210, 5, {0, 0, -54.2}, {90, 0, 0}))),
                  ring("ring", 14.82, 4.5, {0, 0, 0}, {0, 0, 90}));
}

Part hook_eye_left() {
  return eye_hook(closed_ends(flex(hook("hook", 19, 210, 5, {0, 0, -54.2}, {120, 0, 0}))),
                  ring("ring", 14.82, 4.5, {0, 0, 0}, {0, 0, 90}));
}

Part hook_eye_left_s() {
  return eye_hook(closed_ends(hook("hook", 19, 210, 5, {0, 0, -54.2}, {90, 0, 180})),
                  flex(ring("ring", 14.82, 4.5, {0, 0, 0}, {0, 0, 90})));
}

Part hula_hoop() {
  return assemble({flex(ring("ring", 345.75, 11.5, {0, 0, 0}, {0, 0, 0}))}, {}, 904256.0);
}

Part long_tension_rod() {
  auto r = rod("rod", 12.7, 2920, {1525, 127, 2133.5}, {0, 90, 0});
  // Rod spanning x 65..2985 with rubber end pads against the walls.
  TriangleMesh body = cylinder_between({45, 127, 2133.5}, {65, 127, 2133.5}, 25, 24);
  body.append(cylinder_between({2985, 127, 2133.5}, {3005, 127, 2133.5}, 25, 24));
  return assemble({r}, body, 1576597.0);
}

Part mug() {
  auto h = closed(hook("hook", 30.5, 200, 6, {49.5, 0, 50}, {10, 0, 90}));
  auto t = tube("tube", 100, 2.2, 43, {0, 0, 50}, {0, 0, 0});
  // The tube is the wall, the hook the handle; add the bottom.
  return assemble({h, t}, cylinder_between({0, 0, 0}, {0, 0, 5}, 45.2, 32), 151538.3);
}

Part obstacle_ring_l() {
  return assemble({ring("ring", 195, 3, {0, 0, 0}, {0, 90, 0})}, {}, 83606.1);
}

Part obstacle_ring_m() {
  return assemble({ring("ring", 127.25, 3, {0, 0, 0}, {0, 90, 0})}, {}, 77979.4);
}

Part open_handle_basket() {
  auto h = hook("hook", 87.5, 180, 12.7, {0, 0, 200}, {270, 0, 90});
  // The hook is the arched handle (x-z plane); its ends stand on a basket's rim at z 130.
  TriangleMesh body = open_box({-100, -75, 0}, {100, 75, 130}, 4, 4);
  for (double x : {-87.5, 87.5}) body.append(cylinder_between({x, 0, 130}, {x, 0, 200}, 12.7, 16));
  return assemble({h}, body, 349067.0);
}

Part paper_towel_roll() {
  // The roll itself is the tube.
  return assemble({ctl(tube("tube", 279.4, 29, 21, {0, 0, -140}, {0, 0, 0}))}, {}, 1817000.1);
}

// Reference §10.2: hook_y = 6 + 10 + 27.5 + extended_length / 2 (bolt, hook, half body, and
// half the extension on each side).
Part param_turnbuckle(const ParamValues& v) {
  const double hook_y = 6 + 10 + 27.5 + v.at("extended_length") / 2;
  auto h1 = hook("hook1", 5.75, 220, 1.5, {2, hook_y, 0}, {175, 90, 0});
  auto h2 = flex(hook("hook2", 5.75, 220, 1.5, {-2, -hook_y, 0}, {355, 90, 0}));
  // The screws slide out of the body, so the mass stays 1699.8 for every extension.
  return assemble({h1, h2}, turnbuckle_body(h1, h2), 1699.8);
}

Part pen() {
  auto r = rod("rod", 5.9, 137, {68.4, 30, 0}, {90, 180, 90});
  auto e = edge("edge", 47, 5.5, 6.1, {113.5, 30, -8.2}, {0, 0, 0});
  // Barrel along x (the rod), the pocket clip (edge) under the cap end, and the nib.
  TriangleMesh body = cylinder_between({-9, 30, 0}, {0, 30, 0}, 2.5, 12);
  return assemble({r, e}, body, 14363.8);
}

Part phone() {
  // The phone's body is its edge primitive (153 x 65 x 8 mm).
  return assemble({edge("edge", 153, 65, 8, {-9.7, -4, -6.8}, {90, 90, 0})}, {}, 78344.5);
}

Part plastic_clip() {
  auto c = clip("clip", 1, 17, 8, 13, 12, {0, 26, 0}, {90, 0, 180});
  auto m1 = hemisphere("hemisphere1", 8.5, {-12, -21.7, 0}, {270, 0, 0});
  auto m2 = hemisphere("hemisphere2", 8.5, {12, -21.7, 0}, {270, 0, 0});
  // Two round feet (the hemispheres, bulging to -y) on a cross bar, a stem along +y and a
  // base under the jaw.
  TriangleMesh body = box_between({-20.5, -21.7, -6}, {20.5, -16, 6});
  body.append(box_between({-3, -16, -4}, {3, 20, 4}));
  body.append(box_between({-7.5, 20, -8.5}, {7.5, 22.5, 8.5}));
  return assemble({c, m1, m2}, body, 7255.6);
}

Part reading_room() {
  auto r1 = rod("rod1", 10, 1500, {-175, 1030, 1283}, {0, 90, 0});
  auto r2 = rod("rod2", 2.5, 20, {72.2, -1375, 1293.7}, {120, 0, 0});
  // The pin is a screw: its t = 1 end is in the wall (y = -1383) and its head closes the tip,
  // so a hook hung on it cannot slide off either end (it can still be hooked on).
  r2.open_ends = {false, false};
  // Floor and the two facing walls: rod1 on brackets in front of one, the pin (rod2) stuck in
  // the other.
  TriangleMesh body = box_between({-1000, -1405, -20}, {1000, 1100, 0});
  body.append(box_between({-1000, -1405, 0}, {1000, -1383, 2400}));
  body.append(box_between({-1000, 1080, 0}, {1000, 1100, 2400}));
  for (double x : {-925.0, 575.0}) {
    body.append(cylinder_between({x, 1030, 1283}, {x, 1080, 1283}, 8, 12));
  }
  return assemble({r1, r2}, body, 900881024.0);
}

Part ring_part(double arc_radius, double mass) {
  return assemble({ring("ring", arc_radius, 3.3, {0, 0, 0}, {0, 90, 0})}, {}, mass);
}

Part ring_link() {
  auto h1 = closed_ends(flex(hook("hook1", 18, 150, 4, {13.5, 0, 0}, {255, 90, 0})));
  auto h2 = closed_ends(flex(hook("hook2", 18, 150, 4, {-13.5, 0, 0}, {75, 90, 0})));
  // C-shaped link: the two arcs (x-y plane) joined by one straight side; the other side has
  // a gap to hook links together.
  const double y = 18 * std::sin(75 * kDegToRad);
  const double x = 13.5 + 18 * std::cos(75 * kDegToRad);
  TriangleMesh body = cylinder_between({-x, -y, 0}, {x, -y, 0}, 4, 12);
  body.append(cylinder_between({-x, y, 0}, {-x + 12, y, 0}, 4, 12));
  body.append(cylinder_between({x - 12, y, 0}, {x, y, 0}, 4, 12));
  return assemble({h1, h2}, body, 7991.9);
}

Part round_handle_basket() {
  auto h = closed(flex(hook("hook", 85, 210, 10, {0, 0, 120}, {285, 0, 0})));
  // The hook is the round handle (y-z plane); its ends rest on the rim of the basket.
  return assemble({h}, open_box({-70, -95, 0}, {70, 95, 98}, 4, 4), 502457.9);
}

Part shower_curtain_rod() {
  auto r = rod("rod", 6.5, 351, {200, 127, 2133.5}, {0, 90, 0});
  TriangleMesh body = cylinder_between({18.5, 127, 2133.5}, {24.5, 127, 2133.5}, 12, 20);
  body.append(cylinder_between({375.5, 127, 2133.5}, {381.5, 127, 2133.5}, 12, 20));
  return assemble({r}, body, 58433.7);
}

Part small_bird_feeder_env() {
  auto h1 = hook("hook1", 12.5, 180, 1.25, {0, -245, -61}, {90, 0, 0});
  auto h2 = hook("hook2", 12.5, 180, 1.25, {0, 245, -61}, {90, 0, 0});
  TriangleMesh body = wall_hook_body({0, -229, 0});  // two wall hooks, as BirdFeederEnv
  body.append(wall_hook_body({0, 261, 0}));
  return assemble({h1, h2}, body, 21187.4);
}

Part soap_bottle() {
  auto r = rod("rod", 38.5, 140, {0, 0, 70}, {0, 0, 0});
  auto s = surface("surface", 77, 77, {0, 0, -1}, {0, 0, 0});
  // Bottle body (the rod), base, neck and pump head with its nozzle.
  TriangleMesh body = cylinder_between({0, 0, -1}, {0, 0, 0}, 38.5, 32);
  body.append(cylinder_between({0, 0, 140}, {0, 0, 160}, 12, 20));
  body.append(cylinder_between({0, 0, 160}, {0, 0, 185}, 8, 16));
  body.append(box_between({0, -4, 177}, {30, 4, 185}));
  return assemble({r, s}, body, 688663.2);
}

Part soda_can_tab() {
  auto r1 = ctl(ring("ring1", 7, 0.7, {0, 0, 0.64}, {0, 90, 0}));
  auto r2 = ctl(ring("ring2", 3.5, 0.5, {0, 12.7, 0.64}, {0, 90, 0}));
  // The metal between the two holes.
  return assemble({r1, r2}, box_between({-2.5, 6.5, 0.3}, {2.5, 9.5, 0.98}), 191.8);
}

Part tack() {
  auto r1 = rod("rod1", 3.5, 21, {18.5, 0, 0}, {0, 90, 0});
  auto r2 = rod("rod2", 1, 28.6, {-10.2, 0, 0}, {0, 90, 0});
  auto s = surface("surface", 10, 10, {4, 0, 0}, {0, 90, 0});
  // Push pin along x: needle (rod2), the flat head plate behind the surface, the grip (rod1).
  TriangleMesh body = cylinder_between({4, 0, 0}, {8, 0, 0}, 6, 20);
  body.append(cylinder_between({-27, 0, 0}, {-24.5, 0, 0}, 0.4, 8));
  return assemble({r1, r2, s}, body, 1323.7);
}

Part toothbrush() {
  auto m = hemisphere("hemisphere", 9, {0, 188, 29}, {180, 0, 0});
  auto r = ctl(rod("rod", 2.8, 12, {0, 46, 6}, {106, 0, 0}));
  // Handle along the rod's axis, neck up to the head, head block under the bristle dome.
  TriangleMesh body = cylinder_between({0, 0, -7.2}, {0, 52, 7.7}, 5, 16);
  body.append(cylinder_between({0, 52, 7.7}, {0, 176, 25}, 3.5, 12));
  body.append(box_between({-6, 173, 21}, {6, 203, 29}));
  // The handle comes first: end_with(Toothbrush(), frame) in the paper's App. B.1 gives the
  // handle's frame (the reference's own example targets it).
  return assemble({r, m}, body, 24397.8);
}

Part towel_hanging_env() {
  auto h1 = hook("hook1", 12.5, 120, 1.25, {15, -170, -60}, {30, 0, 90});
  auto h2 = hook("hook2", 12.5, 120, 1.25, {15, 170, -60}, {30, 0, 90});
  // A wall panel (x < -3) with two small plates; each hook's back end joins its plate.
  TriangleMesh body = box_between({-8, -250, -150}, {-3, 250, 50});
  for (const Primitive* h : {&h1, &h2}) {
    const double y = h->frame.pos.y();
    body.append(box_between({-3, y - 20, -90}, {0, y + 20, -30}));
    const Vec3 end = hook_end_near(*h, {0, y, -70});
    body.append(cylinder_between(end, {0, y, end.z()}, 1.25, 8));
  }
  return assemble({h1, h2}, body, 56287.3);
}

Part turnbuckle() {
  auto h1 = hook("hook1", 5.75, 220, 1.5, {1.45, 63.5, -1.45}, {175, 135, 0});
  auto h2 = flex(hook("hook2", 5.75, 220, 1.5, {-2, -63.5, 0}, {355, 90, 0}));
  return assemble({h1, h2}, turnbuckle_body(h1, h2), 2005.2);
}

Part twohole_basket() {
  auto h1 = hook("hook1", 19, 180, 1, {117.5, 0, 178.2}, {270, 0, 270});
  auto h2 = hook("hook2", 19, 180, 1, {117.5, -340, 178.2}, {270, 0, 90});
  auto s = surface("surface", 235, 340, {117.5, -170, 4}, {0, 0, 0});
  // Basket whose end walls carry the two handle holes (the hooks are their upper edges).
  return assemble({h1, h2, s}, open_box({0, -340, 0}, {235, 0, 200}, 3, 3.95), 1102641.0);
}

Part wall_hook() {
  auto h = hook("hook", 12.5, 180, 1.25, {0, -16, -61}, {90, 0, 0});
  auto s = surface("surface", 68, 68, {0, 0, 0}, {90, 270, 0});
  return assemble({h, s}, wall_hook_body({0, 0, 0}), 10593.7);
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
    p.mesh = hanger_body(h1, h2, h3, {0, 0, -110 + v.at("height")}, bar_r);
    for (const Primitive& prim : p.primitives) p.mesh.append(primitive_mesh(prim));
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

// ---------------------------------------------------------------------------------------------
// Registration.

// A fixed part is built once; make() hands out copies.
void add_fixed(PartsLibrary& lib,
               std::string name,
               PC category,
               Part (*build)(),
               std::string description,
               std::vector<std::string> aliases = {}) {
  auto part = std::make_shared<Part>(build());
  part->type_name = name;
  part->description = description;
  part->category = category;
  PartGenerator g;
  g.name = std::move(name);
  g.aliases = std::move(aliases);
  g.description = std::move(description);
  g.category = category;
  g.build = [part = std::shared_ptr<const Part>(part)](const ParamValues&) { return *part; };
  lib.add(std::move(g));
}

}  // namespace

void register_builtin_parts(PartsLibrary& lib) {
  // clang-format off
  add_fixed(lib, "BackSeats", PC::kEnvironment, back_seats,
            "two car back-seat headrest posts (env)");
  add_fixed(lib, "Basket", PC::kHack, basket,
            "wire basket with two side rods and a floor");
  add_fixed(lib, "BasketBase", PC::kOther, basket_base,
            "basket body with two small eyelets");
  add_fixed(lib, "BasketHandle", PC::kOther, basket_handle,
            "basket handle bar with two pivot pins");
  add_fixed(lib, "BinderClip", PC::kHack, binder_clip,
            "binder clip (clip + two wire loops)");
  add_fixed(lib, "BirdFeeder", PC::kEnvironment, bird_feeder,
            "bird feeder with top hanging ring");
  add_fixed(lib, "BirdFeederEnv", PC::kEnvironment, bird_feeder_env,
            "two wall hooks 628 mm apart (env)");
  add_fixed(lib, "Board", PC::kOther, board,
            "board with two faces");
  add_fixed(lib, "BroomRod", PC::kHack, broom_rod,
            "hollow broom handle (tube)");
  add_fixed(lib, "Cable", PC::kEnvironment, cable,
            "charger cable: thin cord (centerline rod) + plug body rod");
  add_fixed(lib, "CarSeat", PC::kEnvironment, car_seat_part,
            "car seat headrest posts (env)");
  add_fixed(lib, "CeilingHook", PC::kOther, ceiling_hook,
            "ceiling swag hook (env)");
  add_fixed(lib, "ClipLight", PC::kEnvironment, clip_light,
            "clip-on reading light (clip)");
  add_fixed(lib, "ClosetRods", PC::kEnvironment, closet_rods,
            "two closet/towel rods 350 mm apart (env)", {"TowelRackRods"});  // paper Fig. 8
  add_fixed(lib, "ClothesClip", PC::kHack, clothes_clip,
            "clothes peg with a small wire ring");
  add_fixed(lib, "CurtainRing", PC::kHack, curtain_ring,
            "curtain ring (split hook)");
  add_fixed(lib, "DiaperCaddy", PC::kEnvironment, diaper_caddy,
            "diaper caddy with two hooks");
  add_fixed(lib, "DoubleHook", PC::kHack, double_hook,
            "small S-hook (two 270° hooks)");
  add_fixed(lib, "DoubleHookMedium", PC::kHack, double_hook_medium,
            "medium S-hook");
  add_fixed(lib, "FabricHanger", PC::kHack, fabric_hanger,
            "fabric clothes hanger (top hook, bar, two shoulder notches)");
  add_fixed(lib, "FlagRod", PC::kHack, flag_rod,
            "flag rod (centerline rod)");
  add_fixed(lib, "HandleBasket", PC::kEnvironment, handle_basket,
            "basket with a handle bar and floor");
  add_fixed(lib, "Hanger", PC::kHack, hanger,
            "wire clothes hanger (top hook, bottom bar, two shoulder notches)");
  add_fixed(lib, "HookEyeConnector", PC::kOther, hook_eye_right,
            "eye hook (same as HookEyeRight; paper Fig. 8 name)");
  add_fixed(lib, "HookEyeLeft", PC::kHack, hook_eye_left,
            "eye hook (screw eye + hook), hook rotated 120°");
  add_fixed(lib, "HookEyeLeftS", PC::kOther, hook_eye_left_s,
            "eye hook variant used in the user study (flexible eye, rigid hook)",
            {"HookEyeLeft5"});  // paper App. B.3
  add_fixed(lib, "HookEyeRight", PC::kHack, hook_eye_right,
            "eye hook, hook rotated 90°");
  add_fixed(lib, "HulaHoop", PC::kEnvironment, hula_hoop,
            "hula hoop (target of the reading nook)");
  add_fixed(lib, "LongTensionRod", PC::kEnvironment, long_tension_rod,
            "2.92 m tension rod (env)");
  add_fixed(lib, "Mug", PC::kEnvironment, mug,
            "mug (handle hook + body tube)");
  add_fixed(lib, "ObstacleRingL", PC::kHack, obstacle_ring_l,
            "large obstacle-course ring");
  add_fixed(lib, "ObstacleRingM", PC::kHack, obstacle_ring_m,
            "medium obstacle-course ring");
  add_fixed(lib, "OpenHandleBasket", PC::kEnvironment, open_handle_basket,
            "basket with open handle");
  add_fixed(lib, "PaperTowelRoll", PC::kEnvironment, paper_towel_roll,
            "paper towel roll (centerline tube)");
  add_fixed(lib, "Pen", PC::kEnvironment, pen,
            "pen (rod + clip edge)");
  add_fixed(lib, "Phone", PC::kEnvironment, phone,
            "phone (edge)");
  add_fixed(lib, "PlasticClip", PC::kHack, plastic_clip,
            "plastic clip standing on two feet (hemispheres)");
  add_fixed(lib, "ReadingRoom", PC::kEnvironment, reading_room,
            "scanned room: ceiling-level rod + small wall pin (env)");
  add_fixed(lib, "RingL", PC::kHack, [] { return ring_part(63.3, 13409.2); },
            "metal ring L");
  add_fixed(lib, "RingLink", PC::kHack, ring_link,
            "toy ring link (two closed hooks)");
  add_fixed(lib, "RingM", PC::kHack, [] { return ring_part(53.3, 11290.8); },
            "metal ring M");
  add_fixed(lib, "RingS", PC::kHack, [] { return ring_part(43.3, 9172.5); },
            "metal ring S");
  add_fixed(lib, "RingXS", PC::kHack, [] { return ring_part(33.3, 7054.1); },
            "metal ring XS");
  add_fixed(lib, "RoundHandleBasket", PC::kEnvironment, round_handle_basket,
            "basket with round handle (hook)");
  add_fixed(lib, "ShowerCurtainRod", PC::kHack, shower_curtain_rod,
            "shower curtain rod");
  add_fixed(lib, "SmallBirdFeederEnv", PC::kEnvironment, small_bird_feeder_env,
            "two wall hooks 490 mm apart (env)");
  add_fixed(lib, "SoapBottle", PC::kEnvironment, soap_bottle,
            "soap bottle (body rod + bottom surface)");
  add_fixed(lib, "SodaCanTab", PC::kHack, soda_can_tab,
            "soda can tab (two centerline rings)");
  add_fixed(lib, "Tack", PC::kOther, tack,
            "push pin");
  add_fixed(lib, "Toothbrush", PC::kEnvironment, toothbrush,
            "toothbrush (head hemisphere + centerline handle rod)");
  add_fixed(lib, "TowelHangingEnv", PC::kEnvironment, towel_hanging_env,
            "wall with two small hooks 340 mm apart (env)");
  add_fixed(lib, "Turnbuckle", PC::kHack, turnbuckle,
            "fixed turnbuckle");
  add_fixed(lib, "TwoholeBasket", PC::kBoth, twohole_basket,
            "basket with two hook holes");
  add_fixed(lib, "WallHook", PC::kHack, wall_hook,
            "adhesive wall hook");
  // clang-format on

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

#include "fabkit/hacks/connection_rules.h"

#include <gtest/gtest.h>

#include <set>
#include <utility>

namespace fabkit::hacks {
namespace {

using PT = PrimitiveType;

TEST(ConnectionRules, TableOneExactly) {
  // Paper Table 1 (upper triangle), and nothing else.
  const std::set<std::pair<PT, PT>> allowed = {{PT::kHook, PT::kHook},
                                               {PT::kHook, PT::kRing},
                                               {PT::kHook, PT::kRod},
                                               {PT::kHook, PT::kTube},
                                               {PT::kRing, PT::kRod},
                                               {PT::kRing, PT::kTube},
                                               {PT::kHemisphere, PT::kSurface},
                                               {PT::kEdge, PT::kClip},
                                               {PT::kRod, PT::kTube},
                                               {PT::kRod, PT::kClip},
                                               {PT::kTube, PT::kTube},
                                               {PT::kTube, PT::kClip},
                                               {PT::kSurface, PT::kSurface}};
  const PT all[] = {PT::kRod,
                    PT::kHook,
                    PT::kRing,
                    PT::kClip,
                    PT::kTube,
                    PT::kEdge,
                    PT::kSurface,
                    PT::kHemisphere};
  for (PT a : all) {
    for (PT b : all) {
      const bool expected = allowed.count({a, b}) || allowed.count({b, a});
      EXPECT_EQ(pair_allowed(a, b), expected) << to_string(a) << "-" << to_string(b);
    }
  }
  EXPECT_EQ(allowed_partners(PT::kHook),
            (std::vector<PT>{PT::kRod, PT::kHook, PT::kRing, PT::kTube}));
}

TEST(ConnectionRules, AlignmentOffsetsAndFlips) {
  const AlignmentOffset rod_hook = alignment_offset(ConnectorKind::kRod, ConnectorKind::kHookFlex);
  EXPECT_EQ(rod_hook.rotation(AlignmentChoice::kDefault), Vec3(180, 0, 90));
  EXPECT_EQ(rod_hook.rotation(AlignmentChoice::kFlip), Vec3(180, 0, -90));
  const AlignmentOffset clip_rod =
      alignment_offset(ConnectorKind::kClip, ConnectorKind::kRodCenterline);
  EXPECT_EQ(clip_rod.rotation(AlignmentChoice::kFlip), Vec3(0, 0, 0));
  const AlignmentOffset edge_clip = alignment_offset(ConnectorKind::kEdge, ConnectorKind::kClip);
  EXPECT_EQ(edge_clip.rotation(AlignmentChoice::kFlip), Vec3(0, 90, 90));
  const AlignmentOffset surf = alignment_offset(ConnectorKind::kSurface, ConnectorKind::kSurface);
  EXPECT_EQ(surf.rotation(AlignmentChoice::kFlip), Vec3(180, 0, 0));
  // Centre-line variants have their own entries; a missing pair aligns with the identity.
  EXPECT_EQ(alignment_offset(ConnectorKind::kRodCenterline, ConnectorKind::kRingCenterline).rot,
            Vec3(0, 0, 90));
  EXPECT_EQ(alignment_offset(ConnectorKind::kRod, ConnectorKind::kTubeCenterline).rot,
            Vec3(0, 0, 0));
  const AlignmentOffset hemi =
      alignment_offset(ConnectorKind::kSurface, ConnectorKind::kHemisphere);
  EXPECT_EQ(hemi.rot, Vec3(0, 0, 0));
  EXPECT_FALSE(hemi.flippable());
}

// A connection means one thing whichever of its sides came first: the offset read one way is
// the inverse of the offset read the other, for every pair of kinds and either alignment (the
// table's own two directions are not: Tube/Hook is a quarter turn both ways).
TEST(ConnectionRules, AlignmentReadEitherWayIsOneConnection) {
  const ConnectorKind kinds[] = {ConnectorKind::kRod,
                                 ConnectorKind::kRodCenterline,
                                 ConnectorKind::kHook,
                                 ConnectorKind::kHookFlex,
                                 ConnectorKind::kRing,
                                 ConnectorKind::kRingFlex,
                                 ConnectorKind::kRingCenterline,
                                 ConnectorKind::kTube,
                                 ConnectorKind::kTubeCenterline,
                                 ConnectorKind::kClip,
                                 ConnectorKind::kEdge,
                                 ConnectorKind::kSurface,
                                 ConnectorKind::kHemisphere};
  int not_inverse_in_table = 0;
  for (ConnectorKind a : kinds) {
    for (ConnectorKind b : kinds) {
      for (AlignmentChoice choice : {AlignmentChoice::kDefault, AlignmentChoice::kFlip}) {
        const Mat4 ab = alignment_matrix(a, b, choice);
        const Mat4 ba = alignment_matrix(b, a, choice);
        EXPECT_LT((ab * ba - Mat4::Identity()).cwiseAbs().maxCoeff(), 1e-12)
            << to_string(a) << "_" << to_string(b) << " " << to_string(choice);
        // Each offset is a rotation.
        EXPECT_LT(
            (ab.topLeftCorner<3, 3>().transpose() * ab.topLeftCorner<3, 3>() - Mat3::Identity())
                .cwiseAbs()
                .maxCoeff(),
            1e-12);
        const Mat4 table =
            alignment_offset(a, b).matrix(choice) * alignment_offset(b, a).matrix(choice);
        if ((table - Mat4::Identity()).cwiseAbs().maxCoeff() > 1e-9) ++not_inverse_in_table;
      }
    }
  }
  // The table itself has pairs whose two directions disagree (why alignment_matrix exists).
  EXPECT_GT(not_inverse_in_table, 0);
  // Where the table's directions agree, the offset is the table's row as it stands.
  EXPECT_EQ(alignment_matrix(ConnectorKind::kHook, ConnectorKind::kRod, AlignmentChoice::kDefault),
            alignment_offset(ConnectorKind::kHook, ConnectorKind::kRod)
                .matrix(AlignmentChoice::kDefault));
  // Tube/Hook: read hook first, whichever side the hook is on.
  EXPECT_EQ(alignment_matrix(ConnectorKind::kHook, ConnectorKind::kTube, AlignmentChoice::kDefault),
            alignment_offset(ConnectorKind::kHook, ConnectorKind::kTube)
                .matrix(AlignmentChoice::kDefault));
}

Primitive rod(double r, double l, bool open = true) {
  PrimitiveShape s;
  s.radius = r;
  s.length = l;
  Primitive p = Primitive::make("rod", PT::kRod, s);
  p.is_open = p.open_for_connect = open;
  return p;
}

Primitive hook(double r, double th, bool open = true) {
  PrimitiveShape s;
  s.arc_radius = r;
  s.arc_angle = 270;
  s.thickness = th;
  Primitive p = Primitive::make("hook1", PT::kHook, s);
  p.is_open = p.open_for_connect = open;
  return p;
}

std::string check(const Primitive& a,
                  const std::string& la,
                  const Primitive& b,
                  const std::string& lb,
                  std::vector<double> avail_a = {}) {
  Diagnostics d;
  PrimitiveInUse ua{&a, la, std::move(avail_a)};
  PrimitiveInUse ub{&b, lb, {}};
  check_compatibility(ua, ub, d);
  return d.format();
}

TEST(ConnectionRules, HookOpeningSmallerThanRodRadius) {
  EXPECT_EQ(check(rod(12.7, 2920), "Rods.rod1", hook(11.6, 2), "DoubleHook#2.hook1"),
            "error: DoubleHook#2.hook1: hook opening 9.6 mm is smaller than rod radius 12.7 mm "
            "(Rods.rod1)\n");
  EXPECT_EQ(check(rod(5, 500), "Door.rod", hook(11.6, 2), "DoubleHook.hook1"), "");
}

// The opening is what is free inside the wire (arc radius less wire radius), not the arc radius:
// a 10.5 mm rod does not fit an 11.6 mm arc of 2 mm wire (9.6 mm free), a 9.5 mm rod does.
TEST(ConnectionRules, OpeningIsTheFreeRadiusInsideTheWire) {
  EXPECT_EQ(check(rod(10.5, 500), "Rod.rod", hook(11.6, 2), "S.hook1"),
            "error: S.hook1: hook opening 9.6 mm is smaller than rod radius 10.5 mm (Rod.rod)\n");
  EXPECT_EQ(check(rod(9.5, 500), "Rod.rod", hook(11.6, 2), "S.hook1"), "");
  // Two hooks: each wire must fit in the other's opening.
  EXPECT_NE(check(hook(5, 2), "A.hook1", hook(20, 3.5), "B.hook1")
                .find("A.hook1: hook opening 3.0 mm is smaller than wire radius 3.5 mm (B.hook1)"),
            std::string::npos);
  EXPECT_EQ(check(hook(6, 2), "A.hook1", hook(20, 3.5), "B.hook1"), "");
}

TEST(ConnectionRules, BothClosed) {
  const std::string msg = check(rod(3, 72, false), "Basket.rod1", hook(30.5, 6, false), "Mug.hook");
  EXPECT_NE(msg.find("Basket.rod1 and Mug.hook are both closed"), std::string::npos) << msg;
}

TEST(ConnectionRules, RingNeedsAnOpenRod) {
  PrimitiveShape s;
  s.arc_radius = 14.82;
  s.thickness = 4.5;
  const Primitive ring = Primitive::make("ring", PT::kRing, s);
  const std::string msg = check(rod(3, 72, false), "Basket.rod1", ring, "HookEye.ring");
  EXPECT_NE(msg.find("Basket.rod1 is closed at its ends, so HookEye.ring (ring) cannot be slid "
                     "onto it"),
            std::string::npos)
      << msg;
}

TEST(ConnectionRules, NoSpaceLeftOnRod) {
  const std::string msg =
      check(rod(2.5, 20), "Room.rod2", hook(5.75, 1.5), "Turnbuckle.hook1", {2});
  EXPECT_NE(msg.find("Room.rod2: only 2.0 mm of its 20.0 mm length is still free, but "
                     "Turnbuckle.hook1 needs 3.0 mm"),
            std::string::npos)
      << msg;
}

TEST(ConnectionRules, ClipOpeningAgainstRodDiameter) {
  PrimitiveShape s;
  s.width = 30;
  s.height = 30;
  s.thickness = 1;
  s.dist = 13.5;
  s.open_gap = 13.5;
  const Primitive clip = Primitive::make("clip", PT::kClip, s);
  EXPECT_EQ(check(rod(6.5, 385), "Hanger.rod", clip, "Light.clip"), "");
  const std::string msg = check(rod(10, 385), "Hanger.rod", clip, "Light.clip");
  EXPECT_NE(msg.find("Light.clip: clip opening 13.5 mm is smaller than rod diameter 20.0 mm"),
            std::string::npos)
      << msg;
}

TEST(ConnectionRules, CriticalDimensionBookkeeping) {
  const Primitive r = rod(5, 100);
  const Primitive h = hook(11.6, 2);
  EXPECT_EQ(consume_critical_dim(r, {100}, h, {}), std::vector<double>{96});
  PrimitiveShape surf;
  surf.width = 400;
  surf.length = 400;
  const Primitive s = Primitive::make("s", PT::kSurface, surf);
  PrimitiveShape hs;
  hs.radius = 8.5;
  const Primitive hemi = Primitive::make("h", PT::kHemisphere, hs);
  EXPECT_EQ(consume_critical_dim(s, {400, 400}, hemi, {}), (std::vector<double>{383, 383}));
  // Hooks have no critical dimension: nothing to consume.
  EXPECT_TRUE(consume_critical_dim(h, {}, r, {100}).empty());
}

}  // namespace
}  // namespace fabkit::hacks

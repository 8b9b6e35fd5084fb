#include <gtest/gtest.h>

#include "fabkit/flatpack/diagnostic_codes.h"
#include "fabkit/flatpack/joint_widths.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

using test::check_yaml;

// Appendix A with fabkit's convention (Δ removed per side of every drawn line).
TEST(JointWidths, FingerIsDeltaWiderThanItsDentOnceCut) {
  for (double kerf : {0.0, 0.08, 0.15, 0.3}) {
    for (double interference : {0.0, 0.05, 0.1, 0.2}) {
      for (double nominal : {6.0, 9.0, 18.0}) {
        const DrawnWidths w = finger_and_opening(nominal, kerf, interference);
        EXPECT_NEAR(
            w.finger_mm, w.opening_mm + 4 * kerf + interference, 1e-12);  // w_f = w_d + 4Δ + δ
        EXPECT_NEAR(cut_solid_width(w.finger_mm, kerf) - cut_opening_width(w.opening_mm, kerf),
                    interference,
                    1e-12);
      }
    }
  }
}

TEST(JointWidths, SlotComesOutDeltaNarrowerThanTheBoard) {
  for (double t : {3.0, 6.0, 12.0}) {
    for (double kerf : {0.0, 0.1, 0.2}) {
      for (double interference : {0.0, 0.1}) {
        const double w = slot_width(t, kerf, interference);
        EXPECT_NEAR(w, t - 2 * kerf - interference, 1e-12);
        EXPECT_NEAR(cut_opening_width(w, kerf), t - interference, 1e-12);
      }
    }
  }
}

// A minimal pair for each joint kind, checked on the cut outlines.
std::string pair(const std::string& b_type,
                 const std::string& connection,
                 double t = 3,
                 double kerf = 0.1,
                 double delta = 0.1) {
  return "fabkit: flatpack/1\nmaterial: {thickness: " + std::to_string(t) +
         ", kerf: " + std::to_string(kerf) + ", interference: " + std::to_string(delta) +
         "}\ncomponents:\n  - {name: A, type: Rectangle, l: 60, w: 40}\n  - " + b_type +
         "\nconnections:\n  - " + connection + "\n";
}

TEST(Joints, EdgeToEdgeIsFingerFingerWithComplementaryFingers) {
  const Analysis a = check_yaml(pair("{name: B, type: Rectangle, l: 60, w: 40}",
                                     "{connect: [A.t, B.b], rotation: [90, 0, 0]}"));
  ASSERT_EQ(a.joints.size(), 1u) << a.diagnostics.format();
  const Joint& j = a.joints[0];
  EXPECT_EQ(j.kind, JointKind::kFingerFinger);
  EXPECT_FALSE(j.automatic());
  EXPECT_NEAR(j.length_mm, 60, 1e-9);
  // Usable 60 − 2·3 = 54 mm at ~9 mm: 7 units (A 4 fingers, B 3), each 54/7 mm.
  EXPECT_EQ(j.fingers, 7);
  EXPECT_NEAR(j.finger_width_mm, 54.0 / 7, 1e-9);
  // Area: A loses its 1.5 mm band and gains 4 fingers 3 mm long, each widened by 2Δ + δ/2.
  const double w = 54.0 / 7, widen = 2 * 0.1 + 0.1 / 2;
  EXPECT_NEAR(area(a.pieces[0].cut), 60 * 40 - 60 * 1.5 + 4 * (w + widen) * 3, 1e-3);
  EXPECT_NEAR(area(a.pieces[1].cut), 60 * 40 - 60 * 1.5 + 3 * (w + widen) * 3, 1e-3);
}

TEST(Joints, EdgeOnFaceIsFingerHoleWithHolesNarrowerByTheFit) {
  const Analysis a =
      check_yaml(pair("{name: B, type: Rectangle, l: 60, w: 80}",
                      "{connect: [A.t, B.b], offset: [0, 30, 0], rotation: [90, 0, 0]}"));
  ASSERT_EQ(a.joints.size(), 1u) << a.diagnostics.format();
  EXPECT_EQ(a.joints[0].kind, JointKind::kFingerHole);
  EXPECT_EQ(a.pieces[a.joints[0].piece_a].name, "A");  // fingers on the edge piece
  const Piece& b = a.pieces[1];
  ASSERT_EQ(b.cut.size(), 1u);
  const int fingers = a.joints[0].fingers;
  ASSERT_EQ(static_cast<int>(b.cut[0].holes.size()), fingers);
  const double w = a.joints[0].finger_width_mm;
  // Each hole: (w − 2Δ − δ/2) long, one board (3 mm) wide; each finger (w + 2Δ + δ/2).
  for (const Ring& h : b.cut[0].holes) EXPECT_NEAR(std::abs(signed_area(h)), (w - 0.25) * 3, 1e-3);
  EXPECT_NEAR((w + 0.25) - (w - 0.25), 4 * 0.1 + 0.1, 1e-12);
}

TEST(Joints, CrossingFacesAreSlotSlotWithHalfLengthSlots) {
  // B stands in the plane x = 30 across A's right half and past A's top edge: a half lap.
  const Analysis c = check_yaml(
      "fabkit: flatpack/1\nmaterial: {thickness: 3, kerf: 0.1, interference: 0.1}\ncomponents:\n"
      "  - {name: A, type: Rectangle, l: 60, w: 40}\n  - {name: B, type: Rectangle, l: 40, w: 40}\n"
      "connections:\n  - {connect: [B.b, A.r], offset: [20, 30, -20], rotation: [90, 0, 0]}\n");
  ASSERT_EQ(c.joints.size(), 1u) << c.diagnostics.format();
  const Joint& j = c.joints[0];
  EXPECT_EQ(j.kind, JointKind::kSlotSlot);
  EXPECT_NEAR(j.length_mm, 20, 1e-6);
  // Each piece loses a slot of half the length × (3 − 2Δ − δ), open at its own edge.
  const double ws = 3 - 0.2 - 0.1;
  EXPECT_NEAR(area(c.pieces[0].cut), 60 * 40 - ws * 10, 1e-3);
  EXPECT_NEAR(area(c.pieces[1].cut), 40 * 40 - ws * 10, 1e-3);
  EXPECT_EQ(std::abs(j.slot_open_a), 1);
  EXPECT_EQ(j.slot_open_b, -j.slot_open_a);
}

// Item 6: a slot fabkit draws comes out of the cutter δ narrower than the board it takes, so the
// board presses in. Measured across the slot in the cut outline of a crossing pair, for several
// thicknesses, kerfs and interferences.
TEST(Joints, CutSlotIsTheBoardThicknessLessTheInterference) {
  for (double t : {3.0, 6.0}) {
    for (double kerf : {0.05, 0.2}) {
      for (double fit : {0.0, 0.1}) {
        SCOPED_TRACE(testing::Message() << "t " << t << " Δ " << kerf << " δ " << fit);
        const Analysis c = check_yaml(
            "fabkit: flatpack/1\nmaterial: {thickness: " + std::to_string(t) +
            ", kerf: " + std::to_string(kerf) + ", interference: " + std::to_string(fit) +
            "}\ncomponents:\n  - {name: A, type: Rectangle, l: 60, w: 40}\n"
            "  - {name: B, type: Rectangle, l: 40, w: 40}\n"
            "connections:\n  - {connect: [B.b, A.r], offset: [20, 30, -20], rotation: [90, 0, "
            "0]}\n");
        ASSERT_EQ(c.joints.size(), 1u) << c.diagnostics.format();
        const Joint& j = c.joints[0];
        ASSERT_EQ(j.kind, JointKind::kSlotSlot);
        for (int side = 0; side < 2; ++side) {
          const Piece& p = c.pieces[static_cast<std::size_t>(side == 0 ? j.piece_a : j.piece_b)];
          const int open = side == 0 ? j.slot_open_a : j.slot_open_b;
          ASSERT_EQ(std::abs(open), 1);
          // A point a quarter of the joint in from the slot's open end, in the piece's frame,
          // and the direction across the slot.
          const Vec3 along = (j.end - j.start).normalized();
          const Vec3 at = open > 0 ? Vec3(j.start + 0.25 * j.length_mm * along)
                                   : Vec3(j.end - 0.25 * j.length_mm * along);
          const Mat4 inv = rigid_inverse(p.frame);
          const Vec3 at_local = inv.topLeftCorner<3, 3>() * at + inv.topRightCorner<3, 1>();
          const Vec3 u = inv.topLeftCorner<3, 3>() * along;
          const Vec2 across(-u.y(), u.x());
          const Vec2 o = Vec2(at_local.x(), at_local.y()) - 20 * across;
          const auto stretches = classify_line(p.cut[0], o, across);
          ASSERT_EQ(stretches.size(), 2u);
          const double slot = stretches[1].s0 - stretches[0].s1;
          EXPECT_NEAR(slot, t - 2 * kerf - fit, 1e-6);                // drawn: w_m − 2Δ − δ
          EXPECT_NEAR(cut_opening_width(slot, kerf), t - fit, 1e-6);  // cut: the board − δ
          EXPECT_LT(stretches[0].s1, 20);                             // the point is in it
          EXPECT_GT(stretches[1].s0, 20);
        }
      }
    }
  }
}

TEST(Joints, CoplanarTouchingComponentsMerge) {
  const Analysis a = check_yaml(
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 60, w: 40}\n"
      "  - {name: B, type: Rectangle, l: 60, w: 20}\nconnections:\n  - {connect: [B.b, A.t]}\n");
  ASSERT_EQ(a.pieces.size(), 1u) << a.diagnostics.format();
  EXPECT_NEAR(area(a.pieces[0].cut), 60 * 60, 1e-3);
  EXPECT_EQ(a.merging_connections.size(), 1u);
  EXPECT_EQ(a.graph_joints(), 1);
}

TEST(Joints, NonRightAnglesAndShortJointsWarn) {
  const Analysis a = check_yaml(pair("{name: B, type: Rectangle, l: 60, w: 40}",
                                     "{connect: [A.t, B.b], rotation: [60, 0, 0]}"));
  EXPECT_TRUE(test::has_code(a.diagnostics, codes::kNotPerpendicular)) << a.diagnostics.format();
  EXPECT_NE(a.diagnostics.format().find("meets at 60.0°"), std::string::npos)
      << a.diagnostics.format();
  const Analysis b = check_yaml(
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 8, w: 40}\n  - {name: B, "
      "type: Rectangle, l: 8, w: 40}\n"
      "connections:\n  - {connect: [A.t, B.b], rotation: [90, 0, 0]}\n");
  EXPECT_TRUE(test::has_code(b.diagnostics, codes::kJointFit)) << b.diagnostics.format();
}

TEST(Joints, DogbonesRemoveMaterialAtInnerCorners) {
  const std::string base = pair("{name: B, type: Rectangle, l: 60, w: 40}",
                                "{connect: [A.t, B.b], rotation: [90, 0, 0]}");
  const Analysis plain = check_yaml(base);
  const Analysis bones = check_yaml(base + "joints: {dogbone: 3}\n");
  EXPECT_LT(area(bones.pieces[0].cut), area(plain.pieces[0].cut) - 1.0);
}

}  // namespace
}  // namespace fabkit::flatpack

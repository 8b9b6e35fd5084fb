#pragma once
/// What a flat-pack design becomes once solved and placed: components with their dimensions
/// and world frames, pieces (components after coplanar merging, paper Alg. 2 lines 1–7) with
/// their cut outlines, and joints (Alg. 2 lines 8–28, Appendix A).
///
/// Frames: world is mm with z up; a piece's frame maps its 2D outline (z = 0, the mid-plane)
/// into the world; its board spans z ∈ [−t/2, t/2] in that frame.

#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/frame.h"
#include "fabkit/core/polygon2d.h"
#include "fabkit/flatpack/design.h"

namespace fabkit::flatpack {

/// A component instance after solving and placement (Alg. 1).
struct PlacedComponent {
  std::string name;  ///< full name: "desk.top" inside a sub-design "desk"
  std::string type;
  std::map<std::string, double> values;  ///< its parameters, solved
  ComponentShape shape;                  ///< in its own frame (cutouts applied)
  Material material;
  Mat4 frame = Mat4::Identity();  ///< component frame → world
  int piece = -1;                 ///< index into Analysis::pieces
};

enum class JointKind { kFingerFinger, kFingerHole, kSlotSlot };
std::string_view to_string(JointKind kind);

/// One intersection of two pieces and the joint cut there.
struct Joint {
  int id = 0;  ///< 1-based, in detection order
  JointKind kind = JointKind::kFingerFinger;
  int piece_a = -1;  ///< finger piece for finger–hole; the one slotted from its edge first
  int piece_b = -1;
  Vec3 start = Vec3::Zero();  ///< the intersection segment in the world, mm
  Vec3 end = Vec3::Zero();
  double length_mm = 0;
  double angle_deg = 90;       ///< between the two boards
  int connection = -1;         ///< index of the user connection it implements; -1: automatic
  int fingers = 0;             ///< fingers (finger–finger: both pieces' together) or slots
  double finger_width_mm = 0;  ///< nominal (centre-line) finger width
  /// World unit vectors from the segment into each piece's material, in the piece's plane.
  Vec3 inward_a = Vec3::Zero();
  Vec3 inward_b = Vec3::Zero();
  /// Slot–slot: where each piece's slot opens (+1 at `start`, -1 at `end`; 2: a closed slot
  /// the other piece passes through; 0: no slot).
  int slot_open_a = 0;
  int slot_open_b = 0;
  bool automatic() const { return connection < 0; }
};

/// A planar piece to cut: one component, or several coplanar ones merged.
struct Piece {
  std::string name;               ///< the first component's name
  std::vector<int> components;    ///< indices into Analysis::components
  Mat4 frame = Mat4::Identity();  ///< piece frame → world (the first component's frame)
  Material material;
  Polygon2d outline;  ///< before joints, piece frame
  Region2d cut;       ///< after joints (fingers, dents, holes, slots, dog-bones), piece frame
  /// Where to engrave assembly marks: text and position in the piece frame, with rotation.
  struct Mark {
    std::string text;
    Vec2 position = Vec2::Zero();
    double rotation_deg = 0;
  };
  std::vector<Mark> marks;
};

/// One step of the press-fit order.
struct AssemblyStep {
  int piece = -1;
  Vec3 direction = Vec3::Zero();  ///< the piece slides in along this (world, unit)
  std::vector<int> joints;        ///< joints it closes (ids)
  /// 0, or a sub-assembly number: consecutive steps with the same number are put together off
  /// the furniture first, and the sub-assembly then goes in along its last step's direction.
  int group = 0;
};

}  // namespace fabkit::flatpack

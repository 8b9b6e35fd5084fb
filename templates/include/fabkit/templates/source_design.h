#pragma once
/// A source design: an expert's fabricable model, detailed down to the screws, that the
/// database turns into a template (paper §3.1). Every part references a catalog item and is an
/// axis-aligned box; connecting parts (screws, brackets, hinges, slides) are marked apart from
/// the principal parts (shelves, legs, wheels); articulations describe doors, drawers and wheels.

#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/box.h"

namespace fabkit::templates {

/// Principal parts are what the user designs with; connecting parts hold them together and
/// are found automatically when parts are combined (paper §3.1, §4.5).
enum class PartRole { kPrincipal, kConnecting };
/// "principal", "connecting".
std::string_view to_string(PartRole r);

struct DesignPart {
  std::string name;  ///< unique in the design
  std::string item;  ///< catalog item id
  Box box;           ///< mm, world frame (z up, floor at z = 0)
  PartRole role = PartRole::kPrincipal;
  std::string group;  ///< sub-assembly path, '/'-separated ("base/legs"); "" = the design itself
  SourceLocation where;
};

/// The joint types of the paper's articulations.
enum class JointType { kPrismatic, kHinge, kBall };
/// "prismatic", "hinge", "ball".
std::string_view to_string(JointType t);

/// A moving sub-assembly: a drawer on slides, a door on hinges, a wheel on its axle. The design
/// holds it in one rest pose (the lower limit); the other limit is the second rest pose.
struct Articulation {
  std::string name;
  JointType type = JointType::kHinge;
  std::vector<std::string> parts;  ///< moving parts (names), already expanded from groups
  int axis = 2;                    ///< world axis of the hinge axis or slide direction
  int direction = 1;               ///< +1 or -1 along `axis` (slide direction, rotation sense)
  Vec3 pivot = Vec3::Zero();       ///< a point on the hinge axis, mm (hinges)
  double lower = 0;                ///< the design's pose: mm (prismatic) or degrees (hinge)
  double upper = 0;                ///< the other rest pose
  SourceLocation where;
};

struct SourceDesign {
  std::string name;      ///< database key ("dining_table")
  std::string title;     ///< "Dining table"
  std::string category;  ///< "table", "storage", "seating", "vehicle", ...
  std::string description;
  std::vector<DesignPart> parts;
  std::vector<Articulation> articulations;
  std::string file;  ///< where it was read from (for messages)

  const DesignPart* find(std::string_view part) const;
};

}  // namespace fabkit::templates

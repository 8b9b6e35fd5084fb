#pragma once
/// A flat-pack furniture design (paper §4.1–4.2, the model M = ({components}, {connections},
/// {constraints}, {interfaces})): parameters, components, constraints binding their dimensions
/// to expressions, connections between named edges, materials, and what it exports when used
/// as a component of a larger design.

#include <array>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/nesting.h"
#include "fabkit/flatpack/component.h"

namespace fabkit::flatpack {

/// An expression over parameters and component dimensions ("2*l2 + 10", "A.w"), parsed by
/// muParser; names may contain '.' (component.parameter). Trigonometry: sin/cos/tan take
/// radians, sind/cosd/tand degrees.
struct Expression {
  std::string text;
  SourceLocation where;
};

struct DesignParameter {
  std::string name;
  ParamKind kind = ParamKind::kLength;
  /// The default; applies when no constraint determines the parameter.
  std::optional<double> value;
  bool meta = false;  ///< one of the few parameters an expert exposes (paper §4.1.1)
  std::string description;
  SourceLocation where;
};

/// A hole cut into a component, in the component's frame (mm).
struct Cutout {
  enum class Shape { kRectangle, kCircle };
  Shape shape = Shape::kRectangle;
  std::array<Expression, 2> at;    ///< lower-left corner (rectangle) or centre (circle)
  std::array<Expression, 2> size;  ///< width, height; a circle uses size[0] as its diameter
  SourceLocation where;
};

struct ComponentUse {
  std::string name;
  std::string type;                          ///< a built-in type or a design in `Design::library`
  std::map<std::string, Expression> params;  ///< inline constraints `name.param = expr`
  std::vector<Vec2> points;                  ///< Polygon only
  std::vector<std::string> edge_names;       ///< Polygon only (default e0, e1, ...)
  std::vector<Cutout> cutouts;
  std::string material;  ///< empty: the design's material
  SourceLocation where;
};

struct Constraint {
  Expression lhs;
  Expression rhs;
  SourceLocation where;
  std::string text() const { return lhs.text + " = " + rhs.text; }
};

enum class Alignment { kFrontFront, kFrontBack };
std::string_view to_string(Alignment a);
std::optional<Alignment> alignment_from_string(std::string_view text);

/// The paper's 5-tuple Connection((A, a), (B, b), alignment, offset, rotation): A's edge `a`
/// is laid on B's edge `b`, midpoints together (front-front: A beside B in B's plane, same
/// front; front-back: A flipped over the edge). Then A moves by `offset` (mm, in B's edge frame:
/// x along b, y into B, z along B's front normal) and turns by `rotation` (degrees about A's own
/// edge axes x, y, z in that order; +90 about x folds A about the edge towards its front).
struct Connection {
  std::string name;  ///< "c1" unless named
  std::string a_component, a_edge, b_component, b_edge;
  Alignment alignment = Alignment::kFrontFront;
  std::array<Expression, 3> offset;
  std::array<Expression, 3> rotation;
  /// `joint: none`: the connection only places A (a lid resting on a box); no joint is expected
  /// and none is warned about when the pieces do not meet.
  bool places_only = false;
  SourceLocation where;
  std::string text() const;  ///< "A.t → B.b"
};

/// A sheet material and how the cutter treats it (paper Appendix A).
struct Material {
  std::string name = "plywood";
  double thickness_mm = 3;
  /// Δ: material the cutter removes on each side of a drawn line (half the kerf width), mm.
  double kerf_mm = 0.1;
  /// δ: how much wider a cut finger is than its cut dent (press fit), mm.
  double interference_mm = 0.1;
};

/// How joints are drawn (defaults scale with the material's thickness when 0).
struct JointOptions {
  double finger_width_mm = 0;  ///< target finger width; 0: 3 × thickness
  double end_margin_mm = 0;    ///< no fingers this close to a joint's ends; 0: the thickness
  double dogbone_tool_mm = 0;  ///< > 0: dog-bone inner corners for a router bit of this diameter
  double angle_tolerance_deg = 0.5;  ///< pieces within this of 90° count as perpendicular
};

/// Labels engraved on pieces.
struct LabelOptions {
  bool piece_names = true;     ///< the piece's name on its face
  bool assembly_marks = true;  ///< at each joint, the name of the piece that goes there
  double height_mm = 0;        ///< 0: about the thickness × 1.5, at least 3 mm
};

struct Design {
  std::string name;
  std::string description;
  std::filesystem::path source;  ///< the file it was read from (empty for text)
  std::vector<DesignParameter> parameters;
  std::vector<ComponentUse> components;
  std::vector<Constraint> constraints;
  std::vector<Connection> connections;
  /// Exported interfaces for composition: name → "component.edge" (or a sub-design's export).
  std::map<std::string, std::string> interfaces;
  Material material;                ///< the default material
  std::vector<Material> materials;  ///< further named materials components may pick
  JointOptions joints;
  LabelOptions labels;
  NestingOptions sheet;
  /// Designs used as component types ("uses:"), by type name.
  std::map<std::string, std::shared_ptr<const Design>> library;
};

}  // namespace fabkit::flatpack

#pragma once
/// Parameterised planar components (paper §4.1.1): a registry of generators, each with a typed
/// parameter schema, named edges ("interfaces") and its own constraints.
///
/// A component is a polygon in its own frame (mm, the xy-plane; its front faces +z, so the
/// outer ring is counter-clockwise seen from the front). Edge i runs from outer vertex i to
/// vertex i+1. The polygon is the piece's mid-plane: the board spans ±thickness/2 about it.

#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/polygon2d.h"

namespace fabkit::flatpack {

enum class ParamKind {
  kLength,  ///< mm
  kAngle,   ///< degrees
  kCount,   ///< a whole number
  kNumber,  ///< dimensionless
};
std::string_view to_string(ParamKind kind);
std::optional<ParamKind> param_kind_from_string(std::string_view text);

/// One parameter of a component's schema.
struct ParamSpec {
  std::string name;
  ParamKind kind = ParamKind::kLength;
  std::string description;
  std::optional<double> default_value;  ///< used only when no constraint determines it
  double min = -std::numeric_limits<double>::infinity();
  bool exclusive_min = false;  ///< value must be > min (sizes)
  double max = std::numeric_limits<double>::infinity();
};

/// A named edge of a component: from outer vertex `vertex` to the next.
struct NamedEdge {
  std::string name;
  int vertex = 0;
};

/// A component's geometry for given parameter values.
struct ComponentShape {
  Polygon2d polygon;
  std::vector<NamedEdge> edges;
};

/// A component generator (Rectangle, Trapezoid, ...).
struct ComponentType {
  std::string name;
  std::string description;
  std::vector<ParamSpec> params;
  /// The component's own constraints, `lhs = rhs` in its parameters ("w", "l" for a square).
  std::vector<std::pair<std::string, std::string>> constraints;
  std::vector<std::string> edge_names;  ///< for docs and did-you-mean; Polygon: e0, e1, ...
  /// The shape for `values` (every parameter set); nullopt with `error` saying which value
  /// makes no shape ("notch width nl = 120 mm is not less than the width l = 100 mm").
  std::function<std::optional<ComponentShape>(const std::map<std::string, double>& values,
                                              const std::vector<Vec2>& points,
                                              std::string& error)>
      generate;
  /// Free polygons take a point list instead of parameters.
  bool takes_points = false;

  const ParamSpec* param(std::string_view name) const;
};

/// The built-in component types, by name.
class ComponentLibrary {
 public:
  /// Rectangle, Square, RightTriangle, IsoscelesTriangle, Trapezoid, RegularPolygon, LShape,
  /// UShape, Disc and Polygon.
  static const ComponentLibrary& builtin();
  const ComponentType* find(std::string_view name) const;
  std::vector<std::string> names() const;
  void add(ComponentType type);

 private:
  std::vector<ComponentType> types_;
};

}  // namespace fabkit::flatpack

// The built-in component generators.
#include <fmt/format.h>

#include <cmath>

#include "fabkit/flatpack/component.h"
#include "fabkit/flatpack/design.h"
#include "fabkit/flatpack/diagnostic_codes.h"

namespace fabkit::flatpack {

std::span<const DiagnosticCode> flatpack_codes() {
  static constexpr std::array kAll = {codes::kUnknownComponent,
                                      codes::kUnknownEdge,
                                      codes::kBadExpression,
                                      codes::kUnderConstrained,
                                      codes::kOverConstrained,
                                      codes::kBadShape,
                                      codes::kCycleMismatch,
                                      codes::kNotConnected,
                                      codes::kConnectionMakesNoJoint,
                                      codes::kNotPerpendicular,
                                      codes::kJointFit,
                                      codes::kOverlap,
                                      codes::kNotAssemblable};
  return kAll;
}

std::string_view to_string(ParamKind kind) {
  switch (kind) {
    case ParamKind::kLength:
      return "length";
    case ParamKind::kAngle:
      return "angle";
    case ParamKind::kCount:
      return "count";
    case ParamKind::kNumber:
      return "number";
  }
  return "length";
}

std::optional<ParamKind> param_kind_from_string(std::string_view text) {
  for (ParamKind k :
       {ParamKind::kLength, ParamKind::kAngle, ParamKind::kCount, ParamKind::kNumber}) {
    if (to_string(k) == text) return k;
  }
  return std::nullopt;
}

std::string_view to_string(Alignment a) {
  return a == Alignment::kFrontFront ? "front-front" : "front-back";
}

std::optional<Alignment> alignment_from_string(std::string_view text) {
  if (text == "front-front") return Alignment::kFrontFront;
  if (text == "front-back") return Alignment::kFrontBack;
  return std::nullopt;
}

std::string Connection::text() const {
  return fmt::format("{}.{} → {}.{}", a_component, a_edge, b_component, b_edge);
}

const ParamSpec* ComponentType::param(std::string_view n) const {
  for (const ParamSpec& p : params) {
    if (p.name == n) return &p;
  }
  return nullptr;
}

const ComponentType* ComponentLibrary::find(std::string_view name) const {
  for (const ComponentType& t : types_) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::vector<std::string> ComponentLibrary::names() const {
  std::vector<std::string> out;
  for (const ComponentType& t : types_) out.push_back(t.name);
  return out;
}

void ComponentLibrary::add(ComponentType type) {
  types_.push_back(std::move(type));
}

namespace {

using Values = std::map<std::string, double>;

ParamSpec length(std::string name, std::string description) {
  return ParamSpec{
      std::move(name), ParamKind::kLength, std::move(description), std::nullopt, 0, true};
}

ComponentShape shape(Ring outer, std::vector<std::string> edge_names) {
  ComponentShape s;
  s.polygon.outer = std::move(outer);
  for (std::size_t i = 0; i < edge_names.size(); ++i)
    s.edges.push_back({edge_names[i], static_cast<int>(i)});
  return s;
}

ComponentType rectangle_type(std::string name, std::string description) {
  ComponentType t;
  t.name = std::move(name);
  t.description = std::move(description);
  t.params = {length("l", "length along x (edges b and t), mm"),
              length("w", "width along y (edges r and l), mm")};
  t.edge_names = {"b", "r", "t", "l"};
  t.generate =
      [](const Values& v, const std::vector<Vec2>&, std::string&) -> std::optional<ComponentShape> {
    const double l = v.at("l"), w = v.at("w");
    return shape({{0, 0}, {l, 0}, {l, w}, {0, w}}, {"b", "r", "t", "l"});
  };
  return t;
}

ComponentLibrary make_builtin() {
  ComponentLibrary lib;
  lib.add(rectangle_type("Rectangle", "a rectangle l × w; edges b (bottom), r, t (top), l"));
  {
    ComponentType t = rectangle_type("Square", "a square: a Rectangle whose w equals its l");
    t.constraints = {{"w", "l"}};
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "RightTriangle";
    t.description = "a right triangle with legs w (along x) and h (along y) and hypotenuse c";
    t.params = {length("w", "leg along x (edge b), mm"),
                length("h", "leg along y (edge l), mm"),
                length("c", "hypotenuse (edge d), mm")};
    t.constraints = {{"c", "sqrt(w^2 + h^2)"}};
    t.edge_names = {"b", "d", "l"};
    t.generate = [](const Values& v,
                    const std::vector<Vec2>&,
                    std::string&) -> std::optional<ComponentShape> {
      return shape({{0, 0}, {v.at("w"), 0}, {0, v.at("h")}}, {"b", "d", "l"});
    };
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "IsoscelesTriangle";
    t.description = "an isosceles triangle with base w, height h and equal sides s";
    t.params = {length("w", "base (edge b), mm"),
                length("h", "height, mm"),
                length("s", "each equal side (edges r, l), mm")};
    t.constraints = {{"s", "sqrt((w/2)^2 + h^2)"}};
    t.edge_names = {"b", "r", "l"};
    t.generate = [](const Values& v,
                    const std::vector<Vec2>&,
                    std::string&) -> std::optional<ComponentShape> {
      const double w = v.at("w");
      return shape({{0, 0}, {w, 0}, {w / 2, v.at("h")}}, {"b", "r", "l"});
    };
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "Trapezoid";
    t.description =
        "a trapezoid: bottom b, top t parallel at height h, the top starting o to the right of the "
        "bottom's start";
    t.params = {
        length("b", "bottom length (edge b), mm"),
        length("t", "top length (edge t), mm"),
        length("h", "height, mm"),
        ParamSpec{
            "o", ParamKind::kLength, "offset of the top's left end from the bottom's, mm", 0.0}};
    t.edge_names = {"b", "r", "t", "l"};
    t.generate = [](const Values& v,
                    const std::vector<Vec2>&,
                    std::string&) -> std::optional<ComponentShape> {
      const double b = v.at("b"), top = v.at("t"), h = v.at("h"), o = v.at("o");
      return shape({{0, 0}, {b, 0}, {o + top, h}, {o, h}}, {"b", "r", "t", "l"});
    };
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "RegularPolygon";
    t.description = "a regular n-gon of side s, edge e0 along x from the origin";
    t.params = {ParamSpec{"n", ParamKind::kCount, "number of sides", std::nullopt, 3, false, 1000},
                length("s", "side length, mm")};
    t.generate = [](const Values& v,
                    const std::vector<Vec2>&,
                    std::string&) -> std::optional<ComponentShape> {
      const int n = static_cast<int>(std::lround(v.at("n")));
      Ring ring;
      std::vector<std::string> names;
      Vec2 p(0, 0);
      for (int i = 0; i < n; ++i) {
        ring.push_back(p);
        names.push_back(fmt::format("e{}", i));
        const double a = 2 * M_PI * i / n;
        p += v.at("s") * Vec2(std::cos(a), std::sin(a));
      }
      return shape(ring, names);
    };
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "LShape";
    t.description = "an L: l × w overall, a vertical arm a wide and a horizontal arm b high";
    t.params = {length("l", "overall length along x, mm"),
                length("w", "overall height along y, mm"),
                length("a", "width of the vertical arm, mm"),
                length("b", "height of the horizontal arm, mm")};
    t.edge_names = {"b", "r", "ih", "iv", "t", "l"};
    t.generate = [](const Values& v,
                    const std::vector<Vec2>&,
                    std::string& error) -> std::optional<ComponentShape> {
      const double l = v.at("l"), w = v.at("w"), a = v.at("a"), b = v.at("b");
      if (a >= l || b >= w) {
        error = fmt::format(
            "arm widths a = {:g} mm and b = {:g} mm must be less than l = {:g} mm and w = {:g} mm",
            a,
            b,
            l,
            w);
        return std::nullopt;
      }
      return shape({{0, 0}, {l, 0}, {l, b}, {a, b}, {a, w}, {0, w}},
                   {"b", "r", "ih", "iv", "t", "l"});
    };
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "UShape";
    t.description =
        "a notched panel l × w with a notch nl wide and nw deep centred in its bottom edge";
    t.params = {length("l", "width along x, mm"),
                length("w", "height along y, mm"),
                length("nl", "notch width, mm"),
                length("nw", "notch depth, mm")};
    t.edge_names = {"b1", "nl", "nt", "nr", "b2", "r", "t", "l"};
    t.generate = [](const Values& v,
                    const std::vector<Vec2>&,
                    std::string& error) -> std::optional<ComponentShape> {
      const double l = v.at("l"), w = v.at("w"), nl = v.at("nl"), nw = v.at("nw");
      if (nl >= l || nw >= w) {
        error = fmt::format(
            "notch nl = {:g} mm × nw = {:g} mm must be smaller than the panel l = {:g} mm × w = "
            "{:g} mm",
            nl,
            nw,
            l,
            w);
        return std::nullopt;
      }
      const double x1 = (l - nl) / 2, x2 = (l + nl) / 2;
      return shape({{0, 0}, {x1, 0}, {x1, nw}, {x2, nw}, {x2, 0}, {l, 0}, {l, w}, {0, w}},
                   {"b1", "nl", "nt", "nr", "b2", "r", "t", "l"});
    };
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "Disc";
    t.description = "a disc of diameter d (a regular polygon of n sides), centred on the origin";
    t.params = {length("d", "diameter, mm"),
                ParamSpec{"n",
                          ParamKind::kCount,
                          "sides of the polygon that approximates it",
                          64.0,
                          8,
                          false,
                          720}};
    t.generate = [](const Values& v,
                    const std::vector<Vec2>&,
                    std::string&) -> std::optional<ComponentShape> {
      const int n = static_cast<int>(std::lround(v.at("n")));
      ComponentShape s;
      s.polygon = circle(Vec2::Zero(), v.at("d") / 2, n);
      for (int i = 0; i < n; ++i) s.edges.push_back({fmt::format("e{}", i), i});
      return s;
    };
    lib.add(std::move(t));
  }
  {
    ComponentType t;
    t.name = "Polygon";
    t.description =
        "a free polygon from a point list (counter-clockwise seen from the front); edges e0, e1, "
        "... or named";
    t.takes_points = true;
    t.generate = [](const Values&,
                    const std::vector<Vec2>& points,
                    std::string& error) -> std::optional<ComponentShape> {
      if (points.size() < 3) {
        error = fmt::format("a polygon needs at least 3 points, not {}", points.size());
        return std::nullopt;
      }
      if (signed_area(points) <= 0) {
        error = "the points must run counter-clockwise seen from the front (positive area)";
        return std::nullopt;
      }
      ComponentShape s;
      s.polygon.outer = points;
      for (std::size_t i = 0; i < points.size(); ++i)
        s.edges.push_back({fmt::format("e{}", i), static_cast<int>(i)});
      return s;
    };
    lib.add(std::move(t));
  }
  return lib;
}

}  // namespace

const ComponentLibrary& ComponentLibrary::builtin() {
  static const ComponentLibrary lib = make_builtin();
  return lib;
}

}  // namespace fabkit::flatpack

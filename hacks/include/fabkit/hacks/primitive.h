#pragma once
/// The eight FabHaL connector primitives (paper §4.1, Table 2; reference §2).

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"

namespace fabkit::hacks {

/// Primitive types. The paper's "hole" is kRing.
enum class PrimitiveType { kRod, kHook, kRing, kClip, kTube, kEdge, kSurface, kHemisphere };

/// "rod", "hook", "ring", "clip", "tube", "edge", "surface", "hemisphere".
std::string_view to_string(PrimitiveType t);
/// Case-insensitive; accepts "hole" for kRing and "hemi" for kHemisphere.
std::optional<PrimitiveType> primitive_type_from_string(std::string_view s);

/// How a primitive's connector frame is parameterised (the reference's MCF classes). The
/// spelling of to_string() is the reference's ctype ("HookFlex", "RodCtl", ...).
enum class ConnectorKind {
  kRod,             ///< (t, φ, ψ): point on the rod surface, tilt ±45°, angle around the rod
  kRodCenterline,   ///< (t): point on the rod axis
  kHook,            ///< (θ): point on the inner side of the hook wire
  kHookFlex,        ///< (θ, φ)
  kRing,            ///< (θ) on the inner side of the ring wire, unbounded
  kRingFlex,        ///< (θ, φ)
  kRingCenterline,  ///< (v0, v1): the ring centre, two unbounded angles
  kTube,            ///< (t, θ): point on the outer surface
  kTubeCenterline,  ///< (t, θ): point on the inner wall
  kClip,            ///< (t): along the jaw
  kEdge,            ///< (t): along the long edge
  kSurface,         ///< (t1, t2, s): point on the surface and spin
  kHemisphere,      ///< (θ, φ, s): point on the hemisphere and spin
};

std::string_view to_string(ConnectorKind k);
/// Number of connector parameters of a kind.
int connector_dof(ConnectorKind k);

/// The paper's three parameter tags (§4.3.3).
enum class ParamTag {
  kUnbounded,          ///< periodic; wraps from max to min
  kBoundedAndClamped,  ///< geometry keeps it inside [min, max]
  kBoundedAndOpen,     ///< leaving [min, max] means the connection comes apart
};
/// "UNBOUNDED", "BOUNDED_AND_CLAMPED", "BOUNDED_AND_OPEN".
std::string_view to_string(ParamTag t);
std::optional<ParamTag> param_tag_from_string(std::string_view s);

/// One connector parameter: t-like parameters are fractions in [0, 1], angles are degrees.
struct ParamSpec {
  std::string name;  ///< "t", "phi", "theta", "t1", "t2", "s", "v0", "v1"
  double init = 0;
  double lo = 0;
  double hi = 0;
  ParamTag tag = ParamTag::kBoundedAndOpen;
  bool critical_dim = false;         ///< positions along the critical dimension (t, t1, t2)
  bool fixed_under_physics = false;  ///< pinned during relaxation (clip jaws, fixed joints)
  bool constant = false;             ///< never optimised (lo == hi == init)
  /// Whether running out past lo / hi lets the connection come apart (sliding parameters of
  /// open primitives). Tilt limits (φ) are joint stops, never open.
  bool open_at_lo = false;
  bool open_at_hi = false;
  bool is_angle() const { return name != "t" && name != "t1" && name != "t2"; }
};

/// Shape parameters, mm and degrees. Which fields a type uses: rod (radius, length), hook
/// (arc_radius, arc_angle, thickness = wire radius), ring (arc_radius, thickness), tube
/// (inner_radius, thickness, length), clip (width, height, thickness, dist, open_gap), edge
/// (width, length, height), surface (width, length), hemisphere (radius).
struct PrimitiveShape {
  double radius = 0;
  double length = 0;
  double arc_radius = 0;
  double arc_angle = 0;
  double thickness = 0;
  double inner_radius = 0;
  double width = 0;
  double height = 0;
  double dist = 0;
  double open_gap = 0;
};

/// Names of the shape fields a type uses, in the order of Table 2.
std::vector<std::string_view> shape_field_names(PrimitiveType t);
/// Pointer to a shape field by name (nullptr if the name is not a shape field).
double* shape_field(PrimitiveShape& s, std::string_view name);
double shape_field_value(const PrimitiveShape& s, std::string_view name);

/// What is wrong with one shape field's value (not finite, not positive, absurd, an arc angle
/// outside (0, 360]), as a message prefixed by `who`; nullopt if nothing.
std::optional<std::string> shape_field_problem(PrimitiveType type,
                                               std::string_view field,
                                               double value,
                                               std::string_view who);

/// A connector primitive on a part.
struct Primitive {
  std::string name;  ///< unique within its part, e.g. "hook1"
  PrimitiveType type = PrimitiveType::kRod;
  PrimitiveShape shape;
  Frame frame;        ///< base frame in the part's coordinates
  bool flex = false;  ///< hook/ring: extra φ tilt (HookFlex, RingFlex)
  bool centerline =
      false;  ///< rod/ring/tube: connect on the axis/centre (RodCtl, RingCtl, TubeCtl)
  /// Rod/hook/tube/surface: false when the part's geometry closes the ends, so connector
  /// parameters are clamped instead of running off (defaults: true, surface false).
  bool is_open = true;
  /// Whether something can be slid onto it at all. Rings are always closed.
  bool open_for_connect = true;
  /// Which ends let a connection slide off while is_open: rod/tube/edge t = 0 and t = 1, hook
  /// θ at its lower and upper bound. A cable's plug or a pin's wall end is closed.
  std::array<bool, 2> open_ends{true, true};
  std::optional<std::array<double, 2>> theta_range;  ///< hook θ bounds, default [0, arc_angle]
  std::optional<std::array<double, 2>> phi_range;    ///< flex φ bounds, default [45, 135]

  /// A primitive with the type's defaults (surface is closed; everything else open).
  static Primitive make(std::string name,
                        PrimitiveType type,
                        const PrimitiveShape& shape,
                        const Frame& frame = {});

  ConnectorKind connector_kind() const;
  /// Clips and hemispheres hold one thing only.
  bool single_connection() const;
  /// True when nothing can be slid onto it (rings always; others when !open_for_connect).
  bool closed_for_connect() const;
  /// Connector parameters of a fresh connection, tags resolved (§2.3, §4.5).
  std::vector<ParamSpec> connector_params() const;
  /// Critical dimension (§4.1): rod/tube/edge length, ring arc radius, surface {width, length};
  /// empty for hook, clip and hemisphere.
  std::vector<double> critical_dim() const;
  /// What this primitive occupies on another's critical dimension (reference §5.4):
  /// hook/ring thickness, rod radius, tube length/2, clip width/2, hemisphere {r, r},
  /// surface {width/2, length/2}; empty for edge.
  std::vector<double> connector_critical_dim() const;
  /// One-line description, e.g. "hook (arc radius 11.6 mm, arc angle 270°, wire radius 2 mm)".
  std::string describe() const;
  /// Checks every used shape field is finite, positive and below 100 m, angles in range.
  /// `who` prefixes messages ("DoubleHook.hook1").
  void validate(std::string_view who, Diagnostics& diags, const SourceLocation& where = {}) const;
};

}  // namespace fabkit::hacks

#pragma once
/// Which primitives may connect, how their connector frames align, and whether their sizes
/// fit (paper §4.1, Table 1, §4.3.1; reference §3, §4.3).

#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"
#include "fabkit/hacks/primitive.h"

namespace fabkit::hacks {

/// The paper's connectivity table (Table 1), symmetric.
bool pair_allowed(PrimitiveType a, PrimitiveType b);
/// The types `t` can connect to, in enum order.
std::vector<PrimitiveType> allowed_partners(PrimitiveType t);

/// `alignment` argument of connect().
enum class AlignmentChoice { kDefault, kFlip };
std::string_view to_string(AlignmentChoice a);
std::optional<AlignmentChoice> alignment_choice_from_string(std::string_view s);

/// Alignment offset between two connector frames: a connection requires
/// C_first_global · A = C_second_global, with A = rot_euler(rot).
struct AlignmentOffset {
  Vec3 rot = Vec3::Zero();     ///< default offset, degrees
  std::vector<int> flip_axes;  ///< Euler components that "flip" changes; empty = not flippable
  /// The offset for a choice. Flipping maps 0 ↔ 180 and negates anything else, per component.
  Vec3 rotation(AlignmentChoice choice) const;
  Mat4 matrix(AlignmentChoice choice) const {
    return Frame(Vec3::Zero(), rotation(choice)).matrix();
  }
  bool flippable() const { return !flip_axes.empty(); }
};

/// Offset for connecting `first` (the primitive already in the assembly, or the first
/// argument of a cycle-closing connect) to `second`. Looked up by ctype ("HookFlex_Rod"),
/// then by class ("Hook_Rod"); pairs without an entry align with the identity.
AlignmentOffset alignment_offset(ConnectorKind first, ConnectorKind second);

/// The offset A of a connection between `first` and `second` (the primitive already in the
/// assembly and the new one, or the two sides of a cycle-closing connect): the connection
/// holds where C_first · A = C_second. The table is keyed by ordered pairs whose two
/// directions are not always each other's inverse (Tube/Hook is a quarter turn both ways), so
/// that reading it in whichever order the connects happened to come gave one connect two
/// meanings: a broom handle held by two eye hooks could not reach its target when the other
/// eye hook's connect came first. Each pair of kinds is read in one fixed order (the host
/// first: edge, surface, ring, hook, rod, tube, clip, hemisphere), and inverted when the
/// connection's sides come the other way.
Mat4 alignment_matrix(ConnectorKind first, ConnectorKind second, AlignmentChoice choice);

/// A primitive as the checks see it: its label for messages ("DoubleHook#2.hook1") and
/// its currently available critical dimension (empty if it has none).
struct PrimitiveInUse {
  const Primitive* primitive = nullptr;
  std::string label;
  std::vector<double> available;
};

/// Physical compatibility of a connection (reference §3.2): closedness, sizes, and the
/// available critical dimension. Adds one diagnostic per failed quantity, naming the
/// primitives and the numbers; returns true if nothing failed.
bool check_compatibility(const PrimitiveInUse& a,
                         const PrimitiveInUse& b,
                         Diagnostics& diags,
                         const SourceLocation& where = {});

/// Available critical dimension of `self` after it takes a connection to `other`
/// (reference §4.3). `other_available` is the other primitive's current availability.
std::vector<double> consume_critical_dim(const Primitive& self,
                                         std::vector<double> available,
                                         const Primitive& other,
                                         const std::vector<double>& other_available);

}  // namespace fabkit::hacks

#pragma once
/// Scale invariance as a feature (RodSteward §6, Fig. 12): scaling node positions leaves every
/// joint identical (only the rods change), so a rescaled design reuses the printed joints.

#include <optional>
#include <vector>

#include "fabkit/rods/layout.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods {

/// A joint of one design that is geometrically the same as a joint of another.
struct JointMatch {
  int node = 0;     ///< in the new design
  int printed = 0;  ///< in the printed design
};

/// Joints of `b` whose geometry equals a joint of `a`: same r, p, σ, h, ε and leaf offset, the
/// same rod directions with the same profile orientation, offsets and socket lengths (within
/// `tolerance` mm, and the same direction within tolerance / 1000 mm). Each joint of `a` is used
/// at most once; the same node number is preferred.
std::vector<JointMatch> matching_joints(const Structure& a,
                                        const Parameters& pa,
                                        const Structure& b,
                                        const Parameters& pb,
                                        double tolerance = 1e-6);

/// The factor f with b = f · a (every node, about the origin) when the two structures have the
/// same edges; nullopt otherwise.
std::optional<double> uniform_scale_between(const Structure& a, const Structure& b);

}  // namespace fabkit::rods

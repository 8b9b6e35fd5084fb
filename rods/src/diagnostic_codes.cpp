#include "fabkit/rods/diagnostic_codes.h"

#include <array>

namespace fabkit::rods {

std::span<const DiagnosticCode> rods_codes() {
  static constexpr std::array kAll = {codes::kNoSuchNode,
                                      codes::kZeroLengthEdge,
                                      codes::kDuplicateEdge,
                                      codes::kIsolatedNode,
                                      codes::kOverlappingEdges,
                                      codes::kNodesMerged,
                                      codes::kNoRodLeft,
                                      codes::kRodsIntersect,
                                      codes::kJointSwallowsRod,
                                      codes::kRodTooShort,
                                      codes::kUnbalanced,
                                      codes::kRodOverstressed,
                                      codes::kMechanism,
                                      codes::kDisconnected,
                                      codes::kJointsReused,
                                      codes::kSmallEngraving,
                                      codes::kPieceLongerThanStock};
  return kAll;
}

}  // namespace fabkit::rods

#include "fabkit/hacks/diagnostic_codes.h"

#include <array>

namespace fabkit::hacks {

std::span<const DiagnosticCode> hacks_codes() {
  static constexpr std::array kAll = {codes::kUnknownPart,
                                      codes::kUnknownPrimitive,
                                      codes::kNotInAssembly,
                                      codes::kPairNotAllowed,
                                      codes::kBothClosed,
                                      codes::kDimensionMismatch,
                                      codes::kNoSpaceLeft,
                                      codes::kSingleConnection,
                                      codes::kAlreadyConnected,
                                      codes::kMultiConnection,
                                      codes::kCycleTooLong,
                                      codes::kCycleNotClosable,
                                      codes::kNoEnvironment,
                                      codes::kTargetMissing,
                                      codes::kNotConnected,
                                      codes::kNotAtRest,
                                      codes::kPartsOverlap,
                                      codes::kFallsApart,
                                      codes::kNotASolid};
  return kAll;
}

}  // namespace fabkit::hacks

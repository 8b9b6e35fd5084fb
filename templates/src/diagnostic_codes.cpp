#include "fabkit/templates/diagnostic_codes.h"

#include <array>

namespace fabkit::templates {

std::span<const DiagnosticCode> templates_codes() {
  static constexpr std::array kAll = {codes::kUnknownItem,
                                      codes::kUnknownTemplate,
                                      codes::kItemMismatch,
                                      codes::kCatalogError,
                                      codes::kConstrained,
                                      codes::kFixedControl,
                                      codes::kNoConnection,
                                      codes::kSolverFailed,
                                      codes::kUnstable,
                                      codes::kPartsOverlap,
                                      codes::kFloatingPart,
                                      codes::kPieceTooLarge};
  return kAll;
}

}  // namespace fabkit::templates

#include "fabkit/core/diagnostics.h"

#include <fmt/format.h>

#include <array>

namespace fabkit {
namespace {

struct CodeName {
  DiagnosticCode code;
  std::string_view name;
};

constexpr std::array kCodeNames = {
    CodeName{DiagnosticCode::kMalformedInput, "malformed-input"},
    CodeName{DiagnosticCode::kUnreadableFile, "unreadable-file"},
    CodeName{DiagnosticCode::kInvalidValue, "invalid-value"},
    CodeName{DiagnosticCode::kUnknownName, "unknown-name"},
    CodeName{DiagnosticCode::kUnknownPart, "unknown-part"},
    CodeName{DiagnosticCode::kUnknownPrimitive, "unknown-primitive"},
    CodeName{DiagnosticCode::kDuplicateName, "duplicate-name"},
    CodeName{DiagnosticCode::kNotInAssembly, "not-in-assembly"},
    CodeName{DiagnosticCode::kPairNotAllowed, "pair-not-allowed"},
    CodeName{DiagnosticCode::kBothClosed, "both-closed"},
    CodeName{DiagnosticCode::kDimensionMismatch, "dimension-mismatch"},
    CodeName{DiagnosticCode::kNoSpaceLeft, "no-space-left"},
    CodeName{DiagnosticCode::kSingleConnection, "single-connection"},
    CodeName{DiagnosticCode::kAlreadyConnected, "already-connected"},
    CodeName{DiagnosticCode::kMultiConnection, "multi-connection"},
    CodeName{DiagnosticCode::kCycleTooLong, "cycle-too-long"},
    CodeName{DiagnosticCode::kCycleNotClosable, "cycle-not-closable"},
    CodeName{DiagnosticCode::kNoEnvironment, "no-environment"},
    CodeName{DiagnosticCode::kTargetMissing, "target-missing"},
    CodeName{DiagnosticCode::kNotConnected, "not-connected"},
};

}  // namespace

std::string_view to_string(Severity s) {
  switch (s) {
    case Severity::kError:
      return "error";
    case Severity::kWarning:
      return "warning";
    case Severity::kNote:
      return "note";
  }
  return "error";
}

std::string_view to_string(DiagnosticCode c) {
  for (const auto& [code, name] : kCodeNames) {
    if (code == c) return name;
  }
  return "unknown";
}

std::optional<DiagnosticCode> diagnostic_code_from_string(std::string_view s) {
  for (const auto& [code, name] : kCodeNames) {
    if (name == s) return code;
  }
  return std::nullopt;
}

std::string Diagnostic::format() const {
  std::string prefix;
  if (where.known()) {
    prefix = where.file;
    if (where.line > 0) prefix += fmt::format(":{}", where.line);
    if (where.line > 0 && where.column > 0) prefix += fmt::format(":{}", where.column);
    prefix += ": ";
  }
  return fmt::format("{}{}: {}", prefix, to_string(severity), message);
}

void Diagnostics::error(DiagnosticCode code, std::string message, SourceLocation where) {
  items_.push_back({Severity::kError, code, std::move(message), std::move(where)});
}

void Diagnostics::warning(DiagnosticCode code, std::string message, SourceLocation where) {
  items_.push_back({Severity::kWarning, code, std::move(message), std::move(where)});
}

void Diagnostics::append(const Diagnostics& other) {
  items_.insert(items_.end(), other.items_.begin(), other.items_.end());
}

bool Diagnostics::has_errors() const {
  for (const auto& d : items_) {
    if (d.severity == Severity::kError) return true;
  }
  return false;
}

std::string Diagnostics::format() const {
  std::string out;
  for (const auto& d : items_) {
    out += d.format();
    out += '\n';
  }
  return out;
}

}  // namespace fabkit

#include "fabkit/core/diagnostics.h"

#include <fmt/format.h>

#include <array>

#include "fabkit/core/text.h"

namespace fabkit {

std::string_view to_string(DiagnosticClass c) {
  switch (c) {
    case DiagnosticClass::kInput:
      return "input";
    case DiagnosticClass::kInfeasible:
      return "infeasible";
    case DiagnosticClass::kFallsApart:
      return "falls-apart";
    case DiagnosticClass::kCheck:
      return "check";
    case DiagnosticClass::kIo:
      return "io";
    case DiagnosticClass::kTimeout:
      return "timeout";
    case DiagnosticClass::kInternal:
      return "internal";
  }
  return "internal";
}

std::span<const DiagnosticCode> core_codes() {
  static constexpr std::array kAll = {codes::kMalformedInput,
                                      codes::kUnreadableFile,
                                      codes::kInvalidValue,
                                      codes::kUnknownName,
                                      codes::kDuplicateName,
                                      codes::kUnknownKit,
                                      codes::kLimitExceeded,
                                      codes::kWriteFailed,
                                      codes::kTimeLimit,
                                      codes::kInternalError};
  return kAll;
}

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

void Diagnostics::add(Diagnostic d) {
  // Messages quote what users wrote (names, keys, yaml-cpp's own excerpts of the input), which
  // need not be UTF-8: every message must still print and encode as JSON.
  if (!is_valid_utf8(d.message)) d.message = to_valid_utf8(d.message);
  if (!is_valid_utf8(d.where.file)) d.where.file = to_valid_utf8(d.where.file);
  items_.push_back(std::move(d));
}

void Diagnostics::error(DiagnosticCode code, std::string message, SourceLocation where) {
  add({Severity::kError, code, std::move(message), std::move(where)});
}

void Diagnostics::warning(DiagnosticCode code, std::string message, SourceLocation where) {
  add({Severity::kWarning, code, std::move(message), std::move(where)});
}

void Diagnostics::note(DiagnosticCode code, std::string message, SourceLocation where) {
  add({Severity::kNote, code, std::move(message), std::move(where)});
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

bool Diagnostics::has_errors_of(DiagnosticClass c) const {
  for (const auto& d : items_) {
    if (d.severity == Severity::kError && d.kind() == c) return true;
  }
  return false;
}

std::optional<DiagnosticClass> Diagnostics::deciding_class() const {
  for (DiagnosticClass c : {DiagnosticClass::kInput,
                            DiagnosticClass::kIo,
                            DiagnosticClass::kInternal,
                            DiagnosticClass::kTimeout,
                            DiagnosticClass::kInfeasible,
                            DiagnosticClass::kFallsApart,
                            DiagnosticClass::kCheck}) {
    if (has_errors_of(c)) return c;
  }
  return std::nullopt;
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

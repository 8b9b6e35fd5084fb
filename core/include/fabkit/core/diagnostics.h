#pragma once
/// Diagnostics: what the library says about bad input, infeasible designs and failures.
///
/// Library code never prints and never throws on user input; it returns diagnostics that
/// name the file and line, or the part, primitive and quantity that failed. Front ends turn
/// them into `error:` lines, exit codes, Python exceptions or HTTP statuses, and they decide
/// which by the diagnostic's *class*, never by its code: every kit defines its own codes (in
/// its own module), each belonging to one class.

#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fabkit {

enum class Severity { kError, kWarning, kNote };

/// What kind of failure a diagnostic reports; front ends map classes to exit codes and HTTP
/// statuses.
enum class DiagnosticClass {
  kInput,       ///< the input cannot be understood: syntax, unknown names, NaN, absurd sizes
  kInfeasible,  ///< the input is understood but the design cannot be made as asked
  kFallsApart,  ///< the design can be made but does not hold (falls apart, tips over)
  kCheck,       ///< the design builds, but a fabrication check failed (collision, fit, balance)
  kIo,          ///< an output could not be written (directory, disk, permissions)
  kTimeout,     ///< the work stopped at its time limit
  kInternal,    ///< a bug: an invariant broke (please report)
};
std::string_view to_string(Severity s);

/// "input", "infeasible", "falls-apart", "check", "io", "timeout", "internal".
std::string_view to_string(DiagnosticClass c);

/// A diagnostic code: a stable spelling ("dimension-mismatch") and its class. Core defines
/// the codes every kit shares (fabkit::codes); each kit adds its own (fabkit::hacks::codes).
struct DiagnosticCode {
  std::string_view name;
  DiagnosticClass kind = DiagnosticClass::kInput;
  constexpr bool operator==(const DiagnosticCode& o) const { return name == o.name; }
};
inline std::string_view to_string(const DiagnosticCode& c) {
  return c.name;
}

/// Codes shared by every kit.
namespace codes {
inline constexpr DiagnosticCode kMalformedInput{"malformed-input", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kUnreadableFile{"unreadable-file", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kInvalidValue{"invalid-value", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kUnknownName{"unknown-name", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kDuplicateName{"duplicate-name", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kUnknownKit{"unknown-kit", DiagnosticClass::kInput};
/// A design larger than a limit (parts, connections, bytes) set by the caller.
inline constexpr DiagnosticCode kLimitExceeded{"limit-exceeded", DiagnosticClass::kInput};
inline constexpr DiagnosticCode kWriteFailed{"write-failed", DiagnosticClass::kIo};
inline constexpr DiagnosticCode kTimeLimit{"time-limit", DiagnosticClass::kTimeout};
inline constexpr DiagnosticCode kInternalError{"internal-error", DiagnosticClass::kInternal};
}  // namespace codes

/// The codes of namespace codes, for documentation and tests.
std::span<const DiagnosticCode> core_codes();

/// Where in an input file something was written (1-based; 0 = unknown).
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
  bool known() const { return !file.empty(); }
};

struct Diagnostic {
  Severity severity = Severity::kError;
  DiagnosticCode code = codes::kMalformedInput;
  std::string message;
  SourceLocation where;

  DiagnosticClass kind() const { return code.kind; }
  /// "file:line:col: error: message" (location omitted when unknown).
  std::string format() const;
};

/// An ordered list of diagnostics with small helpers.
class Diagnostics {
 public:
  /// Adds `d`; invalid UTF-8 in its message or file name becomes U+FFFD.
  void add(Diagnostic d);
  void error(DiagnosticCode code, std::string message, SourceLocation where = {});
  void warning(DiagnosticCode code, std::string message, SourceLocation where = {});
  void note(DiagnosticCode code, std::string message, SourceLocation where = {});
  void append(const Diagnostics& other);

  bool has_errors() const;
  /// Whether any error is of class `c`.
  bool has_errors_of(DiagnosticClass c) const;
  /// The class that decides an outcome when errors of several classes are present: the first
  /// of input, I/O, internal, time limit, infeasible, falls apart, check that has an error
  /// (the user must fix the input before anything else means much). nullopt: no errors.
  std::optional<DiagnosticClass> deciding_class() const;
  bool empty() const { return items_.empty(); }
  std::size_t size() const { return items_.size(); }
  const std::vector<Diagnostic>& items() const { return items_; }
  auto begin() const { return items_.begin(); }
  auto end() const { return items_.end(); }
  /// All diagnostics, one formatted line each.
  std::string format() const;

 private:
  std::vector<Diagnostic> items_;
};

}  // namespace fabkit

#pragma once
/// Diagnostics: what the library says about bad input and infeasible designs.
///
/// Library code never prints and never throws on user input; it returns diagnostics that
/// name the file and line, or the part, primitive and quantity that failed. Front ends turn
/// them into `error:` lines, exit codes, Python exceptions or HTTP 400 bodies.

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fabkit {

enum class Severity { kError, kWarning, kNote };

/// One failure class per code; front ends spell them with to_string().
enum class DiagnosticCode {
  kMalformedInput,     ///< the file cannot be parsed (syntax, wrong node type)
  kUnreadableFile,     ///< the file cannot be opened or read
  kInvalidValue,       ///< NaN, negative or absurd sizes, out-of-range numbers
  kUnknownName,        ///< unknown key, part, primitive or option
  kUnknownPart,        ///< no part of that name in the library
  kUnknownPrimitive,   ///< the part has no primitive of that name
  kDuplicateName,      ///< a name used twice where names must be unique
  kNotInAssembly,      ///< neither primitive's part is in the assembly yet
  kPairNotAllowed,     ///< the two primitive types cannot connect (paper Table 1)
  kBothClosed,         ///< both primitives are closed: there is no way to slide one on
  kDimensionMismatch,  ///< the primitives' sizes do not fit (hook opening vs rod radius, ...)
  kNoSpaceLeft,        ///< the available critical dimension is used up
  kSingleConnection,   ///< a clip/hemisphere already holds something
  kAlreadyConnected,   ///< the same two primitives are connected already
  kMultiConnection,    ///< several connections on one primitive cannot be spaced apart
  kCycleTooLong,       ///< polygon-inequality quick reject of a cycle-closing connect
  kCycleNotClosable,   ///< the cycle-closure search found no configuration that closes it
  kNoEnvironment,      ///< an assembly needs an environment before anything else
  kTargetMissing,      ///< no end_with target, or it is not connected
  kNotConnected,       ///< a part is in the design but connected to nothing
};

std::string_view to_string(Severity s);
std::string_view to_string(DiagnosticCode c);
/// Parses the spelling of to_string(); nullopt if unknown.
std::optional<DiagnosticCode> diagnostic_code_from_string(std::string_view s);

/// Where in an input file something was written (1-based; 0 = unknown).
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
  bool known() const { return !file.empty(); }
};

struct Diagnostic {
  Severity severity = Severity::kError;
  DiagnosticCode code = DiagnosticCode::kMalformedInput;
  std::string message;
  SourceLocation where;

  /// "file:line:col: error: message" (location omitted when unknown).
  std::string format() const;
};

/// An ordered list of diagnostics with small helpers.
class Diagnostics {
 public:
  void add(Diagnostic d) { items_.push_back(std::move(d)); }
  void error(DiagnosticCode code, std::string message, SourceLocation where = {});
  void warning(DiagnosticCode code, std::string message, SourceLocation where = {});
  void append(const Diagnostics& other);

  bool has_errors() const;
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

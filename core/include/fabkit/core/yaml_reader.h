#pragma once
/// Reading YAML documents for every kit: positions, typed getters with their own messages,
/// "did you mean" for keys, and the `fabkit: <kit>/<version>` header.
///
///   Diagnostics diags;
///   YamlReader in("design.yaml", diags);
///   auto root = in.parse_mapping(text, "a design with nodes and edges");
///   if (!root) return;                       // file:line:col of the syntax error is in diags
///   in.check_keys(*root, {"fabkit", "name", "nodes"});
///   auto radius = in.number((*root)["radius"], "rod radius", {.min = 0, .max = 1e5, .unit =
///   "mm"});
///
/// Every getter reports its own failure (file:line:col, what was expected, an excerpt of what
/// was found) and returns nullopt; callers just stop using the value.

#include <yaml-cpp/yaml.h>

#include <cstddef>
#include <initializer_list>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"

namespace fabkit {

/// Bounds of a number read from a file; values outside get an invalid-value diagnostic.
struct NumberRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  std::string_view unit;       ///< "mm", "degrees"; used in messages
  bool exclusive_min = false;  ///< require value > min (sizes that must be positive)
};

/// Coordinates beyond 1 km are a unit mistake in any kit (mm throughout).
inline constexpr double kMaxCoordinateMm = 1e6;

/// The `fabkit:` header of a design file: which kit reads it, in which format version.
struct KitTag {
  std::string kit;  ///< "hacks", "rods", "flatpack", "templates"
  int version = 0;
  SourceLocation where;
  /// "hacks/1"
  std::string spelled() const;
};

class YamlReader {
 public:
  /// `file` names the input in every diagnostic (a path, or "design.yaml" for posted text).
  YamlReader(std::string file, Diagnostics& diags);

  const std::string& file() const { return file_; }
  Diagnostics& diagnostics() { return diags_; }
  /// Errors this reader reported so far.
  int errors() const { return errors_; }

  /// Parses one document; a syntax error gets file:line:col and nullopt. yaml-cpp's own
  /// exceptions never escape.
  std::optional<YAML::Node> parse(std::string_view text);
  /// Parses and requires a non-empty mapping at the top; `expected` says what it should hold
  /// ("a design file must be a mapping with <expected>").
  std::optional<YAML::Node> parse_mapping(std::string_view text, std::string_view expected);

  /// The text to parse is an excerpt of the file: its line k (0-based) is the file's line
  /// `file_lines[k]` (1-based), so that positions name the file's own lines.
  void set_line_numbers(std::vector<int> file_lines) { file_lines_ = std::move(file_lines); }

  /// Position of a node (1-based line and column); the file alone if yaml-cpp lost it.
  SourceLocation at(const YAML::Node& node) const;
  /// file:1:1, for things about the document as a whole.
  SourceLocation start() const { return SourceLocation{file_, 1, 1}; }

  void error(DiagnosticCode code, std::string message, SourceLocation where);
  void warning(DiagnosticCode code, std::string message, SourceLocation where);

  /// Reports each key of `map` not in `allowed` ("unknown key 'radus' in a rod; did you mean
  /// 'radius'? expected one of: ..."); `context` names the mapping. True if all are known.
  bool check_keys(const YAML::Node& map,
                  std::span<const std::string_view> allowed,
                  std::string_view context = {});
  bool check_keys(const YAML::Node& map,
                  std::initializer_list<std::string_view> allowed,
                  std::string_view context = {});
  /// Reports a missing required key of `map`.
  bool require(const YAML::Node& map, std::string_view key, std::string_view context);

  /// A scalar string, valid UTF-8 and at most `max_bytes` long.
  std::optional<std::string> string(const YAML::Node& node,
                                    std::string_view what,
                                    std::size_t max_bytes = 4096);
  /// A name others refer to: non-empty, at most 128 bytes, letters, digits, '_', '-' and any
  /// non-ASCII letter; no '.', spaces or control characters.
  std::optional<std::string> name(const YAML::Node& node, std::string_view what);
  /// A finite number within `range`.
  std::optional<double> number(const YAML::Node& node,
                               std::string_view what,
                               const NumberRange& range = {});
  /// An integer within [min, max].
  std::optional<long long> integer(const YAML::Node& node,
                                   std::string_view what,
                                   long long min,
                                   long long max);
  std::optional<bool> boolean(const YAML::Node& node, std::string_view what);
  /// A list of numbers, each within `range`; `count` 0 accepts any length up to `max_count`.
  std::optional<std::vector<double>> numbers(const YAML::Node& node,
                                             std::string_view what,
                                             std::size_t count,
                                             const NumberRange& range = {},
                                             std::size_t max_count = 1'000'000);
  /// [x, y, z], each within `range`.
  std::optional<Vec3> vec3(const YAML::Node& node,
                           std::string_view what,
                           const NumberRange& range = {});
  /// {pos: [x, y, z], rot: [a, b, c]}: mm within ±kMaxCoordinateMm and degrees within ±36000.
  std::optional<Frame> frame(const YAML::Node& node, std::string_view what);
  /// A sequence (or, with `allow_single`, one mapping standing for a one-item list).
  bool is_list(const YAML::Node& node, std::string_view what, bool allow_single = false);
  bool is_mapping(const YAML::Node& node, std::string_view what);

  /// The `fabkit:` header of a parsed document, or nullopt with a diagnostic naming the known
  /// kits when it is missing or not spelled "<kit>/<version>".
  std::optional<KitTag> kit_tag(const YAML::Node& root, std::span<const std::string_view> known);

 private:
  // The file's 1-based line of the parsed text's 0-based line `line`.
  int file_line(int line) const;

  std::string file_;
  std::vector<int> file_lines_;  // set_line_numbers(); empty: the text is the whole file
  Diagnostics& diags_;
  int errors_ = 0;
};

/// Runs a reader that walks a parsed document; what it throws (yaml-cpp throws on a subscript of
/// a scalar: a shape of YAML the reader did not expect) is returned, so that the caller reports
/// it at the file (report_unexpected_shape) instead of aborting. nullopt: it did not throw.
template <class Read>
std::optional<std::string> thrown_by(Read&& read) {
  try {
    read();
    return std::nullopt;
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
}

/// The finding for what thrown_by() returned: "the file could not be read as <what> (...)",
/// an input error at `file`.
void report_unexpected_shape(Diagnostics& diags,
                             std::string_view file,
                             std::string_view what,
                             std::string_view thrown);

/// "; did you mean 'x'?" or "" when nothing is close.
std::string did_you_mean(std::string_view typed, const std::vector<std::string>& candidates);

/// The `fabkit:` header of `text` without reading the rest (front ends dispatch on it).
/// nullopt with a diagnostic when it is missing, malformed or the text is not YAML.
std::optional<KitTag> read_kit_tag(std::string_view text,
                                   std::string_view file,
                                   std::span<const std::string_view> known,
                                   Diagnostics& diags);

}  // namespace fabkit

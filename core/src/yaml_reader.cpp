#include "fabkit/core/yaml_reader.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <exception>

#include "fabkit/core/names.h"
#include "fabkit/core/text.h"

namespace fabkit {
namespace {

std::string join(std::span<const std::string_view> items) {
  std::string out;
  for (std::string_view s : items) {
    if (!out.empty()) out += ", ";
    out += s;
  }
  return out;
}

std::string found(const YAML::Node& node) {
  if (node.IsScalar()) return fmt::format("'{}'", excerpt(node.Scalar(), 40));
  if (node.IsSequence()) return "a list";
  if (node.IsMap()) return "a mapping";
  return "nothing";
}

std::string known_kits(std::span<const std::string_view> known) {
  std::string out;
  for (std::string_view k : known) {
    if (!out.empty()) out += ", ";
    out += fmt::format("{}/1", k);
  }
  return out;
}

}  // namespace

std::string KitTag::spelled() const {
  return fmt::format("{}/{}", kit, version);
}

void report_unexpected_shape(Diagnostics& diags,
                             std::string_view file,
                             std::string_view what,
                             std::string_view thrown) {
  diags.error(codes::kMalformedInput,
              fmt::format("the file could not be read as {} ({})", what, excerpt(thrown, 200)),
              SourceLocation{std::string(file), 0, 0});
}

std::string did_you_mean(std::string_view typed, const std::vector<std::string>& candidates) {
  const std::string best = closest_name(typed, candidates);
  return best.empty() ? "" : fmt::format("; did you mean '{}'?", best);
}

YamlReader::YamlReader(std::string file, Diagnostics& diags)
    : file_(std::move(file)), diags_(diags) {}

std::optional<YAML::Node> YamlReader::parse(std::string_view text) {
  try {
    return YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    SourceLocation where = start();
    if (e.mark.line >= 0) where = {file_, file_line(e.mark.line), e.mark.column + 1};
    error(codes::kMalformedInput, fmt::format("YAML syntax error: {}", e.msg), where);
  } catch (const std::exception& e) {
    // yaml-cpp can run out of stack-safe depth or memory on hostile input.
    error(codes::kMalformedInput, fmt::format("cannot read the YAML: {}", e.what()), start());
  }
  return std::nullopt;
}

std::optional<YAML::Node> YamlReader::parse_mapping(std::string_view text,
                                                    std::string_view expected) {
  auto root = parse(text);
  if (!root) return std::nullopt;
  if (!root->IsMap()) {
    const bool empty = !root->IsDefined() || root->IsNull();
    error(codes::kMalformedInput,
          empty ? fmt::format("the file is empty; it must be a YAML mapping with {}", expected)
                : fmt::format(
                      "the file must be a YAML mapping with {}, not {}", expected, found(*root)),
          empty ? start() : at(*root));
    return std::nullopt;
  }
  return root;
}

SourceLocation YamlReader::at(const YAML::Node& node) const {
  const YAML::Mark m = node.Mark();
  if (m.line < 0) return SourceLocation{file_, 0, 0};
  return SourceLocation{file_, file_line(m.line), m.column + 1};
}

int YamlReader::file_line(int line) const {
  if (file_lines_.empty() || line < 0) return line + 1;
  const auto k = static_cast<std::size_t>(line);
  // Past the excerpt's end (an error found at the end of the text): the lines after its last.
  if (k >= file_lines_.size()) {
    return file_lines_.back() + 1 + static_cast<int>(k - file_lines_.size());
  }
  return file_lines_[k];
}

void YamlReader::error(DiagnosticCode code, std::string message, SourceLocation where) {
  if (where.file.empty()) where.file = file_;
  diags_.error(code, std::move(message), std::move(where));
  ++errors_;
}

void YamlReader::warning(DiagnosticCode code, std::string message, SourceLocation where) {
  if (where.file.empty()) where.file = file_;
  diags_.warning(code, std::move(message), std::move(where));
}

bool YamlReader::check_keys(const YAML::Node& map,
                            std::initializer_list<std::string_view> allowed,
                            std::string_view context) {
  return check_keys(
      map, std::span<const std::string_view>(allowed.begin(), allowed.size()), context);
}

bool YamlReader::check_keys(const YAML::Node& map,
                            std::span<const std::string_view> allowed,
                            std::string_view context) {
  if (!map.IsMap()) return true;
  bool ok = true;
  const std::vector<std::string> names(allowed.begin(), allowed.end());
  for (const auto& kv : map) {
    if (!kv.first.IsScalar()) {
      error(codes::kMalformedInput, "keys must be plain names", at(kv.first));
      ok = false;
      continue;
    }
    const std::string& key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    error(codes::kUnknownName,
          fmt::format("unknown key '{}'{}{} (expected one of: {})",
                      excerpt(key, 40),
                      context.empty() ? "" : fmt::format(" in {}", context),
                      did_you_mean(key, names),
                      join(allowed)),
          at(kv.first));
    ok = false;
  }
  return ok;
}

bool YamlReader::require(const YAML::Node& map, std::string_view key, std::string_view context) {
  if (map.IsMap() && map[std::string(key)]) return true;
  error(codes::kMalformedInput, fmt::format("{} needs '{}'", context, key), at(map));
  return false;
}

std::optional<std::string> YamlReader::string(const YAML::Node& node,
                                              std::string_view what,
                                              std::size_t max_bytes) {
  if (!node.IsScalar()) {
    error(codes::kMalformedInput,
          fmt::format("{} must be a single value, not {}", what, found(node)),
          at(node));
    return std::nullopt;
  }
  const std::string& s = node.Scalar();
  if (!is_valid_utf8(s)) {
    error(codes::kInvalidValue,
          fmt::format("{} '{}' is not valid UTF-8 text", what, excerpt(s, 40)),
          at(node));
    return std::nullopt;
  }
  if (s.size() > max_bytes) {
    error(codes::kInvalidValue,
          fmt::format("{} '{}' is {} bytes long; at most {} are allowed",
                      what,
                      excerpt(s, 40),
                      s.size(),
                      max_bytes),
          at(node));
    return std::nullopt;
  }
  return s;
}

std::optional<std::string> YamlReader::name(const YAML::Node& node, std::string_view what) {
  auto s = string(node, what, 128);
  if (!s) return std::nullopt;
  const bool ok = !s->empty() && std::all_of(s->begin(), s->end(), [](char c) {
    const auto u = static_cast<unsigned char>(c);
    return u >= 0x80 || std::isalnum(u) || c == '_' || c == '-';
  });
  if (!ok) {
    error(codes::kInvalidValue,
          fmt::format("{} '{}' must be a non-empty name of letters, digits, '_' or '-' (no '.', "
                      "spaces or punctuation)",
                      what,
                      excerpt(*s, 40)),
          at(node));
    return std::nullopt;
  }
  return s;
}

std::optional<double> YamlReader::number(const YAML::Node& node,
                                         std::string_view what,
                                         const NumberRange& range) {
  double v = 0;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v)) {
    error(codes::kMalformedInput,
          fmt::format("{} must be a number, not {}", what, found(node)),
          at(node));
    return std::nullopt;
  }
  if (!std::isfinite(v)) {
    error(codes::kInvalidValue,
          fmt::format("{} is {}, not a finite number", what, excerpt(node.Scalar(), 20)),
          at(node));
    return std::nullopt;
  }
  const bool below = range.exclusive_min ? !(v > range.min) : v < range.min;
  if (below || v > range.max) {
    const std::string unit = range.unit.empty() ? "" : fmt::format(" {}", range.unit);
    std::string bounds;
    if (std::isfinite(range.min) && std::isfinite(range.max)) {
      bounds = fmt::format("{} {:g} and at most {:g}{}",
                           range.exclusive_min ? "more than" : "at least",
                           range.min,
                           range.max,
                           unit);
    } else if (std::isfinite(range.min)) {
      bounds =
          range.exclusive_min && range.min == 0
              ? std::string("positive")
              : fmt::format(
                    "{} {:g}{}", range.exclusive_min ? "more than" : "at least", range.min, unit);
    } else {
      bounds = fmt::format("at most {:g}{}", range.max, unit);
    }
    error(codes::kInvalidValue,
          fmt::format("{} {:g}{} is out of range: it must be {}", what, v, unit, bounds),
          at(node));
    return std::nullopt;
  }
  return v;
}

std::optional<long long> YamlReader::integer(const YAML::Node& node,
                                             std::string_view what,
                                             long long min,
                                             long long max) {
  long long v = 0;
  if (!node.IsScalar() || !YAML::convert<long long>::decode(node, v)) {
    error(codes::kMalformedInput,
          fmt::format("{} must be a whole number, not {}", what, found(node)),
          at(node));
    return std::nullopt;
  }
  if (v < min || v > max) {
    error(codes::kInvalidValue,
          fmt::format("{} {} is out of range: it must be from {} to {}", what, v, min, max),
          at(node));
    return std::nullopt;
  }
  return v;
}

std::optional<bool> YamlReader::boolean(const YAML::Node& node, std::string_view what) {
  bool b = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b)) {
    error(codes::kMalformedInput,
          fmt::format("{} must be true or false, not {}", what, found(node)),
          at(node));
    return std::nullopt;
  }
  return b;
}

std::optional<std::vector<double>> YamlReader::numbers(const YAML::Node& node,
                                                       std::string_view what,
                                                       std::size_t count,
                                                       const NumberRange& range,
                                                       std::size_t max_count) {
  if (!node.IsSequence() || (count > 0 && node.size() != count)) {
    error(codes::kMalformedInput,
          count > 0
              ? fmt::format("{} must be a list of {} numbers, not {}", what, count, found(node))
              : fmt::format("{} must be a list of numbers, not {}", what, found(node)),
          at(node));
    return std::nullopt;
  }
  if (node.size() > max_count) {
    error(codes::kLimitExceeded,
          fmt::format("{} has {} numbers; at most {} are allowed", what, node.size(), max_count),
          at(node));
    return std::nullopt;
  }
  std::vector<double> out;
  out.reserve(node.size());
  for (const YAML::Node& item : node) {
    auto v = number(item, what, range);
    if (!v) return std::nullopt;
    out.push_back(*v);
  }
  return out;
}

std::optional<Vec3> YamlReader::vec3(const YAML::Node& node,
                                     std::string_view what,
                                     const NumberRange& range) {
  auto v = numbers(node, what, 3, range);
  if (!v) return std::nullopt;
  return Vec3((*v)[0], (*v)[1], (*v)[2]);
}

std::optional<Frame> YamlReader::frame(const YAML::Node& node, std::string_view what) {
  if (!node.IsMap()) {
    error(codes::kMalformedInput,
          fmt::format(
              "{} must be a mapping {{pos: [x, y, z], rot: [a, b, c]}}, not {}", what, found(node)),
          at(node));
    return std::nullopt;
  }
  const int before = errors_;
  check_keys(node, {"pos", "rot"}, what);
  Frame f;
  if (const YAML::Node p = node["pos"]) {
    if (auto v =
            vec3(p, fmt::format("{} pos", what), {-kMaxCoordinateMm, kMaxCoordinateMm, "mm"})) {
      f.pos = *v;
    }
  }
  if (const YAML::Node r = node["rot"]) {
    if (auto v = vec3(r, fmt::format("{} rot", what), {-36000, 36000, "degrees"})) f.rot = *v;
  }
  if (errors_ > before) return std::nullopt;
  return f;
}

bool YamlReader::is_list(const YAML::Node& node, std::string_view what, bool allow_single) {
  if (node.IsSequence() || (allow_single && node.IsMap())) return true;
  error(codes::kMalformedInput,
        fmt::format("{} must be a list, not {}", what, found(node)),
        at(node));
  return false;
}

bool YamlReader::is_mapping(const YAML::Node& node, std::string_view what) {
  if (node.IsMap()) return true;
  error(codes::kMalformedInput,
        fmt::format("{} must be a mapping, not {}", what, found(node)),
        at(node));
  return false;
}

std::optional<KitTag> YamlReader::kit_tag(const YAML::Node& root,
                                          std::span<const std::string_view> known) {
  const YAML::Node tag = root.IsMap() ? root["fabkit"] : YAML::Node();
  if (!tag) {
    error(codes::kUnknownKit,
          fmt::format("the file has no 'fabkit:' header naming its kit; start it with one of: "
                      "fabkit: {}",
                      known_kits(known)),
          start());
    return std::nullopt;
  }
  const auto s = string(tag, "the fabkit: header", 64);
  if (!s) return std::nullopt;
  KitTag out;
  out.where = at(tag);
  const auto slash = s->find('/');
  std::string kit = s->substr(0, slash);
  int version = 0;
  bool ok = slash != std::string::npos && slash + 1 < s->size();
  if (ok) {
    for (char c : s->substr(slash + 1)) {
      ok = ok && c >= '0' && c <= '9';
      if (ok) version = std::min(version * 10 + (c - '0'), 100000);
    }
  }
  const bool known_kit = std::find(known.begin(), known.end(), kit) != known.end();
  if (!ok || !known_kit) {
    const std::vector<std::string> names(known.begin(), known.end());
    error(codes::kUnknownKit,
          fmt::format("unknown kit '{}' in the fabkit: header{} (known: {})",
                      excerpt(*s, 40),
                      known_kit ? "; write it as <kit>/<version>" : did_you_mean(kit, names),
                      known_kits(known)),
          out.where);
    return std::nullopt;
  }
  out.kit = std::move(kit);
  out.version = version;
  return out;
}

std::optional<KitTag> read_kit_tag(std::string_view text,
                                   std::string_view file,
                                   std::span<const std::string_view> known,
                                   Diagnostics& diags) {
  YamlReader in{std::string(file), diags};
  const auto root = in.parse_mapping(text, "a 'fabkit: <kit>/1' header");
  if (!root) return std::nullopt;
  return in.kit_tag(*root, known);
}

}  // namespace fabkit

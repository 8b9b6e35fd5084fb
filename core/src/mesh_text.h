#pragma once
// Helpers shared by the mesh readers and writers (obj.cpp, stl.cpp): line and token scanning
// with positions for messages, number parsing, and the checks every writer makes.

#include <fmt/format.h>

#include <array>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"
#include "fabkit/core/text.h"

namespace fabkit::mesh_detail {

inline bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

/// A whitespace-separated word of a line with its 1-based column.
struct Token {
  std::string_view text;
  int column = 0;
};

inline std::vector<Token> tokenize(std::string_view line) {
  std::vector<Token> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && is_space(line[i])) ++i;
    if (i >= line.size()) break;
    const std::size_t begin = i;
    while (i < line.size() && !is_space(line[i])) ++i;
    tokens.push_back({line.substr(begin, i - begin), static_cast<int>(begin) + 1});
  }
  return tokens;
}

/// Parses the whole of `s` as a double (a leading '+' is accepted); nullopt otherwise.
/// NaN and infinities parse; callers check finiteness separately to report them precisely.
inline std::optional<double> parse_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

/// Parses the whole of `s` as an int (a leading '+' is accepted); nullopt otherwise.
inline std::optional<long long> parse_int(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  long long value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

/// Splits `text` into lines (without the terminator) and calls `fn(line, line_number)` until it
/// returns false. Returns false if `fn` stopped early.
template <class Fn>
inline bool for_each_line(std::string_view text, Fn&& fn) {
  int number = 0;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    ++number;
    if (!fn(text.substr(pos, end - pos), number)) return false;
    pos = end + 1;
  }
  return true;
}

/// Deduplicates vertices by exact position (STL stores each triangle's corners separately).
class VertexWelder {
 public:
  explicit VertexWelder(TriangleMesh& mesh) : mesh_(mesh) {}
  int index(const Vec3& p) {
    // + 0.0 turns -0 into +0 so that both spellings of zero weld.
    const std::array<double, 3> key{p.x() + 0.0, p.y() + 0.0, p.z() + 0.0};
    const auto [it, inserted] = map_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.emplace_back(key[0], key[1], key[2]);
    return it->second;
  }

 private:
  TriangleMesh& mesh_;
  std::map<std::array<double, 3>, int> map_;
};

/// Checks that `mesh` can be written: it has faces, valid indices and finite coordinates.
inline bool check_writable(const TriangleMesh& mesh, const std::string& name, Diagnostics& diags) {
  if (mesh.faces.empty()) {
    diags.error(codes::kInvalidValue,
                fmt::format("cannot write '{}': the mesh has no faces", name),
                SourceLocation{name, 0, 0});
    return false;
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      diags.error(codes::kInvalidValue,
                  fmt::format("cannot write '{}': vertex {} has a non-finite coordinate", name, i),
                  SourceLocation{name, 0, 0});
      return false;
    }
  }
  const auto nv = static_cast<long long>(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.faces.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      const long long idx = mesh.faces[i][c];
      if (idx < 0 || idx >= nv) {
        diags.error(
            codes::kInvalidValue,
            fmt::format("cannot write '{}': face {} refers to vertex {} of {}", name, i, idx, nv),
            SourceLocation{name, 0, 0});
        return false;
      }
    }
  }
  return true;
}

/// Coordinates are written with 9 significant digits (enough to round-trip a float, sub-micron
/// on metre-sized parts); -0 is written as 0 so that output does not depend on the sign of zero.
inline double canonical(double x) {
  return x + 0.0;
}

}  // namespace fabkit::mesh_detail

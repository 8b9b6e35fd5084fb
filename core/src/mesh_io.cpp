#include "fabkit/core/mesh_io.h"

#include <fmt/format.h>

#include <array>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <string_view>
#include <system_error>
#include <vector>

#include "fabkit/core/file_io.h"

namespace fabkit {
namespace {

namespace fs = std::filesystem;

constexpr std::string_view kSupported = ".obj, .stl";
constexpr std::size_t kStlHeaderSize = 80;
constexpr std::size_t kStlPreambleSize = 84;  // header + uint32 triangle count
constexpr std::size_t kStlTriangleSize = 50;  // 12 floats + uint16 attribute

std::string lower(std::string s) {
  for (char& c : s) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return s;
}

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
}

/// A whitespace-separated word of a line with its 1-based column.
struct Token {
  std::string_view text;
  int column = 0;
};

std::vector<Token> tokenize(std::string_view line) {
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
std::optional<double> parse_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size()) return std::nullopt;
  return value;
}

/// Parses the whole of `s` as an int (a leading '+' is accepted); nullopt otherwise.
std::optional<long long> parse_int(std::string_view s) {
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
bool for_each_line(std::string_view text, Fn&& fn) {
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

// ---------------------------------------------------------------------------------------------
// OBJ

/// A face corner whose positive index could only be checked once all vertices are known.
struct PendingIndex {
  long long index;  // 1-based
  int line;
  int column;
};

std::optional<TriangleMesh> parse_obj(std::string_view text,
                                      const std::string& name,
                                      Diagnostics& diags) {
  TriangleMesh mesh;
  std::vector<PendingIndex> pending;
  bool ok = true;
  auto fail = [&](DiagnosticCode code, std::string message, int line, int column) {
    diags.error(code, fmt::format("{}: {}", name, message), SourceLocation{name, line, column});
    ok = false;
    return false;
  };

  for_each_line(text, [&](std::string_view line, int number) {
    if (const auto hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    const auto tokens = tokenize(line);
    if (tokens.empty()) return true;
    const std::string_view keyword = tokens[0].text;
    if (keyword == "v") {
      // x y z, optionally followed by w or r g b, which are ignored.
      if (tokens.size() < 4) {
        return fail(codes::kMalformedInput,
                    "vertex record needs three coordinates",
                    number,
                    tokens[0].column);
      }
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        const Token& t = tokens[k + 1];
        const auto value = parse_double(t.text);
        if (!value) {
          return fail(codes::kMalformedInput,
                      fmt::format("malformed vertex coordinate '{}'", t.text),
                      number,
                      t.column);
        }
        if (!std::isfinite(*value)) {
          return fail(codes::kInvalidValue,
                      fmt::format("non-finite vertex coordinate '{}'", t.text),
                      number,
                      t.column);
        }
        p[k] = *value;
      }
      for (std::size_t k = 4; k < tokens.size(); ++k) {
        if (!parse_double(tokens[k].text)) {
          return fail(codes::kMalformedInput,
                      fmt::format("malformed number '{}' in vertex record", tokens[k].text),
                      number,
                      tokens[k].column);
        }
      }
      mesh.vertices.push_back(p);
      return true;
    }
    if (keyword != "f") return true;  // vt, vn, o, g, s, usemtl, mtllib, l, p, ... are ignored

    if (tokens.size() < 4) {
      return fail(codes::kMalformedInput,
                  "face record needs at least three vertices",
                  number,
                  tokens[0].column);
    }
    // Each corner is v, v/vt, v/vt/vn or v//vn; only v is used, the others must be integers.
    std::vector<long long> corners;  // resolved 1-based indices (positive)
    for (std::size_t k = 1; k < tokens.size(); ++k) {
      const Token& t = tokens[k];
      std::string_view parts[3];
      int count = 0;
      std::size_t pos = 0;
      bool bad = false;
      while (true) {
        const std::size_t slash = t.text.find('/', pos);
        if (count == 3) {
          bad = true;
          break;
        }
        parts[count++] = t.text.substr(pos, slash == std::string_view::npos ? slash : slash - pos);
        if (slash == std::string_view::npos) break;
        pos = slash + 1;
      }
      std::optional<long long> v = bad ? std::nullopt : parse_int(parts[0]);
      for (int p = 1; p < count && v; ++p) {
        if (!parts[p].empty() && !parse_int(parts[p])) v = std::nullopt;
      }
      if (count == 3 && parts[1].empty() && parts[2].empty()) v = std::nullopt;  // "1//"
      if (count == 2 && parts[1].empty()) v = std::nullopt;                      // "1/"
      if (!v) {
        return fail(codes::kMalformedInput,
                    fmt::format("malformed face vertex '{}'", t.text),
                    number,
                    t.column);
      }
      const auto defined = static_cast<long long>(mesh.vertices.size());
      long long index = *v;
      if (index < 0) {
        index = defined + 1 + index;  // -1 is the most recently defined vertex
        if (index < 1) {
          return fail(
              codes::kMalformedInput,
              fmt::format(
                  "face vertex index {} is out of range ({} vertices defined)", *v, defined),
              number,
              t.column);
        }
      } else if (index == 0) {
        return fail(codes::kMalformedInput,
                    "face vertex index 0 is out of range (OBJ indices start at 1)",
                    number,
                    t.column);
      } else if (index > std::numeric_limits<int>::max()) {
        return fail(codes::kMalformedInput,
                    fmt::format("face vertex index {} is out of range", *v),
                    number,
                    t.column);
      }
      corners.push_back(index);
      if (index > defined) {
        // Checked after parsing: some writers emit faces before their vertices.
        pending.push_back({index, number, t.column});
      }
    }
    // Fan triangulation of the polygon (0, i, i + 1).
    for (std::size_t i = 1; i + 1 < corners.size(); ++i) {
      mesh.faces.emplace_back(static_cast<int>(corners[0] - 1),
                              static_cast<int>(corners[i] - 1),
                              static_cast<int>(corners[i + 1] - 1));
    }
    return true;
  });
  if (!ok) return std::nullopt;

  const auto total = static_cast<long long>(mesh.vertices.size());
  for (const auto& p : pending) {
    if (p.index > total) {
      fail(codes::kMalformedInput,
           fmt::format(
               "face vertex index {} is out of range ({} vertices in the file)", p.index, total),
           p.line,
           p.column);
      return std::nullopt;
    }
  }
  if (mesh.faces.empty()) {
    diags.error(codes::kMalformedInput,
                fmt::format("{}: the mesh has no faces", name),
                SourceLocation{name, 0, 0});
    return std::nullopt;
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// STL

std::uint32_t read_u32_le(const char* p) {
  const auto* b = reinterpret_cast<const unsigned char*>(p);
  return static_cast<std::uint32_t>(b[0]) | (static_cast<std::uint32_t>(b[1]) << 8) |
         (static_cast<std::uint32_t>(b[2]) << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
}

float read_f32_le(const char* p) {
  return std::bit_cast<float>(read_u32_le(p));
}

void write_u32_le(std::string& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFFu));
}

void write_f32_le(std::string& out, float f) {
  write_u32_le(out, std::bit_cast<std::uint32_t>(f));
}

/// True when `bytes` begins (after optional whitespace) with the keyword "solid".
bool starts_with_solid(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && is_space(bytes[i])) ++i;
  if (bytes.substr(i, 5) != "solid") return false;
  return i + 5 == bytes.size() || is_space(bytes[i + 5]);
}

/// True when every byte is printable ASCII or whitespace (binary float data almost never is).
bool looks_like_text(std::string_view bytes) {
  for (const char c : bytes) {
    const auto u = static_cast<unsigned char>(c);
    if (u >= 0x7F || (u < 0x20 && !is_space(c))) return false;
  }
  return true;
}

/// Binary if the size is exactly 84 + 50·n for the stored n, unless the file is plainly an
/// ASCII STL ("solid" followed by text only). Otherwise ASCII if it starts with "solid".
enum class StlKind { kBinary, kAscii, kUnknown };

StlKind detect_stl(std::string_view bytes) {
  const bool solid = starts_with_solid(bytes);
  if (bytes.size() >= kStlPreambleSize) {
    const std::uint64_t n = read_u32_le(bytes.data() + kStlHeaderSize);
    if (kStlPreambleSize + kStlTriangleSize * n == bytes.size()) {
      return solid && looks_like_text(bytes) ? StlKind::kAscii : StlKind::kBinary;
    }
  }
  return solid ? StlKind::kAscii : StlKind::kUnknown;
}

std::optional<TriangleMesh> parse_stl_binary(std::string_view bytes,
                                             const std::string& name,
                                             Diagnostics& diags) {
  TriangleMesh mesh;
  VertexWelder welder(mesh);
  const std::uint32_t n = read_u32_le(bytes.data() + kStlHeaderSize);
  mesh.faces.reserve(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* rec = bytes.data() + kStlPreambleSize + kStlTriangleSize * t;
    Eigen::Vector3i face;
    for (int c = 0; c < 3; ++c) {
      Vec3 p;
      for (int k = 0; k < 3; ++k) {
        p[k] = static_cast<double>(read_f32_le(rec + 12 + 12 * c + 4 * k));
      }
      if (!p.allFinite()) {
        diags.error(codes::kInvalidValue,
                    fmt::format("{}: triangle {} has a non-finite vertex coordinate", name, t + 1),
                    SourceLocation{name, 0, 0});
        return std::nullopt;
      }
      face[c] = welder.index(p);
    }
    mesh.faces.push_back(face);
  }
  return mesh;
}

std::optional<TriangleMesh> parse_stl_ascii(std::string_view text,
                                            const std::string& name,
                                            Diagnostics& diags) {
  TriangleMesh mesh;
  VertexWelder welder(mesh);
  enum class State { kOutside, kInSolid, kInFacet, kInLoop, kAfterLoop };
  State state = State::kOutside;
  std::vector<int> loop;
  int last_line = 0;
  bool ok = true;
  auto fail = [&](DiagnosticCode code, std::string message, int line, int column) {
    diags.error(code, fmt::format("{}: {}", name, message), SourceLocation{name, line, column});
    ok = false;
    return false;
  };
  auto parse_vec = [&](const std::vector<Token>& tokens,
                       std::size_t first,
                       int number,
                       std::string_view what) -> std::optional<Vec3> {
    if (tokens.size() != first + 3) {
      fail(codes::kMalformedInput,
           fmt::format("'{}' needs exactly three numbers", what),
           number,
           tokens[0].column);
      return std::nullopt;
    }
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      const Token& t = tokens[first + k];
      const auto value = parse_double(t.text);
      if (!value) {
        fail(
            codes::kMalformedInput, fmt::format("malformed number '{}'", t.text), number, t.column);
        return std::nullopt;
      }
      if (!std::isfinite(*value)) {
        fail(codes::kInvalidValue, fmt::format("non-finite number '{}'", t.text), number, t.column);
        return std::nullopt;
      }
      p[k] = *value;
    }
    return p;
  };

  for_each_line(text, [&](std::string_view line, int number) {
    last_line = number;
    const auto tokens = tokenize(line);
    if (tokens.empty()) return true;
    const std::string keyword = lower(std::string(tokens[0].text));
    auto unexpected = [&] {
      return fail(codes::kMalformedInput,
                  fmt::format("unexpected '{}'", tokens[0].text),
                  number,
                  tokens[0].column);
    };
    switch (state) {
      case State::kOutside:
        if (keyword != "solid") return unexpected();
        state = State::kInSolid;
        return true;
      case State::kInSolid:
        if (keyword == "endsolid") {
          state = State::kOutside;
          return true;
        }
        if (keyword != "facet") return unexpected();
        if (tokens.size() < 2 || lower(std::string(tokens[1].text)) != "normal") {
          return fail(
              codes::kMalformedInput, "expected 'facet normal nx ny nz'", number, tokens[0].column);
        }
        if (!parse_vec(tokens, 2, number, "facet normal")) return false;
        state = State::kInFacet;
        return true;
      case State::kInFacet:
        if (keyword != "outer" || tokens.size() != 2 ||
            lower(std::string(tokens[1].text)) != "loop") {
          return fail(codes::kMalformedInput, "expected 'outer loop'", number, tokens[0].column);
        }
        loop.clear();
        state = State::kInLoop;
        return true;
      case State::kInLoop:
        if (keyword == "vertex") {
          const auto p = parse_vec(tokens, 1, number, "vertex");
          if (!p) return false;
          loop.push_back(welder.index(*p));
          return true;
        }
        if (keyword != "endloop") return unexpected();
        if (loop.size() < 3) {
          return fail(codes::kMalformedInput,
                      "a facet needs at least three vertices",
                      number,
                      tokens[0].column);
        }
        for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
          mesh.faces.emplace_back(loop[0], loop[i], loop[i + 1]);
        }
        state = State::kAfterLoop;
        return true;
      case State::kAfterLoop:
        if (keyword != "endfacet") return unexpected();
        state = State::kInSolid;
        return true;
    }
    return true;
  });
  if (!ok) return std::nullopt;
  if (state != State::kOutside && state != State::kInSolid) {
    fail(codes::kMalformedInput, "unexpected end of file inside a facet", last_line, 0);
    return std::nullopt;
  }
  // A missing final "endsolid" is tolerated: many writers truncate it.
  return mesh;
}

std::optional<TriangleMesh> parse_stl(std::string_view bytes,
                                      const std::string& name,
                                      Diagnostics& diags) {
  std::optional<TriangleMesh> mesh;
  switch (detect_stl(bytes)) {
    case StlKind::kBinary:
      mesh = parse_stl_binary(bytes, name, diags);
      break;
    case StlKind::kAscii:
      mesh = parse_stl_ascii(bytes, name, diags);
      break;
    case StlKind::kUnknown:
      if (bytes.size() >= kStlPreambleSize) {
        const std::uint64_t n = read_u32_le(bytes.data() + kStlHeaderSize);
        diags.error(codes::kMalformedInput,
                    fmt::format("{}: not an STL file: binary STL with {} triangles should be {} "
                                "bytes, the file has {}, and it does not start with 'solid'",
                                name,
                                n,
                                kStlPreambleSize + kStlTriangleSize * n,
                                bytes.size()),
                    SourceLocation{name, 0, 0});
      } else {
        diags.error(codes::kMalformedInput,
                    fmt::format("{}: not an STL file: too short for binary STL ({} bytes) and "
                                "does not start with 'solid'",
                                name,
                                bytes.size()),
                    SourceLocation{name, 0, 0});
      }
      return std::nullopt;
  }
  if (!mesh) return std::nullopt;
  if (mesh->faces.empty()) {
    diags.error(codes::kMalformedInput,
                fmt::format("{}: the mesh has no faces", name),
                SourceLocation{name, 0, 0});
    return std::nullopt;
  }
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Writing

/// Checks that `mesh` can be written: it has faces, valid indices and finite coordinates.
bool check_writable(const TriangleMesh& mesh, const std::string& name, Diagnostics& diags) {
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
double canonical(double x) {
  return x + 0.0;
}

}  // namespace

std::optional<TriangleMesh> read_mesh(const std::filesystem::path& path, Diagnostics& diags) {
  const std::string name = path.string();
  const std::string ext = lower(path.extension().string());
  if (ext != ".obj" && ext != ".stl") {
    diags.error(codes::kUnreadableFile,
                fmt::format("cannot read mesh '{}': unsupported extension '{}' (supported: {})",
                            name,
                            path.extension().string(),
                            kSupported),
                SourceLocation{name, 0, 0});
    return std::nullopt;
  }
  const auto bytes = read_input_file(path, "mesh", diags);
  if (!bytes) return std::nullopt;
  if (ext == ".obj") return parse_obj(*bytes, name, diags);
  return parse_stl(*bytes, name, diags);
}

bool write_obj(const TriangleMesh& mesh, const std::filesystem::path& path, Diagnostics& diags) {
  if (!check_writable(mesh, path.string(), diags)) return false;
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out),
                 "# fabkit mesh: {} vertices, {} triangles\n",
                 mesh.vertices.size(),
                 mesh.faces.size());
  for (const auto& v : mesh.vertices) {
    fmt::format_to(std::back_inserter(out),
                   "v {:.9g} {:.9g} {:.9g}\n",
                   canonical(v.x()),
                   canonical(v.y()),
                   canonical(v.z()));
  }
  for (const auto& f : mesh.faces) {
    fmt::format_to(std::back_inserter(out), "f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1);
  }
  return write_file_atomically(path, std::string_view(out.data(), out.size()), diags);
}

bool write_stl(const TriangleMesh& mesh, const std::filesystem::path& path, Diagnostics& diags) {
  const std::string name = path.string();
  if (!check_writable(mesh, name, diags)) return false;
  if (mesh.faces.size() > std::numeric_limits<std::uint32_t>::max()) {
    diags.error(codes::kInvalidValue,
                fmt::format("cannot write '{}': too many triangles for binary STL", name),
                SourceLocation{name, 0, 0});
    return false;
  }
  std::string out;
  out.reserve(kStlPreambleSize + kStlTriangleSize * mesh.faces.size());
  // The header must not start with "solid", or readers would take the file for ASCII STL.
  std::string header = "fabkit binary STL";
  header.resize(kStlHeaderSize, ' ');
  out += header;
  write_u32_le(out, static_cast<std::uint32_t>(mesh.faces.size()));
  for (const auto& f : mesh.faces) {
    const Vec3& a = mesh.vertices[f[0]];
    const Vec3& b = mesh.vertices[f[1]];
    const Vec3& c = mesh.vertices[f[2]];
    Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    n = len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3::Zero();
    for (const Vec3* p : std::array<const Vec3*, 4>{&n, &a, &b, &c}) {
      for (int k = 0; k < 3; ++k) write_f32_le(out, static_cast<float>((*p)[k]) + 0.0f);
    }
    out.push_back('\0');  // attribute byte count (uint16) = 0
    out.push_back('\0');
  }
  return write_file_atomically(path, out, diags);
}

}  // namespace fabkit

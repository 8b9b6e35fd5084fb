// STL: reading (ASCII or binary, told apart by content) and writing binary STL.
#include <fmt/format.h>

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <map>
#include <string_view>
#include <vector>

#include "fabkit/core/file_io.h"
#include "fabkit/core/mesh_io.h"
#include "fabkit/core/text.h"
#include "mesh_text.h"

namespace fabkit {
namespace {

using namespace mesh_detail;

constexpr std::size_t kStlHeaderSize = 80;
constexpr std::size_t kStlPreambleSize = 84;  // header + uint32 triangle count
constexpr std::size_t kStlTriangleSize = 50;  // 12 floats + uint16 attribute

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
        fail(codes::kMalformedInput,
             fmt::format("malformed number '{}'", excerpt(t.text, 40)),
             number,
             t.column);
        return std::nullopt;
      }
      if (!std::isfinite(*value)) {
        fail(codes::kInvalidValue,
             fmt::format("non-finite number '{}'", excerpt(t.text, 40)),
             number,
             t.column);
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
    const std::string keyword = ascii_lower(tokens[0].text);
    auto unexpected = [&] {
      return fail(codes::kMalformedInput,
                  fmt::format("unexpected '{}'", excerpt(tokens[0].text, 40)),
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
        if (tokens.size() < 2 || ascii_lower(tokens[1].text) != "normal") {
          return fail(
              codes::kMalformedInput, "expected 'facet normal nx ny nz'", number, tokens[0].column);
        }
        if (!parse_vec(tokens, 2, number, "facet normal")) return false;
        state = State::kInFacet;
        return true;
      case State::kInFacet:
        if (keyword != "outer" || tokens.size() != 2 || ascii_lower(tokens[1].text) != "loop") {
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

}  // namespace

std::optional<TriangleMesh> read_stl_bytes(std::string_view bytes,
                                           const std::string& name,
                                           Diagnostics& diags) {
  return parse_stl(bytes, name, diags);
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

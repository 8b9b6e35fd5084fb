// Wavefront OBJ: reading (v/f records; polygons fan-triangulated) and writing.
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
                      fmt::format("malformed vertex coordinate '{}'", excerpt(t.text, 40)),
                      number,
                      t.column);
        }
        if (!std::isfinite(*value)) {
          return fail(codes::kInvalidValue,
                      fmt::format("non-finite vertex coordinate '{}'", excerpt(t.text, 40)),
                      number,
                      t.column);
        }
        p[k] = *value;
      }
      for (std::size_t k = 4; k < tokens.size(); ++k) {
        if (!parse_double(tokens[k].text)) {
          return fail(
              codes::kMalformedInput,
              fmt::format("malformed number '{}' in vertex record", excerpt(tokens[k].text, 40)),
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
                    fmt::format("malformed face vertex '{}'", excerpt(t.text, 40)),
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

}  // namespace

std::optional<TriangleMesh> read_obj_text(std::string_view text,
                                          const std::string& name,
                                          Diagnostics& diags) {
  return parse_obj(text, name, diags);
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

}  // namespace fabkit

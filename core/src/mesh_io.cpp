// Reading a mesh file by its extension (obj.cpp, stl.cpp do the formats).
#include "fabkit/core/mesh_io.h"

#include <fmt/format.h>

#include "fabkit/core/file_io.h"
#include "fabkit/core/text.h"
#include "mesh_text.h"

namespace fabkit {
namespace {
constexpr std::string_view kSupported = ".obj, .stl";
}  // namespace

std::optional<TriangleMesh> read_mesh(const std::filesystem::path& path, Diagnostics& diags) {
  const std::string name = path.string();
  const std::string ext = ascii_lower(path.extension().string());
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
  if (ext == ".obj") return read_obj_text(*bytes, name, diags);
  return read_stl_bytes(*bytes, name, diags);
}

}  // namespace fabkit

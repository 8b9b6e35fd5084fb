#pragma once
/// Reading and writing triangle meshes (OBJ and STL).

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"

namespace fabkit {

/// Reads an OBJ (v/f records; polygons fan-triangulated) or STL (ASCII or binary) file,
/// chosen by extension. On failure returns nullopt and adds a diagnostic naming the file
/// and, where possible, the line.
std::optional<TriangleMesh> read_mesh(const std::filesystem::path& path, Diagnostics& diags);

/// Parses OBJ text (`name` for messages); the reader behind read_mesh, for fuzzing and memory.
std::optional<TriangleMesh> read_obj_text(std::string_view text,
                                          const std::string& name,
                                          Diagnostics& diags);
/// Parses STL bytes, ASCII or binary.
std::optional<TriangleMesh> read_stl_bytes(std::string_view bytes,
                                           const std::string& name,
                                           Diagnostics& diags);

/// Writes a Wavefront OBJ. Writes to a temporary file and renames it, so no partial file is
/// left behind on failure. Returns false and adds a diagnostic on failure.
bool write_obj(const TriangleMesh& mesh, const std::filesystem::path& path, Diagnostics& diags);

/// Writes a binary STL (same atomic-write guarantee as write_obj).
bool write_stl(const TriangleMesh& mesh, const std::filesystem::path& path, Diagnostics& diags);

}  // namespace fabkit

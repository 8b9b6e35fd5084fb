#pragma once
/// 3MF files for slicers (lib3mf): many named solids in one file, in mm.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"

namespace fabkit {

/// One object of a 3MF build: a mesh (mm, its own frame) placed by `transform` on the plate.
struct ThreeMfObject {
  std::string name;
  TriangleMesh mesh;
  Mat4 transform = Mat4::Identity();  ///< rigid placement on the build plate (mm)
};

/// The bytes of a 3MF package (unit millimetre, one mesh object and build item per object);
/// nullopt with a diagnostic if lib3mf refuses (non-finite vertex, bad index).
std::optional<std::string> encode_3mf(const std::vector<ThreeMfObject>& objects,
                                      Diagnostics& diags);
/// encode_3mf, written atomically to `path`.
bool write_3mf(const std::vector<ThreeMfObject>& objects,
               const std::filesystem::path& path,
               Diagnostics& diags);
/// Reads the build items of a 3MF package (for round trips and tests): names, meshes, and
/// transforms; nullopt with a diagnostic naming `what` if it cannot be read.
std::optional<std::vector<ThreeMfObject>> decode_3mf(const std::string& bytes,
                                                     std::string_view what,
                                                     Diagnostics& diags);

}  // namespace fabkit

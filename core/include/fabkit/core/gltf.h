#pragma once
/// Writing scenes as binary glTF 2.0 (.glb).

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"

namespace fabkit {

/// One named object of a scene: a mesh in its own coordinates (mm), placed by `transform`.
struct SceneObject {
  std::string name;
  TriangleMesh mesh;
  Mat4 transform = Mat4::Identity();
  std::array<float, 4> color{0.7f, 0.7f, 0.7f, 1.0f};  ///< linear RGBA base colour
};

struct GlbOptions {
  /// fabkit works in mm with z up; glTF is metres with y up. The writer scales by 1/1000 and
  /// turns z up into y up on a root node, so viewers show the true size.
  bool convert_to_gltf_axes_and_metres = true;
  std::string root_name = "fabkit";
};

/// The .glb bytes of a scene with one node (and mesh, material) per object; nullopt with a
/// diagnostic if it cannot be encoded (non-finite vertices).
std::optional<std::string> encode_glb(const std::vector<SceneObject>& objects,
                                      Diagnostics& diags,
                                      const GlbOptions& options = {});

/// Writes a .glb with one node (and mesh, material) per object. Writes a temporary file and
/// renames it; on failure adds a diagnostic and leaves no file.
bool write_glb(const std::vector<SceneObject>& objects,
               const std::filesystem::path& path,
               Diagnostics& diags,
               const GlbOptions& options = {});

}  // namespace fabkit

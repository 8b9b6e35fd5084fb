#pragma once
/// Exports of a solved assembly: result.json (docs/result-format.md), scene.glb, a preview
/// picture (preview.svg), STL, OBJ.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/gltf.h"
#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/part_solid.h"
#include "fabkit/hacks/solve.h"

namespace fabkit::hacks {

/// result.json as text (2-space indented, keys in a fixed order, no timestamps).
std::string result_json(const Assembly& assembly,
                        const SolveResult& result,
                        std::string_view design_name);

/// Scene objects of the solved assembly: one per part, placed at its solved frame, coloured
/// by role (environment grey, hack parts blue, target orange), plus a red marker at each
/// slipping connection.
std::vector<SceneObject> solution_scene(const Assembly& assembly, const SolveResult& result);

/// The same scene with every part as one closed solid (part_solid.h: the exact union of its
/// pieces in the part's frame, placed at its solved frame; mm), as the files to build from
/// hold it, and without the slipping markers. Each part type is unioned once through `solids`.
/// A part that cannot be made one solid keeps its display mesh and adds a not-a-solid warning
/// to `diags`.
std::vector<SceneObject> solid_scene(const Assembly& assembly,
                                     const SolveResult& result,
                                     PartSolidCache& solids,
                                     Diagnostics& diags);

/// All parts' display meshes placed in world coordinates (mm), as one mesh.
TriangleMesh solution_mesh(const Assembly& assembly, const SolveResult& result);

struct ExportOptions {
  std::string design_name;
  std::string basename = "assembly";  ///< <basename>.stl / .obj
  /// Solids computed before (a session exporting again); nullptr: a cache for this export.
  PartSolidCache* solids = nullptr;
};

/// Writes result.json, scene.glb, preview.svg, <basename>.stl and <basename>.obj into `directory`
/// (created if needed). Every file holds each part as one closed solid (solid_scene); the
/// glTF scene and the preview add a red marker at each slipping connection. Each file is written
/// atomically; returns false with diagnostics if any could not be written, and adds a
/// not-a-solid warning for a part exported as its display mesh.
bool export_solution(const Assembly& assembly,
                     const SolveResult& result,
                     const std::filesystem::path& directory,
                     Diagnostics& diags,
                     const ExportOptions& options = {});

}  // namespace fabkit::hacks

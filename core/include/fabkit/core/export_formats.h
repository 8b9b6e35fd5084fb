#pragma once
/// The formats a scene (named meshes placed in the world, mm) can be written in, as one table:
/// each format has a writer and a line of description, so front ends list and pick formats the
/// same way and a kit adds its formats in one place.
///
///   for (const ExportFormat& f : export_formats()) ...
///   write_scene("stl", objects, "out/assembly.stl", diags);

#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/gltf.h"

namespace fabkit {

struct ExportFormat {
  std::string_view name;         ///< "stl"
  std::string_view extension;    ///< ".stl"
  std::string_view description;  ///< "binary STL: one merged mesh, for slicers"
  /// Writes the objects to `path` (atomically); false with a diagnostic on failure.
  bool (*write)(const std::vector<SceneObject>& objects,
                const std::filesystem::path& path,
                Diagnostics& diags);
};

/// Every format, in a fixed order: glb, stl, obj, svg (preview picture).
std::span<const ExportFormat> export_formats();
/// The format called `name` or with extension `name` (".stl"); nullptr if none.
const ExportFormat* find_export_format(std::string_view name);

/// Writes `objects` in the format `format` (a name or an extension); an I/O or input
/// diagnostic if the format is unknown or the file cannot be written.
bool write_scene(std::string_view format,
                 const std::vector<SceneObject>& objects,
                 const std::filesystem::path& path,
                 Diagnostics& diags);

/// All objects' meshes placed by their transforms, as one mesh (mm).
TriangleMesh merged_mesh(const std::vector<SceneObject>& objects);

}  // namespace fabkit

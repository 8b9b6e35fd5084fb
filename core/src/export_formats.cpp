#include "fabkit/core/export_formats.h"

#include <fmt/format.h>

#include <array>

#include "fabkit/core/mesh_io.h"
#include "fabkit/core/svg_preview.h"

namespace fabkit {
namespace {

bool glb(const std::vector<SceneObject>& o, const std::filesystem::path& p, Diagnostics& d) {
  return write_glb(o, p, d);
}
bool stl(const std::vector<SceneObject>& o, const std::filesystem::path& p, Diagnostics& d) {
  return write_stl(merged_mesh(o), p, d);
}
bool obj(const std::vector<SceneObject>& o, const std::filesystem::path& p, Diagnostics& d) {
  return write_obj(merged_mesh(o), p, d);
}
bool svg(const std::vector<SceneObject>& o, const std::filesystem::path& p, Diagnostics& d) {
  return write_svg_preview(o, p, d);
}

constexpr std::array kFormats = {
    ExportFormat{
        "glb", ".glb", "binary glTF 2.0: one node per part, coloured, in metres with y up", glb},
    ExportFormat{"stl", ".stl", "binary STL: every part's mesh in one file, mm, for slicers", stl},
    ExportFormat{"obj", ".obj", "Wavefront OBJ: every part's mesh in one file, mm", obj},
    ExportFormat{"svg", ".svg", "a preview picture (flat-shaded, for documents)", svg},
};

}  // namespace

std::span<const ExportFormat> export_formats() {
  return kFormats;
}

const ExportFormat* find_export_format(std::string_view name) {
  for (const ExportFormat& f : kFormats) {
    if (f.name == name || f.extension == name) return &f;
  }
  return nullptr;
}

bool write_scene(std::string_view format,
                 const std::vector<SceneObject>& objects,
                 const std::filesystem::path& path,
                 Diagnostics& diags) {
  const ExportFormat* f = find_export_format(format);
  if (!f) {
    std::string known;
    for (const ExportFormat& k : kFormats)
      known += (known.empty() ? "" : ", ") + std::string(k.name);
    diags.error(codes::kUnknownName,
                fmt::format("unknown export format '{}' (known: {})", format, known),
                SourceLocation{path.string(), 0, 0});
    return false;
  }
  return f->write(objects, path, diags);
}

TriangleMesh merged_mesh(const std::vector<SceneObject>& objects) {
  TriangleMesh all;
  for (const SceneObject& o : objects) all.append(o.mesh.transformed(o.transform));
  return all;
}

}  // namespace fabkit

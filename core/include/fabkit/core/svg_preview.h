#pragma once
/// A picture of a scene as SVG: flat-shaded triangles in an orthographic view, drawn back to
/// front. For previews in documentation and reports, not for fabrication.

#include <filesystem>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/gltf.h"

namespace fabkit {

struct SvgPreviewOptions {
  Vec3 view_direction = Vec3(-1.0, -1.4, -0.8);  ///< direction the camera looks along (world)
  Vec3 up = Vec3::UnitZ();                       ///< world up
  int width_px = 640;                            ///< image width; height follows the scene
  double margin = 0.05;                          ///< fraction of the image left empty around
};

/// Writes an SVG picture of the objects (same objects as write_glb). Atomic like every
/// writer; returns false with a diagnostic on failure.
bool write_svg_preview(const std::vector<SceneObject>& objects,
                       const std::filesystem::path& path,
                       Diagnostics& diags,
                       const SvgPreviewOptions& options = {});

}  // namespace fabkit

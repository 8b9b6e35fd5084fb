#pragma once
/// Engraved joint IDs (RodSteward §4.1): a flat, visible spot chosen from random surface
/// samples by curvature (distance-weighted mean dihedral angle to the k nearest samples) plus
/// ambient occlusion (against the joint with its rods inserted); the lowest sum wins. The text
/// comes from a real font (FreeType), sized to the spot's flat radius.

#include <optional>
#include <string>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/mesh.h"

namespace fabkit::rods {

struct EngravingOptions {
  int samples = 10000;          ///< random surface samples (the paper's 10,000)
  int neighbors = 200;          ///< k nearest samples for curvature and the flat radius (k = 200)
  int occlusion_rays = 32;      ///< rays per sample over the hemisphere
  unsigned seed = 1;            ///< seeds the samples: same joint, same spot
  std::string font_file;        ///< empty: DejaVu Sans Bold (core/glyph_outline.h)
  double max_text_height = 10;  ///< mm: a large flat face still gets a modest label
};

/// Where to engrave, in the mesh's frame.
struct EngravingSpot {
  Vec3 position = Vec3::Zero();  ///< mm, on the surface
  Vec3 normal = Vec3::UnitZ();   ///< outward unit normal
  Vec3 up = Vec3::UnitY();       ///< unit text "up" in the tangent plane
  double radius = 0;             ///< mm: distance to the farthest of the k nearest samples
  double curvature = 0;          ///< rad: mean dihedral angle to the neighbours
  double occlusion = 0;          ///< fraction of hemisphere rays blocked, in [0, 1]
};

/// The spot of lowest curvature + occlusion on `mesh`; occlusion counts `occluders` too (the
/// rods in their sockets). `up_hint` (unit) orients the text (world up when assembled).
/// nullopt when the mesh has no area.
std::optional<EngravingSpot> choose_engraving_spot(const TriangleMesh& mesh,
                                                   const TriangleMesh& occluders,
                                                   const Vec3& up_hint,
                                                   const EngravingOptions& options);

/// The solid to subtract for `label` at `spot`: the text fitted in 90% of the spot's flat
/// radius (at most max_text_height tall), reaching `depth` mm below the surface and as far
/// above it. Sets `text_height` (mm) and `text_area` (mm², the inked area).
std::optional<TriangleMesh> engraving_cutter(const std::string& label,
                                             const EngravingSpot& spot,
                                             double depth,
                                             const EngravingOptions& options,
                                             Diagnostics& diags,
                                             double* text_height = nullptr,
                                             double* text_area = nullptr);

}  // namespace fabkit::rods

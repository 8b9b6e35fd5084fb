#pragma once
/// Building a design's outputs (paper §4.5 and beyond): cut sheets nested onto sheets of a
/// given size (SVG and DXF per sheet, labels and assembly marks engraved), the assembled 3D
/// model (STL and scene.glb, boards extruded with their joints) and report.json.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/json.h"
#include "fabkit/core/mesh.h"
#include "fabkit/core/nesting.h"
#include "fabkit/core/svg_sheet.h"
#include "fabkit/flatpack/check.h"

namespace fabkit::flatpack {

struct BuildOptions {
  CheckOptions check;
  std::filesystem::path output_dir;  ///< required
  /// Overrides the design's sheet settings when set.
  std::optional<NestingOptions> sheet;
  bool svg = true;
  bool dxf = true;
  bool stl = true;
  bool glb = true;
  std::optional<std::chrono::steady_clock::time_point> deadline;
};

enum class Termination {
  kBuilt,        ///< every output written (checks may still have failed: see diagnostics)
  kInvalid,      ///< the design could not be checked (input or placement errors)
  kNotNested,    ///< some piece fits on no sheet
  kWriteFailed,  ///< an output could not be written
  kTimeout,
};
std::string_view to_string(Termination t);

struct BuildSummary {
  Termination termination = Termination::kBuilt;
  Analysis analysis;
  NestingResult nesting;
  std::vector<std::filesystem::path> files;  ///< written, in order
  std::vector<StageTiming> timings;          ///< check's stages, then nest and write
  Diagnostics diagnostics;                   ///< everything (analysis's first)
};

BuildSummary build(const Design& design, const BuildOptions& options);

/// The pieces' cut outlines on their sheets, with labels.
std::vector<CutSheet> cut_sheets(const Analysis& analysis,
                                 const NestingResult& nesting,
                                 const NestingOptions& sheet,
                                 const LabelOptions& labels);

/// The assembled model: each piece's cut outline extruded to its thickness and placed; one
/// closed shell per piece.
std::vector<TriangleMesh> piece_meshes(const Analysis& analysis);

/// The sheet as the DXF writer should get it: AutoCAD 2000 DXF text is not UTF-8, so every
/// non-ASCII character of a label ("→", "Δ") is written as the DXF escape \U+XXXX, which CAD
/// programs show as that character (the SVG keeps UTF-8).
CutSheet for_dxf(CutSheet sheet);

/// report.json: pieces, joints by kind, automatic joints, warnings, sheet usage, timings.
Json report_json(const BuildSummary& summary);

}  // namespace fabkit::flatpack

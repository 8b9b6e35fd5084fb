#pragma once
/// A cut sheet for laser cutters and CNC routers — closed outlines to cut and labels to engrave,
/// in mm on a sheet of known size — and its SVG writer. The DXF writer (dxf.h) takes the same
/// sheet.
///
/// Sheet frame: origin at the lower-left corner, x to the right, y up (as in DXF); the SVG
/// writer flips y so the drawing looks the same in both.

#include <filesystem>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/polygon2d.h"

namespace fabkit {

enum class SheetLayer { kCut, kEngrave };

/// A closed outline (a polygon's outer ring or a hole), mm in the sheet frame.
struct SheetOutline {
  Ring points;
  SheetLayer layer = SheetLayer::kCut;
};

/// A single line of text to engrave, centred on `position` (mm, sheet frame).
struct SheetLabel {
  std::string text;  ///< UTF-8
  Vec2 position = Vec2::Zero();
  double height_mm = 4;
  double rotation_deg = 0;  ///< counter-clockwise
  SheetLayer layer = SheetLayer::kEngrave;
};

struct CutSheet {
  std::string name;  ///< "sheet 1"; the SVG title
  double width_mm = 600;
  double height_mm = 400;
  std::vector<SheetOutline> outlines;
  std::vector<SheetLabel> labels;

  /// Adds a polygon's outer ring and holes as cut outlines.
  void add_cut(const Polygon2d& polygon);
};

struct SvgSheetOptions {
  std::string cut_color = "#ff0000";  ///< LightBurn and most laser drivers map colours to layers
  std::string engrave_color = "#0000ff";  ///< engraved labels
  double stroke_width_mm = 0.1;  ///< hairline; cutters that want vector cuts need thin lines
  int decimals = 4;              ///< coordinates are written to 0.1 µm
  std::string font_family = "sans-serif";
};

/// The SVG text of a sheet: width and height in mm with a viewBox in mm (user unit = 1 mm), so
/// Inkscape, LightBurn and browsers import it at scale; one <g> per layer (Inkscape layers).
std::string svg_sheet(const CutSheet& sheet, const SvgSheetOptions& options = {});

/// Writes svg_sheet() atomically; an I/O diagnostic on failure.
bool write_svg_sheet(const std::filesystem::path& path,
                     const CutSheet& sheet,
                     Diagnostics& diags,
                     const SvgSheetOptions& options = {});

}  // namespace fabkit

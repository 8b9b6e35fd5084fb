#pragma once
/// Text as outlines from a real font (FreeType): closed rings in mm, for engraving labels into
/// parts and drawing them on cut sheets.

#include <Eigen/Core>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"

namespace fabkit {

/// The font used when none is given: DejaVu Sans Bold from Debian's fonts-dejavu-core (bold
/// strokes survive engraving and printing).
std::string default_font_file();

struct TextOutlineOptions {
  std::string font_file;    ///< a TrueType/OpenType file; empty: default_font_file()
  double em_size = 10;      ///< mm per em (the font's design size)
  double tolerance = 0.02;  ///< mm, largest distance of the flattened curves from the font's
};

/// A line of text laid out on the x axis from x = 0, baseline y = 0, y up (mm).
struct TextOutline {
  /// Closed rings (last point not repeated); outer boundaries and holes, told apart by
  /// nesting (core/extrude.h extrudes them directly).
  std::vector<std::vector<Eigen::Vector2d>> rings;
  Eigen::Vector2d min = Eigen::Vector2d::Zero();  ///< ink bounding box (mm)
  Eigen::Vector2d max = Eigen::Vector2d::Zero();
  double advance = 0;  ///< mm from the origin to where the next character would start
  /// Inked area (mm²): outer rings minus holes.
  double area() const;
};

/// Outlines of the UTF-8 `text`. nullopt with a diagnostic when the font cannot be opened
/// (unreadable-file, naming the file) or has no glyph for a character (invalid-value).
std::optional<TextOutline> text_outline(std::string_view text,
                                        const TextOutlineOptions& options,
                                        Diagnostics& diags);

}  // namespace fabkit

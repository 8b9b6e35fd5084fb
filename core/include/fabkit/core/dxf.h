#pragma once
/// Native DXF (AutoCAD 2000, written with dxflib) of a cut sheet: every outline a closed
/// LWPOLYLINE on the cut layer, every label a TEXT entity on the label layer, units mm
/// ($INSUNITS = 4).

#include <filesystem>
#include <optional>
#include <string>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/svg_sheet.h"

namespace fabkit {

struct DxfOptions {
  std::string cut_layer = "CUT";
  std::string label_layer = "LABELS";
  int cut_color = 1;          ///< AutoCAD colour index: 1 red
  int label_color = 5;        ///< 5 blue
  bool sheet_border = false;  ///< also draw the sheet's rectangle on a "SHEET" layer
};

/// The DXF text of a sheet; nullopt with an internal diagnostic if dxflib fails.
std::optional<std::string> dxf_sheet(const CutSheet& sheet,
                                     Diagnostics& diags,
                                     const DxfOptions& options = {});

/// Writes dxf_sheet() atomically; an I/O diagnostic on failure.
bool write_dxf(const std::filesystem::path& path,
               const CutSheet& sheet,
               Diagnostics& diags,
               const DxfOptions& options = {});

}  // namespace fabkit

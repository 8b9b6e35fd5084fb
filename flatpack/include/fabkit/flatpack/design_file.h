#pragma once
/// flatpack design files (`fabkit: flatpack/1`, docs/flatpack.md):
///
///   fabkit: flatpack/1
///   name: bookend
///   parameters:
///     l1: {value: 30, type: length}
///   material: {thickness: 3, kerf: 0.1, interference: 0.1}
///   components:
///     - {name: A, type: Rectangle, l: l1, w: 60}
///   constraints:
///     - B.w = A.w
///   connections:
///     - {connect: [A.t, B.b], alignment: front-front, rotation: [90, 0, 0]}
///   uses: {Stool: stool.yaml}        # designs used as components
///   interfaces: {front: A.b}         # what this design exports

#include <filesystem>
#include <string>
#include <string_view>

#include "fabkit/core/diagnostics.h"
#include "fabkit/flatpack/design.h"

namespace fabkit::flatpack {

struct DesignFileOptions {
  bool allow_uses = true;  ///< false: `uses:` (reading other files) is refused (servers)
  int max_depth = 8;       ///< nesting of designs used as components
  /// The file the text was read from, if any: a design that uses this file is refused at once.
  std::filesystem::path file;
};

/// Reads a design file; `diags` gets every problem with file:line:col. The design is usable
/// only when `diags` has no errors.
Design load_design(const std::filesystem::path& path,
                   Diagnostics& diags,
                   const DesignFileOptions& options = {});
Design load_design_text(std::string_view yaml,
                        std::string_view display_name,
                        Diagnostics& diags,
                        const std::filesystem::path& base_dir = {},
                        const DesignFileOptions& options = {});

/// The design as a design file (the paper's toYaml); load_design_text(to_yaml(d)) gives d back.
std::string to_yaml(const Design& design);

}  // namespace fabkit::flatpack

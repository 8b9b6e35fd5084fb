#pragma once
/// The kit's `fabkit: templates/1` YAML files (docs/templates.md), read through the core reader:
///
/// A source design (`design:`), as bundled in templates/data/designs/:
///
///   fabkit: templates/1
///   design: side_table
///   title: Side table
///   category: table
///   parts:
///     - {name: top, item: PANEL-PINE-18, center: [0, 0, 591], size: [500, 400, 18]}
///     - name: leg                       # `mirror` copies it across x = 0 and y = 0
///       item: LUM-PINE-2x2
///       min: [-230, -180, 0]
///       size: [38, 38, 582]
///       mirror: [x, y]
///       names: [leg_fl, leg_fr, leg_bl, leg_br]
///       group: base
///     - {name: screw, item: SCR-4x40, role: connecting, center: [...], size: [8, 8, 40],
///        repeat: {count: [1, 2, 1], step: [0, 20, 0]}}
///   articulations:
///     - {name: door, type: hinge, parts: [door, knob], axis: z, pivot: [...], limits: [0, 90]}
///
/// A working model (`model:`): which templates, reshaped how, composed how:
///
///   fabkit: templates/1
///   name: table with a bottom shelf
///   model:
///     - {use: coffee_table, as: table, set: {size_x: 1100}}
///     - {use: bookshelf/shelf_2, as: shelf, at: [0, 0, 60]}      # snapped, then connected
///   remove: [table/base/legs/leg_fl]                              # after composing
///   adjust:
///     - {node: table, control: size_z, to: 480}
///   loads:
///     - {part: top, at: [500, 0, 480], force: [0, 0, -300]}      # N, for the stability check

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/templates/manipulate.h"
#include "fabkit/templates/source_design.h"

namespace fabkit::templates {

/// Which of the two kinds a `fabkit: templates/1` file is.
enum class TemplatesFileKind { kDesign, kModel };

/// Reads a source design; every bad value gets file:line:col. nullopt on input errors.
std::optional<SourceDesign> read_source_design(std::string_view yaml,
                                               std::string_view file,
                                               Diagnostics& diags);

/// One composition step: add template `use` as `as`, reshape it, drop it, snap and connect.
struct ModelStep {
  std::string use;                                  ///< "design" or "design/path/to/node"
  std::string as;                                   ///< its name in the model
  std::vector<std::pair<ControlKind, double>> set;  ///< controls of its root, mm, in order
  std::optional<Vec3> at;                           ///< where it is dropped (its box centre), mm
  bool snap = true;
  bool connect = true;
  SourceLocation where;
};

/// A control set after composition.
struct Adjustment {
  std::string node;  ///< a node of the model ("table", "table/top", "shelf")
  ControlKind control = ControlKind::kSizeX;
  double value = 0;  ///< mm
  SourceLocation where;
};

/// A node removed after composition (paper §4.3: deleting a part removes its elements and every
/// relation and connection that involves them).
struct Removal {
  std::string node;  ///< a node of the model ("table/base/legs/leg_fl", "leg_fl", "shelf")
  SourceLocation where;
};

/// A force on a part for the stability check.
struct LoadSpec {
  std::string part;           ///< element name
  Vec3 at = Vec3::Zero();     ///< point of application, mm
  Vec3 force = Vec3::Zero();  ///< N
  SourceLocation where;
};

struct ModelFile {
  std::string name;
  std::string description;
  std::vector<ModelStep> steps;
  std::vector<Removal> remove;  ///< applied after the steps, before `adjust`
  std::vector<Adjustment> adjust;
  std::vector<LoadSpec> loads;
  double friction = 0.5;  ///< Coulomb coefficient for every contact
  std::string file;
};

std::optional<ModelFile> read_model_file(std::string_view yaml,
                                         std::string_view file,
                                         Diagnostics& diags);

/// Whether `yaml` (a `fabkit: templates/1` file) is a design or a model; nullopt with a
/// diagnostic when it is neither.
std::optional<TemplatesFileKind> templates_file_kind(std::string_view yaml,
                                                     std::string_view file,
                                                     Diagnostics& diags);

}  // namespace fabkit::templates

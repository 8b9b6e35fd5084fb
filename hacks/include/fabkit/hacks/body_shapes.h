#pragma once
/// The `body:` of a part in a part file: the object's shape as a list of simple solids, in the
/// part's coordinates (mm). The built-in parts are written this way (hacks/data/parts.yaml),
/// and so can a user's part that has no scanned mesh:
///
///   body:
///     - box: {min: [-34, -3, -34], max: [34, 0, 34]}             # corners
///     - box: {size: [20, 10, 5], frame: {pos: [0, 0, 2.5]}}       # centred at its frame
///     - cylinder: {from: [0, 0, 0], to: [0, 0, 80], radius: 70, segments: 32}
///     - open_box: {min: [0, 0, 0], max: [160, 122, 300], wall: 6, floor: 6}   # basket, tray
///     - sphere: {radius: 12, frame: {pos: [0, 0, 290]}}
///     - torus_arc: {arc_radius: 4, wire_radius: 1, angle: 360, frame: {...}}  # a wire arc
///     - primitive: {type: clip, width: 19, height: 11, dist: 8.2, open_gap: 3.5,
///                   thickness: 0.6, frame: {...}}                           # drawn, not a
///                   connector
///
/// `segments` (and `wire_segments` for arcs) set how finely round solids are drawn.

#include <optional>

#include "fabkit/core/mesh.h"
#include "fabkit/core/yaml_reader.h"

namespace fabkit::hacks {

/// The mesh of a `body:` list, or nullopt with diagnostics (file:line) through `in`.
/// `owner` names the part in messages. With `pieces`, the shapes' convex pieces (for contact
/// queries, Part::collision_pieces) are appended there.
std::optional<TriangleMesh> read_body(YamlReader& in,
                                      const YAML::Node& body,
                                      std::string_view owner,
                                      std::vector<TriangleMesh>* pieces = nullptr);

}  // namespace fabkit::hacks

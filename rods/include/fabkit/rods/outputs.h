#pragma once
/// What `fabkit build` writes: one binary STL per joint in its print pose (joint_07.stl), a 3MF
/// of all joints laid out on the plate, scene.glb of the assembled structure (joints white,
/// rods wood-brown, findings red), the cut plan (cut_plan.svg, cut_list.csv), assembly.json,
/// report.json, and tolerance_board.stl when asked for.

#include <filesystem>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/gltf.h"
#include "fabkit/core/json.h"
#include "fabkit/rods/build.h"
#include "fabkit/rods/design_file.h"

namespace fabkit::rods {

/// The assembled structure as scene objects (mm, world frame): exact joints when built, else
/// the preview; parts of failed checks red.
std::vector<SceneObject> scene_objects(const Design& design, const Summary& summary);

/// The assembly steps: [{"step": 1, "kind": "joint", "joint": 7, "label": "07", "text": ...},
/// {"kind": "rod", "rod": "rod 07-12", "joints": [7, 12], "length_mm": ..., ...}].
Json assembly_json(const Design& design, const Summary& summary);

/// Lengths, offsets, angles, joints, cut plan, findings, balance, structure and timings.
Json report_json(const Design& design, const Summary& summary);

/// Writes every output into `directory` (created if needed), each file atomically. Returns the
/// files written; on failure an I/O diagnostic names the file.
std::vector<std::filesystem::path> write_outputs(const Design& design,
                                                 const Summary& summary,
                                                 const std::filesystem::path& directory,
                                                 Diagnostics& diags);

}  // namespace fabkit::rods

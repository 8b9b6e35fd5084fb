#pragma once
/// Rod structure design files (`fabkit: rods/1`, docs/rods.md):
///
///   fabkit: rods/1
///   name: stool
///   rod: {diameter: 12.7, profile: circle, material: hardwood}
///   joint: {wall: 2.5, socket: 20, tolerance: 0.15, material: pla}
///   stock: {length: 914.4, end_padding: 10, kerf: 0.2}
///   nodes:            # joint 1, 2, ... in this order (mm, z up)
///     - [0, 0, 0]
///     - [300, 0, 0]
///   edges:            # pairs of node numbers
///     - [1, 2]
///
/// or `network: shape.obj` (an OBJ with l or f elements, relative to the file) instead of
/// nodes and edges.

#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/rods/frame_analysis.h"
#include "fabkit/rods/structure.h"
#include "fabkit/rods/tolerance_board.h"

namespace fabkit::rods {

/// Whether a design may name other files (`network:`, `reuse_joints_from:`).
enum class FilePolicy {
  kAllow,   ///< relative to the design's directory (command line, Python)
  kRefuse,  ///< an input error: designs posted to a server may not name files
};

struct DesignOptions {
  FilePolicy files = FilePolicy::kAllow;
  int max_nodes = 100000;  ///< refuse larger networks
  int max_edges = 200000;
};

struct Design {
  std::string name;
  std::string description;
  std::filesystem::path source;  ///< file it was read from (empty for text)
  Structure structure;
  Parameters parameters;
  std::vector<PointLoad> loads;   ///< N at nodes
  std::vector<Support> supports;  ///< empty: the floor contacts, pinned
  int assembly_start = -1;        ///< node index to start the assembly at (−1: lowest)
  bool engrave = true;
  std::optional<ToleranceBoardOptions> tolerance_board;
  /// Another design whose printed joints this one may reuse (resolved path).
  std::optional<std::filesystem::path> reuse_joints_from;
  /// Every diagnostic of reading, with file:line.
  Diagnostics diagnostics;
  /// True when the file was read and understood (no input errors).
  bool readable = false;
};

/// Reads a design file; never throws on bad input.
Design load_design(const std::filesystem::path& path, const DesignOptions& options = {});
/// Same, from text; `display_name` names it in diagnostics; files it names are relative to
/// `base_dir`.
Design load_design_text(std::string_view yaml,
                        std::string_view display_name,
                        const std::filesystem::path& base_dir = {},
                        const DesignOptions& options = {});

/// Reads the network of an OBJ file: `v` vertices (mm) and the edges of `l` polylines and of
/// `f` polygon boundaries (each edge once). Diagnostics name the file and line.
bool read_network_obj(std::string_view text,
                      std::string_view display_name,
                      std::vector<NodeInput>& nodes,
                      std::vector<EdgeInput>& edges,
                      Diagnostics& diags);

/// Builds a design from Python-style lists: node positions (mm) and 0-based edges.
Design design_from_lists(const std::vector<Vec3>& nodes,
                         const std::vector<std::pair<long long, long long>>& edges,
                         const Parameters& parameters);

}  // namespace fabkit::rods

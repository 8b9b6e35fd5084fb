#pragma once
/// FabHaL design files: YAML equivalent of a FabHaL program (docs/design-format.md).
///
///   fabkit: hacks/1
///   name: basket between rods
///   environment:
///     - {name: rods, part: ClosetRods, frame: {pos: [0, 0, 200], rot: [0, 0, -90]}}
///   parts:
///     - {name: eyehook1, part: HookEyeConnector}
///   target: {name: basket, part: RoundHandleBasket, frame: {pos: [0, 0, 100], rot: [-75, 0, 90]}}
///   connections:
///     - {connect: [eyehook1.hole, rods.rod1], alignment: flip}
///     - {connect: [eyehook1.hook, basket.hook]}

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/parts_library.h"

namespace fabkit::hacks {

/// Whether a design may name part files (`part_files:`).
enum class PartFilePolicy {
  kAllow,   ///< relative to the design's directory (command line, Python)
  kRefuse,  ///< a 400-style input error: designs posted to the server may not name files
};

struct DesignOptions {
  VerifyOptions verify;
  int max_parts = 0;        ///< refuse designs with more parts than this (0: no limit)
  int max_connections = 0;  ///< refuse designs with more connections than this (0: no limit)
  PartFilePolicy part_files = PartFilePolicy::kAllow;
};

/// One step of the design in file order, with its outcome.
struct DesignStep {
  enum class Kind { kAdd, kConnect, kEndWith };
  Kind kind = Kind::kConnect;
  std::string text;  ///< "connect eyehook1.hole → rods.rod1 (flip)"
  SourceLocation where;
  bool accepted = false;
  bool skipped = false;  ///< not attempted because an earlier step it depends on failed
  /// How the connect verified: in the canonical order of the connects, which the design is
  /// made in (a cycle is closed by the connect that completes it there), or in the file's
  /// order where the canonical one does not verify.
  ConnectReport report;
};

struct Design {
  std::string name;
  std::string description;
  std::filesystem::path source;  ///< file it was read from (empty for strings)
  Assembly assembly;
  std::map<std::string, std::shared_ptr<Part>> parts;  ///< by name in the file
  std::vector<DesignStep> steps;
  /// Every diagnostic: file problems first, then each step's, in order.
  Diagnostics diagnostics;
  /// True when the file could be read and understood (no input errors). A readable design
  /// can still be infeasible: see feasible().
  bool readable = false;
  bool feasible() const { return readable && !diagnostics.has_errors(); }
};

/// Reads and builds a design file, running every add / connect / end_with with full
/// verification. Never throws on bad input: problems become diagnostics with file:line.
Design load_design(const std::filesystem::path& path,
                   const PartsLibrary& library,
                   const DesignOptions& options = {});
/// Same, from text; `display_name` stands in for the file name in diagnostics.
Design load_design_text(std::string_view yaml,
                        std::string_view display_name,
                        const PartsLibrary& library,
                        const DesignOptions& options = {},
                        const std::filesystem::path& base_dir = {});

}  // namespace fabkit::hacks

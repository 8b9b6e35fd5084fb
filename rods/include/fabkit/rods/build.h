#pragma once
/// The two verbs every front end calls: check a design (offsets, lengths, every check, cut
/// plan, frame analysis, assembly order; fast, no booleans) and build it (the same plus the
/// exact engraved joints, in parallel), each returning a Summary.
///
///   Design design = load_design("stool.yaml");
///   Summary s = build(design, BuildOptions{});
///   if (s.termination == Termination::kBuilt) write_outputs(design, s, "out", diags);

#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "fabkit/core/cut_plan.h"
#include "fabkit/rods/assembly_order.h"
#include "fabkit/rods/check.h"
#include "fabkit/rods/design_file.h"
#include "fabkit/rods/frame_analysis.h"
#include "fabkit/rods/joint_solid.h"
#include "fabkit/rods/layout.h"
#include "fabkit/rods/reuse.h"
#include "fabkit/rods/tolerance_board.h"

namespace fabkit::rods {

struct BuildOptions {
  JointSolidOptions joint;  ///< engraving settings (engrave is also the design's)
  CheckOptions checks;
  CutPlanOptions cut_plan;
  bool frame_analysis = true;
  int threads = 2;  ///< joints built at once (the booleans are independent)
  /// Called as joints finish (done, total), from worker threads one at a time.
  std::function<void(int, int)> on_progress;
  std::optional<std::chrono::steady_clock::time_point> deadline;  ///< stop building joints
};

enum class Termination {
  kBuilt,              ///< everything made, every check passed
  kBuiltWithFindings,  ///< everything made, but a check failed (exit 7)
  kInfeasible,         ///< rods that cannot exist or do not fit the stock: nothing to build
  kTimeLimit,          ///< stopped at the deadline
  kFailed,             ///< an input or internal error
};
/// "built", "built-with-findings", "infeasible", "time-limit", "failed".
std::string_view to_string(Termination t);

struct Summary {
  Layout layout;
  CheckReport checks;
  FrameResult frame;
  std::optional<CutPlan> cut_plan;
  std::vector<CutPiece> cut_pieces;  ///< one per rod with ℓ > 0 ("rod 03-07", ℓ)
  std::vector<int> cut_piece_rod;    ///< the rod of each cut piece
  std::vector<AssemblyStep> assembly;
  std::vector<JointSolid> joints;  ///< build: one per node, in node order
  std::vector<JointMatch> reused;  ///< joints shared with reuse_joints_from
  std::string reused_from;
  std::optional<ToleranceBoard> tolerance_board;
  std::vector<std::pair<std::string, double>> timings;  ///< stage, ms
  Diagnostics diagnostics;  ///< input notes, findings, cut plan, frame, build problems
  Termination termination = Termination::kFailed;
  std::string message;  ///< one line for people
};

/// Everything but the exact joints (what `fabkit check` and the designer run).
Summary check(const Design& design, const BuildOptions& options = {});
/// check() plus the exact joints (and the tolerance board when the design asks for one).
Summary build(const Design& design, const BuildOptions& options = {});

}  // namespace fabkit::rods

#pragma once
// Cycle-closure feasibility search (paper §4.3.2) with Ceres: bounded nonlinear least
// squares over the connector parameters on the cycles, automatic derivatives,
// deterministic seeded restarts.

#include <vector>

#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks::detail {

struct ClosureResult {
  bool closed = false;
  double cost = 0;        ///< Σ‖f‖² (mm², deg²) plus multi-connection penalties (mm²)
  std::vector<double> x;  ///< best parameter vector found
  int starts = 0;
};

/// Searches parameters that close every cycle-closing connection of `assembly` and keep
/// multiply-connected primitives' connections apart, starting from `x0`, then from
/// options.restarts - 1 seeded random points; stops at the first success. With `group` ≥ 0
/// (KinematicGraph::movable_groups), only that group's cycles, moving only its parameters:
/// independent cycles are closed independently.
ClosureResult close_cycles(const Assembly& assembly,
                           const std::vector<double>& x0,
                           const VerifyOptions& options,
                           int group = -1);

/// Per-connection closure error at `x`: position gap in mm and orientation gap in degrees.
struct ClosureGap {
  ConnectionId connection;
  double position_mm = 0;
  double rotation_deg = 0;
};
std::vector<ClosureGap> closure_gaps(const Assembly& assembly, const std::vector<double>& x);

/// Twins among the parameters `vars`: parameters with equal `keys` (Assembly::parameter_keys)
/// because their parts hang the same way from the same thing — two S-hooks' places on one
/// rail. Each group ordered by the twins' values at x, then by where their connections are in
/// the world: the same order whatever the parts are called or the order they were connected in.
std::vector<std::vector<int>> twin_groups(const Assembly& a,
                                          const std::vector<std::string>& keys,
                                          const std::vector<int>& vars,
                                          const std::vector<double>& x);
/// `keys` with "#twin<rank>" added to each twin of `vars` after the first of its group: keyed
/// draws by them give twins values of their own (equal draws put both hooks on a rail in one
/// place on every draw).
std::vector<std::string> twin_keys(const Assembly& a,
                                   const std::vector<std::string>& keys,
                                   const std::vector<int>& vars,
                                   const std::vector<double>& x);

}  // namespace fabkit::hacks::detail

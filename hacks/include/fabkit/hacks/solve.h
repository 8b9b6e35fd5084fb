#pragma once
/// Solving a FabHaL assembly (paper §4.3.3): step 1 brings the target as close as possible to
/// its end_with frame subject to every constraint; step 2 relaxes the assembly under gravity
/// to static equilibrium and decides whether it falls apart.

#include <chrono>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "fabkit/core/diagnostics.h"
#include "fabkit/core/frame.h"
#include "fabkit/hacks/assembly.h"

namespace fabkit::hacks {

struct SolveOptions {
  int target_starts = 8;           ///< step 1: starts (the verified configuration + seeded random)
  std::uint64_t seed = 1;          ///< seeds step 1's random starts
  double constraint_weight = 100;  ///< step 1: weight of constraint residuals against the target's
  double closure_tolerance_mm = 1e-6;  ///< connections must close to this after each step
  /// An OPEN parameter at its bound falls off when moving beyond it lowers the assembly's
  /// mean centre-of-mass height by more than this (mm per mm of sliding, or per degree).
  double fall_threshold = 1e-6;
  int max_iterations = 500;  ///< per optimisation run
  bool relax = true;         ///< run step 2
  /// Stop (termination TIMEOUT) once this time has passed; for servers. None: no limit.
  std::optional<std::chrono::steady_clock::time_point> deadline;
  /// Groups hanging separately (independent of each other) relax on up to this many threads
  /// at once; 0: one per core. The answer does not depend on it.
  int threads = 0;
  /// Called as each stage starts ("step1", "step2", "stability"); for progress displays.
  std::function<void(std::string_view stage)> on_stage;
  /// When the design falls apart, slipping at a connection that can be made the other way
  /// round (its alignment turned), or two of its parts pass through each other, solve the
  /// designs with that connection (or the two parts' connections) turned too and say in
  /// SolveResult::remedy if one holds.
  bool seek_remedy = true;
  /// A group the target does not steer that does not hold where its verified configuration
  /// rests is relaxed from up to this many other ways of closing its cycles, four times as many
  /// for a group of up to 16 variables (docs/hacks.md).
  int other_closings = 24;
  /// Step 1: starts of the closure search for a random start whose cycles a local closing does
  /// not close. solve() solves once more with four where the target was not reached, random
  /// starts did not close and nothing held (docs/hacks.md, step 1).
  int start_closings = 1;
};

/// Why the solver stopped.
enum class Termination {
  kConverged,      ///< both steps converged
  kNoTarget,       ///< the assembly has no (connected) target
  kInfeasible,     ///< the constraints could not be satisfied
  kMaxIterations,  ///< an optimisation ran out of iterations (result still usable)
  kTimeout,        ///< stopped at options.deadline (result incomplete)
  kNotConverged,   ///< step 2 ended where the potential still slopes or curves down: not a rest
                   ///< state (the result is reported, but not as stable)
};
std::string_view to_string(Termination t);

/// The verdict on a solve, decided here for every front end (the report, result.json, Python,
/// the editor), in this order: it holds; parts pass through each other (no real parts rest like
/// that, whatever else is wrong; not said of a solve stopped at its time limit); the
/// constraints could not be satisfied; it stopped at its time limit; a connection slips off;
/// or it is not a rest state.
enum class Verdict {
  kStable,            ///< at rest, nothing slips, nothing passes through anything
  kPartsPassThrough,  ///< an overlap deeper than kPenetrationToleranceMm (infeasible as found)
  kInfeasible,        ///< cycles left open
  kStopped,           ///< stopped at the time limit: the result is incomplete
  kFallsApart,        ///< a connection slips off under gravity
  kNotAtRest,         ///< the potential still slopes or curves down where step 2 ended
};
std::string_view to_string(Verdict v);  ///< "STABLE", "PARTS_PASS_THROUGH", ...

/// How far the target is from where end_with asked, split into what a user can act on.
struct PoseError {
  double position_mm = 0;
  double rotation_deg = 0;  ///< geodesic angle, modulo the target primitive's symmetries
  /// How far the target's up direction (the world up of the goal pose, in the target's own
  /// frame) is tilted away from up: what gravity decides.
  double tilt_deg = 0;
  /// The rest of the rotation: a turn about the vertical (signed, (-180, 180]).
  double twist_deg = 0;
  /// Whether the assembly can turn the target about the vertical at no cost (a chain hanging
  /// from one point): then the twist is where it happens to rest, not an error of the design.
  bool twist_free = false;
};

/// A part's solved world frame.
struct SolvedPart {
  std::string name;
  std::string type;
  bool environment = false;
  bool target = false;
  Frame frame;
};

/// A connection that slips: an OPEN parameter at its bound with the energy pulling it out.
struct Slip {
  ConnectionId connection;
  int parameter = -1;   ///< index into the assembly's parameter vector
  std::string message;  ///< "DoubleHook#2.hook1 slides off the open end of door.rod (t = 1)"
};

/// Two parts that touch (or pass through each other) in the reported pose.
struct PartContact {
  std::string part_a;  ///< the assembly's labels ("door", "SHook#2")
  std::string part_b;
  /// Smallest distance between their collision bodies, mm: ≥ 0 touching (within
  /// kTouchingMm), < 0 the depth by which they pass through each other.
  double distance_mm = 0;
};

/// A motion the potential does not change along (a hook free to slide on a level rod): the
/// rest state is a family, and the reported one is where the solve happened to stop.
struct NeutralDirection {
  std::vector<std::string> parameters;  ///< the parameters it moves most ("DoubleHook#1.hook1 θ")
  std::string description;              ///< "moves DoubleHook#1.hook1 θ at no cost"
};

struct StageTiming {
  std::string stage;  ///< "verify", "step1", "step2", "stability"
  double milliseconds = 0;
};

/// Everything a solve found, in a form that maps one to one onto result.json.
struct SolveResult {
  Termination termination = Termination::kConverged;
  std::string message;
  bool feasible = false;
  bool stable = false;
  PoseError target_step1;         ///< target error after step 1
  PoseError target;               ///< after relaxation (step 2)
  std::vector<SolvedPart> parts;  ///< world frames after relaxation
  std::vector<double> step1_parameters;
  std::vector<double> parameters;  ///< after relaxation
  std::vector<Slip> slips;
  std::vector<std::string> stability_notes;  ///< e.g. "sags by 12 mm; stable"
  /// For a design that falls apart or passes through itself: a change to it that holds, found
  /// by solving the changed design ("with s1.hook2 and s2.hook1 connected the other way round —
  /// alignment: flip on that connect (design.yaml:14) — it holds"); empty when none was found.
  std::string remedy;
  double max_gap_mm = 0;  ///< largest connection gap after relaxation
  double max_gap_deg = 0;
  /// Largest slope of the potential (mean centre-of-mass height, mm) along any motion the
  /// connections and bounds allow, per mm of sliding or degree of turning; ~0 at equilibrium.
  double equilibrium_residual = 0;
  /// The smallest curvature of the potential along the allowed motions at the result (the
  /// reduced Hessian's smallest eigenvalue, mm of mean height per unit² of motion): ≥ 0 up to
  /// the neutral threshold at a minimum.
  double smallest_curvature = 0;
  std::vector<NeutralDirection> neutral_directions;
  /// Pairs of parts whose bodies touch or overlap in the reported pose, except where a
  /// connection joins them (a hook on its rod); deepest overlap first.
  std::vector<PartContact> contacts;
  /// Deepest overlap of two parts' bodies (mm, 0 if none): above
  /// kPenetrationToleranceMm the pose is not one real parts can take.
  double max_penetration_mm = 0;
  int escapes = 0;    ///< times step 2 stepped off a saddle or a maximum
  double energy = 0;  ///< Σ m·z_com (mass units · mm)
  int step1_starts = 0;
  std::vector<StageTiming> timings;
  Diagnostics diagnostics;

  /// What the result says in one word (Verdict).
  Verdict verdict() const;
  /// Ceres-style text summary.
  std::string summary() const;
};

/// Solves a verified assembly. Never throws on user input; problems are diagnostics.
SolveResult solve(const Assembly& assembly, const SolveOptions& options = {});

/// World frame of the target primitive and its error against the end_with frame, for
/// parameter vector `x`.
PoseError target_error(const Assembly& assembly, const std::vector<double>& x);

}  // namespace fabkit::hacks

#pragma once
// The two steps of solve() (paper §4.3.3) and the verdict, on the core ManifoldSolver:
// step 1 reaches for the target (least squares on the constraint manifold, seeded starts),
// step 2 relaxes under gravity (Newton on the potential), the verdict finds what slips.

#include <atomic>
#include <chrono>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fabkit/core/parallel.h"
#include "fabkit/core/stop_clock.h"
#include "fabkit/hacks/solve.h"
#include "kinematics.h"

namespace fabkit::hacks::detail {

struct StepResult {
  std::vector<double> x;
  bool converged = true;
  bool closed = true;
  int iterations = 0;
  int escapes = 0;
  std::string note;
  /// A relaxation that ended at a minimum: the curvature at x (its last model).
  std::optional<solvers::ManifoldSolver::Curvature> curvature;
};

/// The ManifoldSolver on one of the assembly's problems, in the parameter vector's terms.
class AssemblySolver {
 public:
  AssemblySolver(const Problem& p,
                 const Variables& v,
                 const std::vector<double>& x,
                 Objective o,
                 std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt);
  /// Closes the cycles from an arbitrary configuration, as a random start needs; false if
  /// they stay open (or close only at a half turn).
  bool close(std::vector<double>& x, int max_iterations);
  StepResult fit(const std::vector<double>& x0,
                 int max_iterations,
                 double give_up = std::numeric_limits<double>::infinity());
  StepResult relax(const std::vector<double>& x0, int max_iterations);

  const Problem& problem() const { return problem_; }
  const Variables& variables() const { return vars_; }
  solvers::ManifoldSolver& solver() { return solver_; }

 private:
  StepResult to_step(const solvers::ManifoldSolver::Result& r, const std::vector<double>& x0) const;

  const Problem& problem_;
  const Variables& vars_;
  AnalyticEvaluator eval_;
  solvers::ManifoldSolver solver_;
};

struct Step1Result {
  std::vector<double> x;  ///< the best start's configuration
  PoseError error;
  int starts = 0;
  bool closed = false;
  bool hit_iteration_limit = false;
  /// Every start that closed, best first (the best is x): step 2 relaxes each, since the
  /// nearest configuration to the target may not be the one that holds.
  struct Candidate {
    std::vector<double> x;
    PoseError error;
    bool hit_iteration_limit = false;
    int start = 0;  ///< the start it came from (0: the verified configuration)
  };
  std::vector<Candidate> candidates;
};

/// Whether two configurations put every part in the same place (within 1e-3 mm and 1e-6 rad).
bool same_poses(const std::vector<Mat4>& a, const std::vector<Mat4>& b);

/// Step 1: start 0 is the configuration the connects verified; the others are seeded random
/// configurations, closed first.
Step1Result run_step1(const Problem& p, const SolveOptions& o);

/// With the target held where a step-1 candidate `x` puts it, the rest of the hack settles
/// under gravity: the choices step 1 is free to make at no cost to the target (where along a
/// rod an eye hook is screwed in, how a loop turns) go where the weight takes them. Which of
/// those equally good configurations a start ends in is an accident of the start (of the
/// order of the connects); where they settle is not. `p` is step 1's problem. Step 2 settles
/// the candidates it relaxes, and only those.
std::vector<double> settle_candidate(const Problem& p,
                                     const std::vector<double>& x,
                                     const SolveOptions& o);

/// Watches, as contact rows of `p`, the piece pairs near each other at `x` (at least one of
/// them a part of p's group). Without a contact model nothing is watched. With `deepest`, how
/// deep parts are inside each other at `x` (deepest_overlap's depth, from the same queries).
void watch_contacts(Problem& p, const std::vector<double>& x, double* deepest = nullptr);
/// Adds to p's watched pairs those near each other at `x`; true if there were new ones.
bool watch_more_contacts(Problem& p, const std::vector<double>& x, double* deepest = nullptr);

/// The deepest interpenetration at `x` of parts of p's group with anything (mm, 0 when
/// nothing passes through anything), and the pair.
struct Overlap {
  double depth = 0;
  PiecePair pair;
};
/// With `parts_only`, only pairs of two parts that are not environments count.
Overlap deepest_overlap(const Problem& p, const std::vector<double>& x, bool parts_only = false);

/// Step 2's tries at unfolding per movable group, for all the candidates it relaxes: a group
/// whose every candidate passes through something (the reading nook's crossed chains) would
/// otherwise pay a relaxation per try per candidate.
inline constexpr int kUnfoldTriesPerGroup = 8;

/// Whether the solve's deadline has passed (or was called by a step that could not finish).
inline bool past_deadline(const Problem& p, const SolveOptions& o) {
  if (p.stop) return p.stop->passed();
  return deadline_passed(o.deadline);
}

/// Iterations of one run: runs with contact rows get fewer (each evaluation queries every
/// watched pair, and a run that needs more rarely gets anywhere with them).
inline int iterations_for(const Problem& q, const SolveOptions& o) {
  return q.watched.empty() ? o.max_iterations : std::min(o.max_iterations, kContactIterations);
}

/// Runs `run(problem, start)` with the contact pairs near `x` watched; a part can move
/// farther than the watch distance in one run, so while the result comes near pairs not yet
/// watched, they are added and it runs again: from there, or from `x` where it ended deeper
/// inside something than `x` was (kContactRounds runs in all, kContactRestartedRounds once it
/// has started again).
template <class Run>
StepResult with_contacts(Problem& p, const std::vector<double>& x, Run run) {
  // How deep parts are inside each other at x (no run from it needs to go deeper).
  double start_depth = 0;
  watch_contacts(p, x, &start_depth);
  StepResult r = run(p, x);
  bool restarted = false;
  for (int round = 1;
       round < (restarted ? kContactRestartedRounds : kContactRounds) && p.contacts && r.closed;
       ++round) {
    double end_depth = 0;
    if (!watch_more_contacts(p, r.x, &end_depth)) break;
    // Pairs it did not watch, the run may have carried through each other (the reading nook's
    // two chains, 33 mm deep, with seeds other than 1): from there no run with their rows can
    // even start, and real parts could not have got there. Where it ended deeper in something
    // than its start was, it runs again from the start with them watched.
    const bool through = end_depth > kPenetrationToleranceMm && end_depth > start_depth;
    restarted = restarted || through;
    StepResult again = run(p, through ? x : r.x);
    // A run that cannot start leaves the last one standing (what it passes through is then
    // measured and reported, and compared with the plain run's).
    if (!again.closed) break;
    r = std::move(again);
  }
  return r;
}

/// Runs `run` without contact rows first (most results pass through nothing, and contact rows
/// cost a distance query per pair and evaluation); only a result where parts pass through
/// each other is run again from `x` with the contacts watched.
/// Past the deadline the plain run's result stands: the contact queries after it cost
/// milliseconds on a long chain, and a result cut by the deadline is never called stable.
/// With `unfold`, a plain result where parts pass through each other is also handed to it:
/// unfold(problem, result, depth, environment) → a result (contact rows off) and its depth, or
/// none. Parts inside each other go to it before the contact rows; a part inside an
/// environment (`environment` true) only when the contact rows do not bring it to rest apart.
template <class Run, class Unfold>
StepResult avoiding_contacts(
    Problem& p, const std::vector<double>& x, Run run, const SolveOptions& o, Unfold unfold) {
  p.watched.clear();
  // Where an earlier candidate of this group only came to rest against an environment with
  // its contact rows, the next ones start with them: the same rest wherever no contact binds
  // (a row that does not bind changes no step), and no plain run to throw away. What does not
  // come to rest apart that way goes the usual way below.
  if (p.contacts && p.contacts_first && *p.contacts_first && !past_deadline(p, o)) {
    Problem kept = p;
    StepResult apart = with_contacts(kept, x, run);
    if (apart.closed && apart.converged &&
        deepest_overlap(kept, apart.x).depth <= kPenetrationToleranceMm) {
      p = std::move(kept);
      return apart;
    }
  }
  StepResult r = run(p, x);
  if (!p.contacts || !r.closed) return r;
  if (past_deadline(p, o)) return r;
  double plain = deepest_overlap(p, r.x).depth;
  if (plain <= kPenetrationToleranceMm) return r;
  // Whether the group's later candidates could start with contacts: only where the plain run
  // passed through nothing but an environment (parts inside each other are for the unfolding
  // first). Asked once per group: the flag, once set, stays.
  const bool environment_only =
      p.contacts_first && !*p.contacts_first &&
      deepest_overlap(p, r.x, /*parts_only=*/true).depth <= kPenetrationToleranceMm;
  // The parts' unfolding, then (unless it brought them apart) the environment's, which is
  // wanted only if the contact rows do not bring the parts to rest apart.
  bool parts_unfolded = false;  // the parts' unfolding ended it (apart, or past the deadline)
  std::optional<std::pair<StepResult, double>> environment_unfolded;
  auto unfold_parts = [&] {
    if (auto unfolded = unfold(p, r, plain, false)) {
      r = std::move(unfolded->first);
      plain = unfolded->second;
      parts_unfolded = plain <= kPenetrationToleranceMm || past_deadline(p, o);
    }
  };
  Problem kept = p;
  StepResult apart;
  double apart_depth = std::numeric_limits<double>::infinity();
  auto run_with_contacts = [&] {
    apart = with_contacts(kept, x, run);
    if (apart.closed) apart_depth = deepest_overlap(kept, apart.x).depth;
  };
  auto rests_apart = [&] { return apart.converged && apart_depth <= kPenetrationToleranceMm; };
  if (p.unfold_tries && *p.unfold_tries > 0 && thread_count(o.threads) > 1) {
    // The contact rows' run starts from x whatever the unfolding finds, so the two run at
    // once, the unfolding going on to the environment's pairs as if the contact rows will
    // not bring the parts to rest apart. Each is called off as soon as the other shows it is
    // not wanted (its clock stops), and what it found is dropped: when the parts' unfolding
    // brings them apart, the contact run; when the contact rows bring the parts to rest
    // apart, the environment's unfolding, and the tries it spent are given back. The answer
    // is the one the sequence below gives.
    const auto contacts_clock = std::make_shared<const StopClock>(p.stop);
    const auto unfold_clock = std::make_shared<const StopClock>(p.stop);
    kept.stop = contacts_clock;
    Problem environment = p;
    environment.stop = unfold_clock;
    int tries_before = 0;
    bool environment_tried = false;
    std::atomic<bool> contacts_rest_apart{false};
    run_in_parallel(2, o.threads, [&](int k) {
      if (k == 1) {
        run_with_contacts();
        if (rests_apart()) {
          contacts_rest_apart = true;
          unfold_clock->call_off();
        }
        return;
      }
      unfold_parts();
      if (parts_unfolded) contacts_clock->call_off();
      if (parts_unfolded || past_deadline(p, o) || contacts_rest_apart) return;
      tries_before = *p.unfold_tries;
      environment_tried = true;
      environment_unfolded = unfold(environment, r, plain, true);
    });
    kept.stop = p.stop;
    if (parts_unfolded) return r;
    if (environment_tried && contacts_rest_apart) {
      *p.unfold_tries = tries_before;
      environment_unfolded.reset();
    }
  } else {
    unfold_parts();
    if (parts_unfolded) return r;
    run_with_contacts();
    if (!rests_apart() && !past_deadline(p, o)) environment_unfolded = unfold(p, r, plain, true);
  }
  if (environment_unfolded && environment_unfolded->second <= kPenetrationToleranceMm)
    return std::move(environment_unfolded->first);
  // Contact rows are bounded in cost; when they leave the parts deeper in each other than
  // the plain run did, the plain run's result stands (and the verdict reports the overlap).
  if (!apart.closed || apart_depth >= plain) return r;
  if (environment_only && apart.converged && apart_depth <= kPenetrationToleranceMm) {
    *p.contacts_first = true;
  }
  p = std::move(kept);
  return apart;
}

template <class Run>
StepResult avoiding_contacts(Problem& p,
                             const std::vector<double>& x,
                             Run run,
                             const SolveOptions& o) {
  return avoiding_contacts(p, x, run, o, [](const Problem&, const StepResult&, double, bool) {
    return std::optional<std::pair<StepResult, double>>();
  });
}

/// Closes p's cycles again from x (a start with some parameters redrawn) by step 2's own
/// variables `vars`, so that what step 2 holds (fixed joints, clip jaws, a wall hook where it
/// was stuck) stays as it is; the verification's search, which may move anything of the group,
/// only when that fails, and its closure only if it moved nothing step 2 holds. False when
/// neither closes them; x is then unchanged.
bool close_again(const Problem& p,
                 const Variables& vars,
                 std::vector<double>& x,
                 const SolveOptions& o);

/// twin_groups (cycle_closure.h) of p's parameter keys.
std::vector<std::vector<int>> twin_groups(const Problem& p,
                                          const std::vector<int>& vars,
                                          const std::vector<double>& x);
/// The keys draw_keyed draws `vars` by, one per entry of `vars`: twin_keys of p's parameter
/// keys.
std::vector<std::string> draw_keys(const Problem& p,
                                   const std::vector<int>& vars,
                                   const std::vector<double>& x);

/// Seeded values keyed by the parameters' structural keys (the same for a parameter whatever its
/// place in the vector or the order of the connects) for the parameters `vars` of x, uniform within
/// their bounds: all of them, or with `unbounded_only` only the unbounded angles. An unbounded
/// angle is turned from its value in x by a uniform draw (its zero depends on how the file
/// placed the primitive, a rod spun about its axis), a bounded parameter drawn afresh.
/// Twins get draws of their own, handed out in twin_groups' order: equal draws would put both
/// hooks on a rail in one place on every draw.
void draw_keyed(const Problem& p,
                const std::vector<int>& vars,
                std::uint64_t seed,
                int stream,
                bool unbounded_only,
                std::vector<double>& x);

/// Step 2: relaxation under gravity from step 1's configuration. With a contact model, pairs
/// that come near during the relaxation are watched from then on and it is repeated.
StepResult run_step2(Problem& p,
                     const Variables& vars,
                     const std::vector<double>& x1,
                     const SolveOptions& o);

struct StabilityReport {
  std::vector<Slip> slips;
  double equilibrium_residual = 0;
  double smallest_curvature = 0;  ///< of the reduced Hessian (0 if nothing can move)
  double neutral_threshold = 0;
  std::vector<NeutralDirection> neutral_directions;
  /// Neutral directions in the full parameter vector (for the target's free twist).
  std::vector<std::vector<double>> neutral_motions;
};

/// The verdict at x: the equilibrium residual (largest slope of the potential along the
/// motions the connections and bounds allow) and every open bound that the potential pulls a
/// connection out of. `relaxed`, the relaxation that ended at x (up to whole turns of its
/// unbounded angles), lends its last model's curvature where that model is the one the check
/// would make (the same free coordinates and rows, no contact binding).
StabilityReport check_stability(const Problem& p,
                                const Variables& vars,
                                const std::vector<double>& x,
                                const SolveOptions& o,
                                const StepResult* relaxed = nullptr);

/// "DoubleHook#2.hook1 slides off the open end of door.rod (t = 1)".
std::string slip_message(const Assembly& a, int index, bool at_upper);

}  // namespace fabkit::hacks::detail

#include <algorithm>
#include <cmath>

#include "random.h"
#include "steps.h"

namespace fabkit::hacks::detail {
namespace {

PoseError error_at(const Problem& p, const std::vector<double>& x) {
  const std::vector<Mat4> frames = p.assembly->part_frames(x);
  return pose_error(*p.target, Rigid<double>::from_matrix(frames[p.target->part.index()]));
}

}  // namespace

Step1Result run_step1(const Problem& p, const SolveOptions& o) {
  const Assembly& a = *p.assembly;
  Step1Result best;
  best.x = a.values();
  best.closed = true;
  if (!p.target) return best;
  best.error = error_at(p, best.x);
  const Variables vars = select_variables(a, /*physics=*/false, &p);
  if (vars.index.empty()) {
    best.candidates.push_back({best.x, best.error, false});
    return best;
  }

  auto score = [](const PoseError& e) {
    return e.position_mm * e.position_mm + e.rotation_deg * e.rotation_deg;
  };
  double best_score = score(best.error);
  SplitMix rng(o.seed);
  for (int start = 0; start < std::max(1, o.target_starts); ++start) {
    // Nothing can beat a target that is already reached.
    if (best.error.position_mm < kTargetReached && best.error.rotation_deg < kTargetReached) break;
    std::vector<double> x0 = a.values();
    if (start > 0) {
      for (int v : vars.index) {
        const ParamSpec& s = a.parameters()[static_cast<std::size_t>(v)].spec;
        x0[static_cast<std::size_t>(v)] = s.lo + rng.uniform() * (s.hi - s.lo);
      }
    }
    if (o.deadline && std::chrono::steady_clock::now() > *o.deadline) break;
    AssemblySolver solver(p, vars, x0, Objective::kTarget, o.deadline);
    if (start > 0 && !solver.close(x0, 100)) {
      // The local closing failed from this start: the verification's global search (two
      // phases, stall detection) usually gets there.
      VerifyOptions v;
      v.restarts = 1;
      v.deadline = o.deadline;
      const ClosureResult closed = close_cycles(a, x0, v);
      if (!closed.closed) continue;
      x0 = closed.x;
    }
    // Random starts explore: a fifth of the iterations of the verified start, and they stop
    // early when they are far from beating the best start so far (f = ½‖r‖²).
    StepResult r = start == 0 ? solver.fit(x0, o.max_iterations)
                              : solver.fit(x0, o.max_iterations / 5, 5 * best_score);
    best.starts = start + 1;
    if (!r.closed) continue;
    for (std::size_t i = 0; i < r.x.size(); ++i) {
      if (a.parameters()[i].spec.tag == ParamTag::kUnbounded) r.x[i] = wrap_360(r.x[i]);
    }
    const PoseError e = error_at(p, r.x);
    // Starts that end where another did are one candidate.
    bool seen = false;
    for (const Step1Result::Candidate& c : best.candidates) {
      seen = seen || (std::abs(score(c.error) - score(e)) < 1e-6 &&
                      std::abs(c.error.position_mm - e.position_mm) < 1e-3);
    }
    if (!seen) best.candidates.push_back({r.x, e, !r.converged});
    if (score(e) < best_score - 1e-9) {
      best_score = score(e);
      best.x = r.x;
      best.error = e;
      best.hit_iteration_limit = !r.converged;
    }
  }
  if (best.candidates.empty()) best.candidates.push_back({best.x, best.error, false});
  std::stable_sort(best.candidates.begin(),
                   best.candidates.end(),
                   [&](const Step1Result::Candidate& u, const Step1Result::Candidate& v) {
                     return score(u.error) < score(v.error);
                   });
  // The best candidate is the result (ties go to the earlier start, the verified one first).
  best.x = best.candidates.front().x;
  best.error = best.candidates.front().error;
  best.hit_iteration_limit = best.candidates.front().hit_iteration_limit;
  return best;
}

}  // namespace fabkit::hacks::detail

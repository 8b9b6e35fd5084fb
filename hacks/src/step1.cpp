#include <algorithm>
#include <atomic>
#include <cmath>
#include <condition_variable>
#include <mutex>
#include <numbers>
#include <optional>
#include <tuple>
#include <utility>

#include "fabkit/core/parallel.h"
#include "hanging.h"
#include "random.h"
#include "steps.h"

namespace fabkit::hacks::detail {
namespace {

PoseError error_at(const Problem& p, const std::vector<double>& x) {
  const std::vector<Mat4> frames = p.assembly->part_frames(x);
  return pose_error(*p.target, Rigid<double>::from_matrix(frames[p.target->part.index()]));
}

}  // namespace

bool same_poses(const std::vector<Mat4>& a, const std::vector<Mat4>& b) {
  for (std::size_t i = 0; i < a.size(); ++i) {
    if ((a[i].topRightCorner<3, 1>() - b[i].topRightCorner<3, 1>()).norm() > 1e-3) return false;
    if ((a[i].topLeftCorner<3, 3>() - b[i].topLeftCorner<3, 3>()).norm() > 1e-6) return false;
  }
  return true;
}

namespace {

// Whether the target, held where x puts it, is inside an environment part (deeper than the
// tolerance): the contact rows between them are then constant and unmet, so no settling with
// contact rows can start.
bool held_target_inside_environment(const Problem& p, const std::vector<double>& x) {
  const Assembly& a = *p.assembly;
  const int target = p.target->part.value;
  std::vector<bool> only_target(a.nodes().size(), false);
  only_target[static_cast<std::size_t>(target)] = true;
  for (const ContactModel::PartPairDistance& near :
       p.contacts->closest_parts(a.part_frames(x), only_target, 0.0)) {
    const int other = near.part_a == target ? near.part_b : near.part_a;
    if (a.node(PartId{other}).environment && -near.distance > kPenetrationToleranceMm) {
      return true;
    }
  }
  return false;
}

}  // namespace

std::vector<double> settle_candidate(const Problem& p,
                                     const std::vector<double>& x,
                                     const SolveOptions& o) {
  if (!p.target || p.total_mass <= 0) return x;
  const Variables vars = select_variables(*p.assembly, /*physics=*/false, &p);
  if (vars.index.empty()) return x;
  Problem held = p;
  const Rigid<double> now =
      Rigid<double>::from_matrix(p.assembly->part_frames(x)[p.target->part.index()])
          .then(p.target->base);
  held.target->goal = now;
  held.target->goal_turned = now;
  // Held inside an environment (step 1 reaches a target through what is in its way: the
  // diaper caddy's goal is inside its seat back), the target stays there while it settles, and
  // a run with contact rows would only fail to start (its projection, then the pull-apart:
  // 2.8 ms of the caddy's solve): the settling goes without them, as it would after that
  // failure. Step 2's relaxation, which lets the target go, still has them.
  if (held.contacts && held_target_inside_environment(held, x)) held.contacts = nullptr;
  // A fifth of a run's iterations, as a random start of step 1 gets: the settling is only the
  // start of the relaxation, which lets the target go and goes on to rest from wherever it
  // ends. Across the hacks tests' 1,200 settlings all but two that came to their slope of
  // 10⁻⁴ did so within 100 iterations (most within 30); five never did, and spent 500: the
  // reading nook's holds its hoop where its two cycles' chains pull nearly straight, and crept
  // for 152 ms lowering the potential by 6·10⁻⁵ of itself (its solve stage 226 -> about
  // 100 ms with the bound; every test's answer unchanged).
  const int iterations = std::max(1, o.max_iterations / 5);
  const StepResult r = avoiding_contacts(
      held,
      x,
      [&](const Problem& q, const std::vector<double>& from) {
        AssemblySolver solver(q, vars, from, Objective::kEnergyHoldingTarget, o.deadline);
        return solver.relax(from, std::min(iterations, iterations_for(q, o)));
      },
      o);
  if (!r.closed) return x;
  // Settling must not move the target (the projection holds it to round-off).
  const PoseError moved =
      pose_error(*held.target,
                 Rigid<double>::from_matrix(p.assembly->part_frames(r.x)[p.target->part.index()]));
  if (moved.position_mm > 1e-6 || moved.rotation_deg > 1e-6) return x;
  return r.x;
}

namespace {

// One start of step 1: where it begins (below) and the fit from there; nothing when its cycles
// could not be closed there or the deadline has passed. The first three begin from `verified`,
// the verified configuration (a long chain hung from the top: hanging.h). `give_up` matters to the
// random starts only (they stop early when far from beating it).
std::optional<StepResult> fit_from_start(const Problem& p,
                                         const Variables& vars,
                                         const std::vector<double>& verified,
                                         const SolveOptions& o,
                                         int start,
                                         double give_up) {
  const Assembly& a = *p.assembly;
  std::vector<double> x0 = start <= 2 ? verified : a.values();
  if (start <= 2) {
    for (int v : vars.index) {
      const ParamSpec& s = a.parameters()[static_cast<std::size_t>(v)].spec;
      double& x = x0[static_cast<std::size_t>(v)];
      x += symmetry_nudge(o.seed, (*p.parameter_keys)[static_cast<std::size_t>(v)], s.hi - s.lo);
      if (s.tag != ParamTag::kUnbounded) x = std::clamp(x, s.lo, s.hi);
      // Start 2 turns every unbounded angle half a turn from the verified configuration:
      // the other way to thread a cord through a ring or to hang a part on a rod, a
      // discrete choice no local fit crosses and a lucky draw should not be needed for.
      if (start == 2 && s.tag == ParamTag::kUnbounded) x += 180.0;
    }
  } else {
    // Even starts draw every parameter; odd ones only the unbounded angles (how a ring is
    // threaded, which way a part spins about a rod), keeping the rest as verified: the
    // choices a local fit cannot change by itself.
    draw_keyed(p, vars.index, o.seed, start, /*unbounded_only=*/start % 2 == 1, x0);
  }
  if (past_deadline(p, o)) return std::nullopt;
  AssemblySolver solver(p, vars, x0, Objective::kTarget, o.deadline);
  if (start > 0 && !solver.close(x0, 100)) {
    // The local closing failed from this start: the verification's global search (two
    // phases, stall detection) usually gets there.
    VerifyOptions v;
    v.restarts = std::max(1, o.start_closings);
    v.stretch_start = false;
    v.deadline = o.deadline;
    const ClosureResult closed = close_cycles(a, x0, v);
    if (!closed.closed) return std::nullopt;
    x0 = closed.x;
  }
  // Start 1 drags the target: from where the verified configuration puts it to the goal in
  // small steps, each a short fit from the last, as a hand would guide it there. It does not
  // depend on luck, and finds goals the direct fit and the random starts miss.
  if (start == 1) {
    std::vector<double> x = verified;
    const Rigid<double> from =
        a.all_part_frames<double>(x.data())[p.target->part.index()].then(p.target->base);
    const Eigen::Quaterniond q0(from.R);
    const Eigen::Quaterniond q1(p.target->goal.R);
    constexpr int kSteps = 8;
    for (int k = 1; k <= kSteps; ++k) {
      const double s = static_cast<double>(k) / kSteps;
      Problem towards = p;
      towards.target->goal.t = (1 - s) * from.t + s * p.target->goal.t;
      towards.target->goal.R = q0.slerp(s, q1).toRotationMatrix();
      towards.target->goal_turned = towards.target->goal;
      if (towards.target->symmetry.half_turn_axis) {
        towards.target->goal_turned.R =
            towards.target->goal.R *
            Eigen::AngleAxisd(std::numbers::pi, *towards.target->symmetry.half_turn_axis);
      }
      AssemblySolver guide(towards, vars, x, Objective::kTarget, o.deadline);
      StepResult r = guide.fit(x, k == kSteps ? o.max_iterations : 20);
      if (!r.closed) break;
      x = r.x;
      // The last step fits the goal itself with a full start's iterations: it is this
      // start's fit (fitting again from its end would only spend them a second time where
      // it stopped at the limit, as a long chain's creeping fit does).
      if (k == kSteps) return r;
    }
    x0 = x;
  }
  // Random starts explore: a fifth of the iterations of the verified start, and they stop
  // early when they are far from beating the best of the full fits (f = ½‖r‖²).
  return start <= 1 ? solver.fit(x0, o.max_iterations)
                    : solver.fit(x0, o.max_iterations / 5, give_up);
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
  auto within_reach = [](const PoseError& e) {
    return e.position_mm < kTargetReached && e.rotation_deg < kTargetReached;
  };
  auto reached = [&] { return within_reach(best.error); };
  double best_score = score(best.error);
  std::vector<std::vector<Mat4>> seen_frames;
  // A start's fit joins the candidates in the order of the starts, whatever order the threads
  // finished them in.
  auto take = [&](int start, std::optional<StepResult>& fit) {
    if (!fit) return;
    best.starts = start + 1;
    StepResult& r = *fit;
    if (!r.closed) return;
    for (std::size_t i = 0; i < r.x.size(); ++i) {
      if (a.parameters()[i].spec.tag == ParamTag::kUnbounded) r.x[i] = wrap_360(r.x[i]);
    }
    const PoseError e = error_at(p, r.x);
    // Starts that end where another did are one candidate. "Where" is every part's pose, not
    // the target error: a symmetric target (a rod end for end) is as near the goal in two
    // configurations that differ in how the hack holds it, and only one of them may hold.
    // (Candidates are settled by step 2, and only those it relaxes: settle_candidate.)
    const std::vector<Mat4> frames = a.part_frames(r.x);
    bool seen = false;
    for (const std::vector<Mat4>& other : seen_frames) seen = seen || same_poses(frames, other);
    if (seen) return;
    best.candidates.push_back({r.x, e, !r.converged, start});
    seen_frames.push_back(frames);
    if (score(e) < best_score - 1e-9) {
      best_score = score(e);
      best.x = r.x;
      best.error = e;
      best.hit_iteration_limit = !r.converged;
    }
  };
  // A long chain's verified configuration is the connects' zigzag, hundreds of millimetres
  // from where it hangs (a 64-hook chain's fit from it took 500 iterations); hung from the top
  // it starts where it rests — where that leaves no parts inside each other (run_step2).
  std::vector<double> verified = a.values();
  if (const Variables physical = select_variables(a, /*physics=*/true, &p);
      static_cast<int>(physical.index.size()) >= kHangFrom) {
    if (std::optional<std::vector<double>> hung = hung_from_the_top(p, physical, verified)) {
      if (deepest_overlap(p, *hung).depth <= kPenetrationToleranceMm) verified = std::move(*hung);
    }
  }
  // The starts are independent fits. The verified start comes first: when it reaches the
  // target nothing can come nearer, and only the half-turn start is still worth its fit (it
  // may reach the target too in a configuration that holds where the first does not).
  // Otherwise the others run at once, the random ones giving up when far from the verified
  // start's fit. They join the candidates in the order of the starts, whatever order the
  // threads finished them in, and a start after one that reached the target is not taken.
  const int starts = std::max(1, o.target_starts);
  std::vector<std::optional<StepResult>> fits(static_cast<std::size_t>(starts));
  // The first start whose own fit reached the target. Once start k has, no start after
  // max(k, 2) is taken (the loop below stops there whatever they find), so those not yet begun
  // are not fitted: the paper towel holder's half-turn start reaches its goal, and its random
  // starts ran on after it for nothing (a third of its step 1).
  std::atomic<int> first_reaching{starts};
  auto fit_start = [&](const Problem& q, int start, double give_up) {
    std::optional<StepResult> fit;
    if (start > 2 && first_reaching.load() < start) return fit;
    fit = fit_from_start(q, vars, verified, o, start, give_up);
    if (fit && fit->closed && within_reach(error_at(p, fit->x))) {
      int seen = first_reaching.load();
      while (start < seen && !first_reaching.compare_exchange_weak(seen, start)) {
      }
    }
    return fit;
  };
  // What the random starts depend on, the verified start's fit alone: the start after the last
  // to run (only the half-turn start once the target is reached) and how far behind it a
  // random start gives up (f = ½‖r‖²).
  auto random_plan = [&] {
    return std::pair(reached() ? std::min(3, starts) : starts, 5 * best_score);
  };
  // With two threads the guided start runs beside the verified one at every size: 1-3 ms off
  // the small gallery designs' solve stages, 215 -> 148 ms for a 32-hook chain (history in
  // docs/benchmarks.md, the twelfth stop).
  if (thread_count(o.threads) > 1 && starts > 1) {
    // The guided start does not depend on the verified start's fit (it gives nothing up), so
    // it runs beside it, called off if the verified start reaches the target (then it is not
    // wanted). The random starts depend on the verified start's fit alone (whether it reached
    // the target, and how far they may fall behind it), so each thread goes on to them as soon
    // as that is known and its own start is done: the reading nook's verified start ends long
    // before its guided one, and its core took up the random starts then, not after both.
    Problem guided = p;
    const auto guided_clock = std::make_shared<const StopClock>(p.stop);
    guided.stop = guided_clock;
    std::mutex planning;
    std::condition_variable planned_signal;
    bool planned = false;
    int last = starts;
    double give_up = 0;
    std::atomic<int> next{2};
    const int workers = std::max(2, std::min(thread_count(o.threads), starts));
    run_in_parallel(workers, o.threads, [&](int k) {
      if (k == 0) {
        // Whatever happens to the verified start's fit, the plan is published (a thread that
        // waits for it must not wait for ever).
        struct Publish {
          std::mutex& m;
          std::condition_variable& cv;
          bool& flag;
          ~Publish() {
            {
              const std::lock_guard lock(m);
              flag = true;
            }
            cv.notify_all();
          }
        } publish{planning, planned_signal, planned};
        fits[0] = fit_from_start(p, vars, verified, o, 0, 0.0);
        take(0, fits[0]);
        if (reached()) guided_clock->call_off();
        std::tie(last, give_up) = random_plan();
      } else if (k == 1) {
        fits[1] = fit_start(guided, 1, 0.0);
      }
      {
        std::unique_lock lock(planning);
        planned_signal.wait(lock, [&] { return planned; });
      }
      for (int start = next++; start < last; start = next++) {
        fits[static_cast<std::size_t>(start)] = fit_start(p, start, give_up);
      }
    });
  } else {
    fits[0] = fit_from_start(p, vars, verified, o, 0, 0.0);
    take(0, fits[0]);
    const int first = reached() ? 2 : 1;  // the first start after the verified one to fit
    int last = starts;
    double give_up = 0;
    std::tie(last, give_up) = random_plan();
    run_in_parallel(std::max(0, last - first), o.threads, [&](int k) {
      fits[static_cast<std::size_t>(first + k)] = fit_start(p, first + k, give_up);
    });
  }
  for (int start = 1; start < starts; ++start) {
    if (start == 1 && reached()) continue;
    if (start > 2 && reached()) break;
    take(start, fits[static_cast<std::size_t>(start)]);
  }
  // The fits let parts pass through each other (they are cheap that way); settling and step 2
  // keep them apart where a result does.
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

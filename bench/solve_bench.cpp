// End-to-end cost of solving each gallery example (issue 3: median under 100 ms each, the
// reading nook under 1 s; issue 9 item 8: the solve stage under 10 ms): reading the design and
// verifying every connect, step 1 (reach the target), step 2 (settle the candidates it
// relaxes, relax under gravity, with contacts where parts would pass through each other) and
// the stability verdict.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "../hacks/tests/span_design.h"
#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/solve.h"

namespace {

using namespace fabkit::hacks;
using fabkit::Frame;
using fabkit::Mat4;
using fabkit::PartId;

std::string read(const std::string& example) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + example + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Reading the design and solving it, per iteration. Designs not at rest are timed too
// (docs/gallery.md says why they are not): the counter `stable` is 1 or 0.
void time_solve(benchmark::State& state, const std::string& text, const std::string& name) {
  const PartsLibrary& lib = PartsLibrary::builtin();
  bool stable = false;
  if (!load_design_text(text, name, lib).feasible()) {
    state.SkipWithError("the design does not verify");
    return;
  }
  for (auto _ : state) {
    const Design d = load_design_text(text, name, lib);
    const SolveResult r = solve(d.assembly);
    stable = r.stable;
    benchmark::DoNotOptimize(r);
  }
  state.counters["stable"] = stable ? 1 : 0;
}

void solve_example(benchmark::State& state, const std::string& example) {
  time_solve(state, read(example), example);
}

// The solve stage alone (issue 9 item 8: under 10 ms): step 1, step 2 and the verdict on a
// design read and verified once, outside the timing.
void solve_stage(benchmark::State& state, const std::string& example) {
  const Design d = load_design_text(read(example), example, PartsLibrary::builtin());
  if (!d.feasible()) {
    state.SkipWithError("the design does not verify");
    return;
  }
  bool stable = false;
  for (auto _ : state) {
    const SolveResult r = solve(d.assembly);
    stable = r.stable;
    benchmark::DoNotOptimize(r);
  }
  state.counters["stable"] = stable ? 1 : 0;
}

#define FABKIT_SOLVE_BENCH(name)                                                             \
  BENCHMARK_CAPTURE(solve_example, name, std::string(#name))->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(solve_stage, name, std::string(#name))->Unit(benchmark::kMillisecond)

FABKIT_SOLVE_BENCH(toothbrush_holder);
FABKIT_SOLVE_BENCH(charger_holder);
FABKIT_SOLVE_BENCH(soap_bottle_holder);
FABKIT_SOLVE_BENCH(soap_bottle_one_eyehook);
FABKIT_SOLVE_BENCH(mug_hanger);
FABKIT_SOLVE_BENCH(paper_towel_holder);
FABKIT_SOLVE_BENCH(diaper_caddy);
FABKIT_SOLVE_BENCH(basket_between_rods);
FABKIT_SOLVE_BENCH(bird_feeder);
FABKIT_SOLVE_BENCH(demo);
FABKIT_SOLVE_BENCH(clip_light_xs);
FABKIT_SOLVE_BENCH(clip_light_s);
FABKIT_SOLVE_BENCH(clip_light_m);
FABKIT_SOLVE_BENCH(clip_light_l);
FABKIT_SOLVE_BENCH(reading_nook);

// ---- Scale (issue 9, item 8) -------------------------------------------------------------

// N S-hooks hanging from a level rod, a mug on the last; with `mug_goal`, the mug is the target
// and its hook's goal that frame.
std::string hook_chain(int n, std::optional<Frame> mug_goal) {
  std::string s =
      "fabkit: hacks/1\nname: chain\nenvironment:\n"
      "  - {name: bar, primitives: {rod: {type: rod, radius: 4, length: 300}}, "
      "frame: {pos: [0, 0, 6000], rot: [90, 0, 0]}}\nparts:\n";
  for (int i = 1; i <= n; ++i) s += "  - {name: s" + std::to_string(i) + ", part: DoubleHook}\n";
  if (mug_goal) {
    s += fmt::format(
        "target: {{name: mug, part: Mug, primitive: hook, frame: {{pos: [{}, {}, {}], rot: [{}, "
        "{}, {}]}}}}\n",
        mug_goal->pos.x(),
        mug_goal->pos.y(),
        mug_goal->pos.z(),
        mug_goal->rot.x(),
        mug_goal->rot.y(),
        mug_goal->rot.z());
  } else {
    s += "  - {name: mug, part: Mug}\n";
  }
  s += "connections:\n  - connect: [s1.hook1, bar.rod]\n";
  for (int i = 2; i <= n; ++i) {
    s += fmt::format("  - connect: [s{}.hook1, s{}.hook2]\n", i, i - 1);
  }
  s += fmt::format("  - connect: [mug.hook, s{}.hook2]\n", n);
  return s;
}

// Where the mug's hook rests at the end of a chain of n hooks (solved once, untimed).
Frame resting_mug_hook(int n) {
  const Design d = load_design_text(hook_chain(n, std::nullopt), "chain", PartsLibrary::builtin());
  const SolveResult r = solve(d.assembly);
  for (int i = 0; i < d.assembly.part_count(); ++i) {
    if (d.assembly.label(PartId{i}) != "mug") continue;
    const Part& mug = *d.assembly.node(PartId{i}).part;
    const Mat4 hook = d.assembly.part_frames(r.parameters)[static_cast<std::size_t>(i)] *
                      mug.primitive(mug.find_primitive("hook")).frame.matrix();
    return Frame::from_matrix(hook);
  }
  return {};
}

// The whole solve of a chain of N hooks with the mug as its target, 20 mm beside its rest.
void chain_with_target(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  Frame goal = resting_mug_hook(n);
  goal.pos.x() += 20;
  time_solve(state, hook_chain(n, goal), "chain");
  state.counters["parts"] = n + 2;
}
BENCHMARK(chain_with_target)
    ->RangeMultiplier(2)
    ->Range(2, 128)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2);

// The same chain with no target: verification, then step 2 alone (from 12 hooks the chain is
// hung link by link before it relaxes: docs/hacks.md).
void chain_alone(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  time_solve(state, hook_chain(n, std::nullopt), "chain");
  state.counters["parts"] = n + 2;
}
BENCHMARK(chain_alone)
    ->RangeMultiplier(2)
    ->Range(2, 128)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(0.2);

// `cycles` chains of 3 S-hooks, each between its own two rods 80 mm apart: independent cycles.
void independent_cycles(benchmark::State& state) {
  const int cycles = static_cast<int>(state.range(0));
  std::string s = "fabkit: hacks/1\nname: cycles\nenvironment:\n";
  for (int c = 0; c < cycles; ++c) {
    s += fmt::format(
        "  - {{name: left{0}, primitives: {{rod: {{type: rod, radius: 4, length: 100}}}}, frame: "
        "{{pos: [-40, {1}, 500], rot: [90, 0, 0]}}}}\n"
        "  - {{name: right{0}, primitives: {{rod: {{type: rod, radius: 4, length: 100}}}}, frame: "
        "{{pos: [40, {1}, 500], rot: [90, 0, 180]}}}}\n",
        c,
        200 * c);
  }
  s += "parts:\n";
  std::string connects = "connections:\n";
  for (int c = 0; c < cycles; ++c) {
    for (int i = 1; i <= 3; ++i) s += fmt::format("  - {{name: s{}_{}, part: DoubleHook}}\n", c, i);
    connects += fmt::format("  - connect: [s{0}_1.hook1, left{0}.rod]\n", c);
    connects += fmt::format("  - connect: [s{0}_2.hook1, s{0}_1.hook2]\n", c);
    connects += fmt::format("  - connect: [s{0}_3.hook1, s{0}_2.hook2]\n", c);
    connects += fmt::format("  - {{connect: [s{0}_3.hook2, right{0}.rod], alignment: flip}}\n", c);
  }
  time_solve(state, s + connects, "cycles");
}
BENCHMARK(independent_cycles)->Arg(1)->Arg(2)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

// N S-hooks slack between two wall hooks 605.5 mm apart (15 reach about 636 mm; 24 about
// 1 m): the cycle search closes the long ones with links folded through each other, and
// step 2 unfolds them (docs/hacks.md, step 2).
void slack_span(benchmark::State& state) {
  const int hooks = static_cast<int>(state.range(0));
  time_solve(state, testing_designs::span_between_wall_hooks(hooks), "span");
}
BENCHMARK(slack_span)->Arg(15)->Arg(20)->Arg(24)->Arg(28)->Unit(benchmark::kMillisecond);

// A shower curtain rod in two S-hooks on a rail (three parts, no target): what relaxations
// with contact rows cost where the contacts they bind change from step to step (three of its
// runs stop at the 150-iteration cap for contact runs: docs/benchmarks.md, the twelfth stop).
void contacts_bar_in_two_hooks(benchmark::State& state) {
  time_solve(state,
             "fabkit: hacks/1\nname: bar in two hooks\nenvironment:\n"
             "  - {name: rail, primitives: {rod: {type: rod, radius: 6, length: 400}}, "
             "frame: {pos: [0, 0, 1200], rot: [0, 90, 0]}}\n"
             "parts:\n  - {name: s1, part: DoubleHook}\n  - {name: s2, part: DoubleHook}\n"
             "  - {name: bar, part: ShowerCurtainRod}\nconnections:\n"
             "  - connect: [s1.hook1, rail.rod]\n  - connect: [bar.rod, s1.hook2]\n"
             "  - connect: [s2.hook1, rail.rod]\n  - connect: [s2.hook2, bar.rod]\n",
             "bar in two hooks");
}
BENCHMARK(contacts_bar_in_two_hooks)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();

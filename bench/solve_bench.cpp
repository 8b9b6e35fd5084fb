// End-to-end cost of solving each gallery example (issue targets: median under 100 ms each,
// the reading nook under 1 s): reading the design and verifying every connect, step 1
// (reach the target), step 2 (relax under gravity) and the stability verdict.
#include <benchmark/benchmark.h>

#include <fstream>
#include <sstream>
#include <string>

#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/solve.h"

namespace {

using namespace fabkit::hacks;

std::string read(const std::string& example) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + example + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void solve_example(benchmark::State& state, const std::string& example) {
  const std::string text = read(example);
  const PartsLibrary& lib = PartsLibrary::builtin();
  bool stable = false;
  for (auto _ : state) {
    const Design d = load_design_text(text, example, lib);
    const SolveResult r = solve(d.assembly);
    stable = r.stable;
    benchmark::DoNotOptimize(r);
  }
  if (!stable) state.SkipWithError("not stable");
}

#define FABKIT_SOLVE_BENCH(name) \
  BENCHMARK_CAPTURE(solve_example, name, std::string(#name))->Unit(benchmark::kMillisecond)

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

}  // namespace

BENCHMARK_MAIN();

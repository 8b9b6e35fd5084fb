// Cost of writing a solved gallery design's files (`fabkit build` / `fabkit solve -o`) now that
// every part is exported as one closed solid: the exact union of its pieces (part_solid.h),
// once per part type, then result.json, scene.glb, preview.svg, assembly.stl and assembly.obj.
// The design is read and solved once, outside the timing.
//   export/<design>  a cold export, as one `fabkit build` pays it (a fresh cache of solids)
//   solids/<design>  only the unions (the solids of every part type of the design)
//   disk/<design>    a `fabkit solve -o` run after the first on this machine: a fresh cache
//                    reading the solids its directory kept (the CLI's ~/.cache/fabkit/solids)
//   display/<design> the same five files from the display meshes (overlapping pieces), as
//                    exports were written before parts became solids: the baseline
//   warm/<design>    an export again in the same session (the cache already holds the solids)
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "fabkit/core/export_formats.h"
#include "fabkit/core/file_io.h"
#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/solution_export.h"
#include "fabkit/hacks/solve.h"

namespace {

using namespace fabkit;
using namespace fabkit::hacks;

struct Solved {
  Design design;
  SolveResult result;
};

const Solved& solved(const std::string& example) {
  static std::map<std::string, Solved> cache;
  if (auto it = cache.find(example); it != cache.end()) return it->second;
  const std::string path = std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + example + ".yaml";
  Solved s{load_design(path, PartsLibrary::builtin()), {}};
  if (!s.design.feasible()) {
    std::fprintf(
        stderr, "%s does not load\n%s", path.c_str(), s.design.diagnostics.format().c_str());
    std::exit(1);
  }
  s.result = solve(s.design.assembly);
  return cache.emplace(example, std::move(s)).first->second;
}

std::filesystem::path out_dir(const std::string& example) {
  return std::filesystem::temp_directory_path() / ("fabkit_export_bench_" + example);
}

void export_cold(benchmark::State& state, const std::string& example) {
  const Solved& s = solved(example);
  bool ok = true;
  for (auto _ : state) {
    Diagnostics d;
    ok = export_solution(s.design.assembly, s.result, out_dir(example), d) && d.empty() && ok;
  }
  std::filesystem::remove_all(out_dir(example));
  if (!ok) state.SkipWithError("export failed or a part is not one solid");
}

void solids_only(benchmark::State& state, const std::string& example) {
  const Solved& s = solved(example);
  int types = 0;
  for (auto _ : state) {
    PartSolidCache solids;
    Diagnostics d;
    benchmark::DoNotOptimize(solid_scene(s.design.assembly, s.result, solids, d));
    types = solids.computed();
  }
  state.counters["part_types"] = types;
  state.counters["parts"] = s.design.assembly.part_count();
}

void export_disk(benchmark::State& state, const std::string& example) {
  const Solved& s = solved(example);
  const std::filesystem::path kept =
      std::filesystem::temp_directory_path() / ("fabkit_export_bench_solids_" + example);
  std::filesystem::remove_all(kept);
  {
    PartSolidCache first(kept);  // the first run on this machine fills the directory
    Diagnostics d;
    solid_scene(s.design.assembly, s.result, first, d);
  }
  bool ok = true;
  int computed = 0;
  for (auto _ : state) {
    PartSolidCache solids(kept);
    ExportOptions options;
    options.solids = &solids;
    Diagnostics d;
    ok = export_solution(s.design.assembly, s.result, out_dir(example), d, options) && d.empty() &&
         ok;
    computed += solids.computed();
  }
  std::filesystem::remove_all(out_dir(example));
  std::filesystem::remove_all(kept);
  if (!ok) state.SkipWithError("export failed or a part is not one solid");
  if (computed > 0) state.SkipWithError("a solid was computed although the directory held it");
}

void export_display(benchmark::State& state, const std::string& example) {
  const Solved& s = solved(example);
  const std::filesystem::path dir = out_dir(example);
  bool ok = true;
  for (auto _ : state) {
    Diagnostics d;
    ok = make_output_directory(dir, d) && ok;
    ok = write_file_atomically(
             dir / "result.json", result_json(s.design.assembly, s.result, example), d) &&
         ok;
    const std::vector<SceneObject> scene = solution_scene(s.design.assembly, s.result);
    const std::vector<SceneObject> parts(scene.begin(),
                                         scene.begin() + s.design.assembly.part_count());
    ok = write_scene("glb", scene, dir / "scene.glb", d) && ok;
    ok = write_scene("svg", scene, dir / "preview.svg", d) && ok;
    ok = write_scene("stl", parts, dir / "assembly.stl", d) && ok;
    ok = write_scene("obj", parts, dir / "assembly.obj", d) && ok;
  }
  std::filesystem::remove_all(dir);
  if (!ok) state.SkipWithError("export failed");
}

void export_warm(benchmark::State& state, const std::string& example) {
  const Solved& s = solved(example);
  PartSolidCache solids;
  {
    Diagnostics d;  // the session's first export, outside the timing
    solid_scene(s.design.assembly, s.result, solids, d);
  }
  ExportOptions options;
  options.solids = &solids;
  bool ok = true;
  for (auto _ : state) {
    Diagnostics d;
    ok = export_solution(s.design.assembly, s.result, out_dir(example), d, options) && ok;
  }
  std::filesystem::remove_all(out_dir(example));
  if (!ok) state.SkipWithError("export failed");
}

#define FABKIT_EXPORT_BENCH(name)                                                             \
  BENCHMARK_CAPTURE(export_cold, name, std::string(#name))->Unit(benchmark::kMillisecond);    \
  BENCHMARK_CAPTURE(solids_only, name, std::string(#name))->Unit(benchmark::kMillisecond);    \
  BENCHMARK_CAPTURE(export_disk, name, std::string(#name))->Unit(benchmark::kMillisecond);    \
  BENCHMARK_CAPTURE(export_display, name, std::string(#name))->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(export_warm, name, std::string(#name))->Unit(benchmark::kMillisecond)

FABKIT_EXPORT_BENCH(toothbrush_holder);
FABKIT_EXPORT_BENCH(charger_holder);
FABKIT_EXPORT_BENCH(soap_bottle_holder);
FABKIT_EXPORT_BENCH(soap_bottle_one_eyehook);
FABKIT_EXPORT_BENCH(mug_hanger);
FABKIT_EXPORT_BENCH(paper_towel_holder);
FABKIT_EXPORT_BENCH(diaper_caddy);
FABKIT_EXPORT_BENCH(basket_between_rods);
FABKIT_EXPORT_BENCH(bird_feeder);
FABKIT_EXPORT_BENCH(demo);
FABKIT_EXPORT_BENCH(clip_light_xs);
FABKIT_EXPORT_BENCH(clip_light_s);
FABKIT_EXPORT_BENCH(clip_light_m);
FABKIT_EXPORT_BENCH(clip_light_l);
FABKIT_EXPORT_BENCH(reading_nook);

}  // namespace

BENCHMARK_MAIN();

// The rods kit against the targets, on the 52-rod model (examples/rods/wolf_head_52):
//   preview (offsets, hulls and prisms, no booleans) + every check   < 16 ms (60 fps designer)
//   the full exact package with engraving, written to disk           < 10 s (2 cores)
//   the cut plan, optimal or proven within one stock rod              < 1 s
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include "fabkit/core/cut_plan.h"
#include "fabkit/rods/build.h"
#include "fabkit/rods/check.h"
#include "fabkit/rods/design_file.h"
#include "fabkit/rods/engraving.h"
#include "fabkit/rods/frame_analysis.h"
#include "fabkit/rods/joint_geometry.h"
#include "fabkit/rods/joint_solid.h"
#include "fabkit/rods/outputs.h"

namespace {

using namespace fabkit;
using namespace fabkit::rods;

const Design& model(const std::string& name = "wolf_head_52") {
  static std::map<std::string, Design> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    Design d = load_design(std::string(FABKIT_SOURCE_DIR) + "/examples/rods/" + name + ".yaml");
    if (!d.readable) {
      std::fprintf(stderr, "%s\n", d.diagnostics.format().c_str());
      std::exit(1);
    }
    it = cache.emplace(name, std::move(d)).first;
  }
  return it->second;
}

// What the designer recomputes on every edit: Appendix A quantities, the preview meshes and
// the checks of §3.1 (rod intersections, swallowed and short rods, balance).
void BM_PreviewAndChecks(benchmark::State& state) {
  const Design& d = model();
  for (auto _ : state) {
    const Layout l = compute_layout(d.structure, d.parameters);
    const Preview preview = make_preview(d.structure, d.parameters, l);
    const CheckReport r = check(d.structure, d.parameters, l, CheckOptions{}, preview.joint_masses);
    benchmark::DoNotOptimize(preview.joints.data());
    benchmark::DoNotOptimize(r.balance.margin);
  }
  state.counters["joints"] = static_cast<double>(d.structure.nodes.size());
  state.counters["rods"] = static_cast<double>(d.structure.rods.size());
}
BENCHMARK(BM_PreviewAndChecks)->Unit(benchmark::kMillisecond);

// Beyond the paper: the 3D frame analysis (self-weight, supports at the floor contacts).
void BM_FrameAnalysis(benchmark::State& state) {
  const Design& d = model();
  const Layout l = compute_layout(d.structure, d.parameters);
  for (auto _ : state) {
    const FrameResult r = analyse_frame(d.structure, d.parameters, l, FrameOptions{});
    benchmark::DoNotOptimize(r.max_utilisation);
  }
}
BENCHMARK(BM_FrameAnalysis)->Unit(benchmark::kMillisecond);

void BM_CutPlanModel(benchmark::State& state) {
  const Design& d = model();
  const Layout l = compute_layout(d.structure, d.parameters);
  std::vector<CutPiece> pieces;
  for (std::size_t e = 0; e < l.rod_length.size(); ++e)
    pieces.push_back({d.structure.rod_name(static_cast<int>(e)), l.rod_length[e]});
  int count = 0, gap = 0;
  for (auto _ : state) {
    Diagnostics diags;
    const auto plan = plan_cuts(pieces, d.parameters.stock, diags);
    count = plan->stock_count();
    gap = plan->gap();
  }
  state.counters["stock"] = count;
  state.counters["gap"] = gap;
}
BENCHMARK(BM_CutPlanModel)->Unit(benchmark::kMillisecond);

// A hard instance of the model's size: 51 pieces whose lengths fill 1 m of usable stock
// exactly in triples (optimum 17), which first fit over every ordering tried misses; the
// integer program has to find the triples.
void BM_CutPlanHard(benchmark::State& state) {
  std::mt19937 rng(3);
  std::vector<CutPiece> pieces;
  while (pieces.size() < 51) {
    const int a = 250 + static_cast<int>(rng() % 251), b = 250 + static_cast<int>(rng() % 251),
              c = 1000 - a - b;
    if (c < 250 || c > 500) continue;
    for (const int x : {a, b, c}) {
      char label[16];
      std::snprintf(label, sizeof label, "p%zu", pieces.size() + 1);
      pieces.push_back({label, double(x)});
    }
  }
  const StockSpec stock{1020, 10, 0};
  int count = 0, gap = 0, first_fit = 0;
  for (auto _ : state) {
    Diagnostics diags;
    const auto plan = plan_cuts(pieces, stock, diags);
    count = plan->stock_count();
    gap = plan->gap();
    first_fit = plan->first_fit_stock_count;
  }
  state.counters["stock"] = count;
  state.counters["gap"] = gap;
  state.counters["first_fit"] = first_fit;
}
BENCHMARK(BM_CutPlanHard)->Unit(benchmark::kMillisecond);

// One joint of the model (the one with most rods), with and without its engraving.
void BM_OneJoint(benchmark::State& state) {
  const Design& d = model();
  const Layout l = compute_layout(d.structure, d.parameters);
  int node = 0;
  for (std::size_t i = 0; i < l.rods_at.size(); ++i) {
    if (l.rods_at[i].size() > l.rods_at[static_cast<std::size_t>(node)].size())
      node = static_cast<int>(i);
  }
  JointSolidOptions o;
  o.engrave = state.range(0) != 0;
  for (auto _ : state) {
    Diagnostics diags;
    const auto j = make_joint_solid(d.structure, d.parameters, l, node, o, diags);
    benchmark::DoNotOptimize(j->volume);
  }
}
BENCHMARK(BM_OneJoint)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// Everything `fabkit build` does: checks, frame, cut plan, assembly, 28 exact engraved joints
// on two threads, and every output file.
void BM_FullPackage(benchmark::State& state) {
  const Design& d = model();
  const auto dir = std::filesystem::temp_directory_path() / "fabkit_rods_bench";
  for (auto _ : state) {
    BuildOptions o;
    o.threads = 2;
    const Summary s = build(d, o);
    Diagnostics io;
    const auto written = write_outputs(d, s, dir, io);
    if (s.joints.size() != d.structure.nodes.size() || io.has_errors())
      state.SkipWithError("build failed");
    benchmark::DoNotOptimize(written.size());
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_FullPackage)->Unit(benchmark::kSecond)->Iterations(1)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();

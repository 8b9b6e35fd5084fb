// flatpack: placement + intersection detection + joints (check) for the reading desk and a
// generated 60-piece bookcase, and nesting their pieces onto 600 × 400 mm sheets.
#include <benchmark/benchmark.h>
#include <fmt/format.h>

#include "fabkit/core/nesting.h"
#include "fabkit/flatpack/check.h"
#include "fabkit/flatpack/design_file.h"

using namespace fabkit;
using namespace fabkit::flatpack;

namespace {

Design reading_desk() {
  Diagnostics d;
  return load_design(std::string(FABKIT_SOURCE_DIR) + "/examples/flatpack/reading_desk.yaml", d);
}

// Two sides and 58 shelves with finger–hole joints: 60 pieces (the benchmark reports the joints).
Design bookcase(int shelves) {
  std::string y =
      "fabkit: flatpack/1\nname: bookcase\ncomponents:\n  - {name: left, type: Rectangle, l: 200, "
      "w: 2000}\n"
      "  - {name: right, type: Rectangle, l: 200, w: 2000}\n";
  for (int k = 0; k < shelves; ++k)
    y += fmt::format("  - {{name: s{}, type: Rectangle, l: 400, w: 200}}\n", k);
  y += "connections:\n  - {connect: [right.l, left.l], offset: [0, 0, -400], alignment: "
       "front-back}\n";
  for (int k = 0; k < shelves; ++k) {
    y +=
        fmt::format("  - {{connect: [s{}.l, left.b], offset: [0, {}, 0], rotation: [-90, 0, 0]}}\n",
                    k,
                    20 + k * (1960.0 / shelves));
  }
  Diagnostics d;
  return load_design_text(y, "bookcase.yaml", d);
}

void BM_CheckReadingDesk(benchmark::State& state) {
  const Design d = reading_desk();
  CheckOptions o;
  o.assembly_order = false;
  for (auto _ : state) benchmark::DoNotOptimize(check(d, o));
}
BENCHMARK(BM_CheckReadingDesk)->Unit(benchmark::kMillisecond);

void BM_CheckBookcase60(benchmark::State& state) {
  const Design d = bookcase(58);
  CheckOptions o;
  o.assembly_order = false;
  const Analysis a = check(d, o);
  state.counters["pieces"] = static_cast<double>(a.pieces.size());
  state.counters["joints"] = static_cast<double>(a.joints.size());
  for (auto _ : state) benchmark::DoNotOptimize(check(d, o));
}
BENCHMARK(BM_CheckBookcase60)->Unit(benchmark::kMillisecond);

void nest_pieces(benchmark::State& state, const Design& d) {
  const Analysis a = check(d);
  std::vector<Polygon2d> pieces;
  double total = 0;
  for (const Piece& p : a.pieces) {
    pieces.push_back(p.cut[0]);
    total += p.cut[0].area();
  }
  NestingResult r;
  for (auto _ : state) r = nest(pieces, {}, {});
  state.counters["sheets"] = r.sheet_count;
  state.counters["utilisation_pct"] = 100 * r.utilisation;
  // A hand layout's lower bound: the pieces' area over one sheet's area, rounded up.
  state.counters["area_bound_sheets"] = std::ceil(total / (600.0 * 400.0));
}

void BM_NestReadingDesk(benchmark::State& state) {
  nest_pieces(state, reading_desk());
}
BENCHMARK(BM_NestReadingDesk)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

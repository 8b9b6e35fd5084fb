// The templates kit's interactive operations, timed (docs/benchmarks.md, "Templates").
//   build/bin/fabkit_bench_templates --benchmark_repetitions=10
//   --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>

#include "fabkit/templates/bom.h"
#include "fabkit/templates/check.h"
#include "fabkit/templates/connect.h"
#include "fabkit/templates/database.h"
#include "fabkit/templates/manipulate.h"
#include "fabkit/templates/snap.h"
#include "fabkit/templates/stability.h"

using namespace fabkit;
using namespace fabkit::templates;

namespace {

const TemplateDatabase& db() {
  return TemplateDatabase::bundled();
}

Template must(std::string_view spec) {
  Diagnostics d;
  auto t = db().find(spec, d);
  if (!t) {
    std::fprintf(stderr, "%s\n", d.format().c_str());
    std::abort();
  }
  return *t;
}

// The example table with a bottom shelf (81 parts), composed.
WorkingModel table_with_shelf() {
  WorkingModel wm;
  Diagnostics d;
  wm.add(must("dining_table"), "dining_table", "table", std::nullopt, d);
  auto c = wm.add(must("bookshelf/shelves/bottom_shelf"), "bookshelf", "shelf", Vec3(0, 0, 40), d);
  {
    const Manipulator m(wm.model());
    wm.model().q = m.set(m.control(c->node, ControlKind::kSizeY), 789).q;
  }
  wm.model().q = snap(wm, *c, db()).q;
  connect(wm, *c, db());
  return wm;
}

// A model of more than 200 parts: the table with its shelf, a chest of drawers beside it and
// a kitchen stool (74 + 106 + 35 = 215 parts).
WorkingModel big_model() {
  WorkingModel wm = table_with_shelf();
  Diagnostics d;
  wm.add(must("chest_of_drawers"), "chest_of_drawers", "chest", Vec3(1500, 0, 450), d);
  wm.add(must("stool"), "stool", "stool", Vec3(-1400, 0, 309), d);
  return wm;
}

void drag_step(benchmark::State& state, QpSolver solver, bool binding) {
  WorkingModel wm = big_model();
  Template& t = wm.model();
  ManipulateOptions o;
  o.solver = solver;
  const Manipulator m(t, o, &db().catalog());
  // Free: the chest's width (its drawers follow). Binding: the table's legs squeezed against
  // the shelf brackets' order constraints.
  const NodeId node = binding ? t.find("table/base/legs") : t.find("chest");
  const Control c = m.control(node, ControlKind::kSizeX);
  const Eigen::VectorXd start = t.q;
  double delta = binding ? -4000 : 2;
  int steps = 0;
  bool solver_used = false;
  for (auto _ : state) {
    const DragResult r = m.drag(c, delta);
    benchmark::DoNotOptimize(r.q.data());
    solver_used = solver_used || r.used_solver;
    if (binding) continue;  // the same clipped step each time
    t.q = r.q;
    delta = -delta;
    ++steps;
  }
  t.q = start;
  state.counters["parts"] = t.part_count();
  state.counters["parameters"] = static_cast<double>(t.q.size());
  state.counters["solver"] = solver_used ? 1 : 0;
}

void BM_DragStep200Parts(benchmark::State& state) {
  drag_step(state, QpSolver::kSlsqp, false);
}
void BM_DragStep200PartsBinding_Slsqp(benchmark::State& state) {
  drag_step(state, QpSolver::kSlsqp, true);
}
void BM_DragStep200PartsBinding_Ipopt(benchmark::State& state) {
  drag_step(state, QpSolver::kIpopt, true);
}

// Starting a drag: the null space of the 200-part model's equalities (done once per control).
void BM_DragSessionStart200Parts(benchmark::State& state) {
  WorkingModel wm = big_model();
  for (auto _ : state) {
    const Manipulator m(wm.model(), {}, &db().catalog());
    const DragResult r = m.drag(m.control(wm.model().find("chest"), ControlKind::kSizeX), 1);
    benchmark::DoNotOptimize(r.q.data());
  }
}

void BM_SnapShelfUnderTable(benchmark::State& state) {
  WorkingModel wm;
  Diagnostics d;
  wm.add(must("dining_table"), "dining_table", "table", std::nullopt, d);
  auto c = wm.add(must("bookshelf/shelves/bottom_shelf"), "bookshelf", "shelf", Vec3(0, 0, 40), d);
  {
    const Manipulator m(wm.model());
    wm.model().q = m.set(m.control(c->node, ControlKind::kSizeY), 789).q;
  }
  int n = 0;
  for (auto _ : state) {
    const SnapResult s = snap(wm, *c, db());
    n = s.combinations;
    benchmark::DoNotOptimize(s.q.data());
  }
  state.counters["placements"] = n;
}

void BM_ConnectShelfUnderTable(benchmark::State& state) {
  WorkingModel wm;
  Diagnostics d;
  wm.add(must("dining_table"), "dining_table", "table", std::nullopt, d);
  auto c = wm.add(must("bookshelf/shelves/bottom_shelf"), "bookshelf", "shelf", Vec3(0, 0, 40), d);
  {
    const Manipulator m(wm.model());
    wm.model().q = m.set(m.control(c->node, ControlKind::kSizeY), 789).q;
  }
  wm.model().q = snap(wm, *c, db()).q;
  for (auto _ : state) {
    WorkingModel copy = wm;
    const ConnectResult r = connect(copy, *c, db());
    benchmark::DoNotOptimize(r.links.data());
  }
}

void stability(benchmark::State& state, QpSolver solver, const char* which) {
  WorkingModel wm = std::string(which) == "big" ? big_model() : table_with_shelf();
  StabilityOptions o;
  o.solver = solver;
  int vars = 0;
  for (auto _ : state) {
    const StabilityResult r = check_stability(wm.model(), db().catalog(), o);
    vars = r.variables;
    benchmark::DoNotOptimize(r.bodies.data());
  }
  state.counters["variables"] = vars;
}
void BM_StabilityTableWithShelf_Slsqp(benchmark::State& s) {
  stability(s, QpSolver::kSlsqp, "table");
}
void BM_StabilityTableWithShelf_Ipopt(benchmark::State& s) {
  stability(s, QpSolver::kIpopt, "table");
}
void BM_Stability200Parts_Slsqp(benchmark::State& s) {
  stability(s, QpSolver::kSlsqp, "big");
}
void BM_Stability200Parts_Ipopt(benchmark::State& s) {
  stability(s, QpSolver::kIpopt, "big");
}

void BM_BillOfMaterials(benchmark::State& state, const char* which) {
  WorkingModel wm = std::string(which) == "big" ? big_model() : table_with_shelf();
  for (auto _ : state) {
    Diagnostics d;
    auto bom = bill_of_materials(wm.model(), db().catalog(), d);
    benchmark::DoNotOptimize(bom->total);
  }
}

void BM_ExtractChestOfDrawers(benchmark::State& state) {
  const SourceDesign& d = *db().design("chest_of_drawers");
  for (auto _ : state) {
    Diagnostics diags;
    auto t = make_template(d, &db().catalog(), diags);
    benchmark::DoNotOptimize(t->q.data());
  }
}

}  // namespace

BENCHMARK(BM_DragStep200Parts)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DragStep200PartsBinding_Slsqp)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DragStep200PartsBinding_Ipopt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DragSessionStart200Parts)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SnapShelfUnderTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConnectShelfUnderTable)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StabilityTableWithShelf_Slsqp)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StabilityTableWithShelf_Ipopt)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Stability200Parts_Slsqp)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Stability200Parts_Ipopt)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BillOfMaterials, table_with_shelf, "table")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_BillOfMaterials, big_model_215_parts, "big")->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ExtractChestOfDrawers)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

// flatpack: placement + intersection detection + joints (check) for the reading desk and a
// generated 60-piece bookcase; nesting the reading desk and the bunk bed onto 600 × 400 mm
// sheets, the bunk bed compared with a hand layout (bench/data/bunk_bed_hand_layout.yaml).
#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <map>
#include <set>

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
  // The right side lies over the left one, 400 mm behind it (front-back flips it over the
  // shared edge, the 200 mm offset along the edge's inward axis brings it back over the left).
  y += "connections:\n  - {connect: [right.l, left.l], offset: [0, 200, -400], alignment: "
       "front-back, joint: none}\n";
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
  // Each shelf goes into both sides.
  if (a.pieces.size() != 60 || a.joints.size() != 116 || a.diagnostics.has_errors()) {
    state.SkipWithError("the bookcase is not 60 pieces with 116 joints");
    return;
  }
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

// A hand layout (bench/data/bunk_bed_hand_layout.yaml): shelves of pieces by their bounding
// boxes. Returns the sheets used and the pieces' area over the sheets' area, after checking the
// layout: every piece once, inside the margin, no two boxes overlapping (else `error` says how).
struct HandLayout {
  int sheets = 0;
  double utilisation = 0;
  std::vector<double> per_sheet;
  std::string error;
};

HandLayout hand_layout(const Analysis& a, const std::string& file) {
  HandLayout out;
  const YAML::Node root = YAML::LoadFile(file);
  const double width = root["sheet"]["width"].as<double>();
  const double height = root["sheet"]["height"].as<double>();
  const double margin = root["sheet"]["margin"].as<double>();
  const double spacing = root["sheet"]["spacing"].as<double>();
  std::map<std::string, const Piece*> by_name;
  for (const Piece& p : a.pieces) by_name[p.name] = &p;
  std::set<std::string> placed;
  for (const YAML::Node& sheet : root["sheets"]) {
    std::vector<Box2d> boxes;
    double y = margin, used = 0;
    for (const YAML::Node& row : sheet) {
      double x = margin, row_height = 0;
      for (const YAML::Node& entry : row) {
        std::string name = entry.as<std::string>();
        const bool turned = name.size() > 3 && name.substr(name.size() - 3) == "@90";
        if (turned) name.resize(name.size() - 3);
        const auto it = by_name.find(name);
        if (it == by_name.end() || !placed.insert(name).second) {
          out.error = "unknown or repeated piece " + name;
          return out;
        }
        Vec2 size = bounds(it->second->cut).size();
        if (turned) size = Vec2(size.y(), size.x());
        Box2d box;
        box.extend(Vec2(x, y));
        box.extend(Vec2(x, y) + size);
        if (box.max.x() > width - margin + 1e-9 || box.max.y() > height - margin + 1e-9) {
          out.error = name + " runs off its sheet";
          return out;
        }
        for (const Box2d& other : boxes) {
          if (box.min.x() < other.max.x() && other.min.x() < box.max.x() &&
              box.min.y() < other.max.y() && other.min.y() < box.max.y()) {
            out.error = name + " overlaps another piece";
            return out;
          }
        }
        boxes.push_back(box);
        used += area(it->second->cut);
        x = box.max.x() + spacing;
        row_height = std::max(row_height, size.y());
      }
      y += row_height + spacing;
    }
    ++out.sheets;
    out.per_sheet.push_back(used / (width * height));
  }
  if (placed.size() != a.pieces.size()) {
    out.error = "the layout leaves pieces out";
    return out;
  }
  double total = 0;
  for (double u : out.per_sheet) total += u;
  out.utilisation = total / out.sheets;
  return out;
}

// Issue 12: nesting the bunk bed onto 600 × 400 mm sheets under 10 s, with sheet count and
// utilisation, compared with a hand layout.
void BM_NestBunkBed(benchmark::State& state) {
  Diagnostics d;
  const Design design =
      load_design(std::string(FABKIT_SOURCE_DIR) + "/examples/flatpack/bunk_bed.yaml", d);
  const Analysis a = check(design);
  if (d.has_errors() || a.diagnostics.has_errors()) {
    state.SkipWithError("the bunk bed does not check");
    return;
  }
  std::vector<Polygon2d> pieces;
  double total = 0;
  for (const Piece& p : a.pieces) {
    pieces.push_back(p.cut[0]);
    total += p.cut[0].area();
  }
  NestingResult r;
  for (auto _ : state) r = nest(pieces, {}, design.sheet);
  if (!r.unplaced.empty()) {
    state.SkipWithError("the nester left pieces out");
    return;
  }
  state.counters["pieces"] = static_cast<double>(pieces.size());
  state.counters["sheets"] = r.sheet_count;
  state.counters["utilisation_pct"] = 100 * r.utilisation;
  state.counters["last_sheet_pct"] = 100 * r.sheet_utilisation.back();
  state.counters["area_bound_sheets"] = std::ceil(total / (600.0 * 400.0));
  const HandLayout hand =
      hand_layout(a, std::string(FABKIT_SOURCE_DIR) + "/bench/data/bunk_bed_hand_layout.yaml");
  if (!hand.error.empty()) {
    state.SkipWithError(("hand layout: " + hand.error).c_str());
    return;
  }
  state.counters["hand_sheets"] = hand.sheets;
  state.counters["hand_utilisation_pct"] = 100 * hand.utilisation;
  state.counters["hand_last_sheet_pct"] = 100 * hand.per_sheet.back();
}
BENCHMARK(BM_NestBunkBed)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

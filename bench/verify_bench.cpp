// Cost of verifying the cycle-closing connect of bundled examples (issue target: < 10 ms).
// Each iteration copies the assembly as it stood just before that connect and runs it:
// pair/closedness/dimension checks, the polygon quick reject and the closure search.
#include <benchmark/benchmark.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "fabkit/hacks/design_file.h"

namespace {

using namespace fabkit::hacks;

struct Prepared {
  Design before;  // the design without its last cycle-closing connect
  PrimitiveRef a, b;
  ConnectOptions options;
};

Prepared prepare(const std::string& example) {
  const std::string path = std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + example + ".yaml";
  const PartsLibrary& lib = PartsLibrary::builtin();
  const Design full = load_design(path, lib);
  int last_cycle = -1;
  int connect_index = -1;
  for (const DesignStep& s : full.steps) {
    if (s.kind != DesignStep::Kind::kConnect) continue;
    ++connect_index;
    if (s.report.closes_cycle) last_cycle = connect_index;
  }
  if (!full.feasible() || last_cycle < 0) {
    std::fprintf(stderr,
                 "%s: not a feasible design with a cycle\n%s",
                 path.c_str(),
                 full.diagnostics.format().c_str());
    std::exit(1);
  }
  YAML::Node root = YAML::LoadFile(path);
  YAML::Node entry = YAML::Clone(root["connections"][static_cast<std::size_t>(last_cycle)]);
  YAML::Node kept(YAML::NodeType::Sequence);
  for (std::size_t i = 0; i < root["connections"].size(); ++i) {
    if (static_cast<int>(i) != last_cycle) kept.push_back(root["connections"][i]);
  }
  root["connections"] = kept;
  YAML::Emitter out;
  out << root;
  Prepared p{load_design_text(out.c_str(), path, lib), {}, {}, {}};
  auto ref = [&](const std::string& text) {
    const auto dot = text.find('.');
    return PrimitiveRef(p.before.parts.at(text.substr(0, dot)), text.substr(dot + 1));
  };
  p.a = ref(entry["connect"][0].as<std::string>());
  p.b = ref(entry["connect"][1].as<std::string>());
  if (entry["alignment"] && entry["alignment"].as<std::string>() == "flip") {
    p.options.alignment = AlignmentChoice::kFlip;
  }
  if (entry["fixed"]) p.options.fixed = entry["fixed"].as<bool>();
  return p;
}

void verify_cycle_connect(benchmark::State& state, const std::string& example) {
  const Prepared p = prepare(example);
  int starts = 0;
  for (auto _ : state) {
    Assembly assembly = p.before.assembly;
    ConnectReport r = assembly.connect(p.a, p.b, p.options);
    if (!r.accepted) {
      state.SkipWithError("the connect was rejected");
      break;
    }
    starts = r.starts_used;
    benchmark::DoNotOptimize(r);
  }
  state.counters["starts"] = starts;
}

BENCHMARK_CAPTURE(verify_cycle_connect, basket_between_rods, std::string("basket_between_rods"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(verify_cycle_connect, bird_feeder, std::string("bird_feeder"))
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(verify_cycle_connect, toothbrush_holder, std::string("toothbrush_holder"))
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();

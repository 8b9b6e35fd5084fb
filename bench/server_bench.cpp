// Round trips through the editor's HTTP API over loopback (issue 5 targets: a connect check
// under 100 ms, solving each gallery design under 500 ms).
#include <benchmark/benchmark.h>
#include <httplib.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include "fabkit/server/editor_server.h"

namespace {

std::string read(const std::string& example) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + example + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Running {
  std::unique_ptr<fabkit::server::EditorServer> server;
  std::thread thread;
  int port = 0;
  Running() {
    fabkit::server::ServerOptions o;
    o.port = 0;
    server = std::make_unique<fabkit::server::EditorServer>(o);
    server->bind();
    port = server->port();
    thread = std::thread([this] { server->listen(); });
  }
  ~Running() {
    server->stop();
    thread.join();
  }
};

Running& running() {
  static Running r;
  return r;
}

void api(benchmark::State& state, const std::string& path, const std::string& example) {
  const std::string body = read(example);
  httplib::Client client("127.0.0.1", running().port);
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);
  for (auto _ : state) {
    const auto r = client.Post(path.c_str(), body, "application/x-yaml");
    if (!r || r->status != 200) {
      state.SkipWithError("request failed");
      break;
    }
    benchmark::DoNotOptimize(r->body);
  }
}

#define FABKIT_API_BENCH(path, name) \
  BENCHMARK_CAPTURE(api, name, std::string(path), std::string(#name))->Unit(benchmark::kMillisecond)

// A connect check: the whole Fig. 8 design (the cycle-closing connect included) checked.
BENCHMARK_CAPTURE(api,
                  check_basket_between_rods,
                  std::string("/api/check"),
                  std::string("basket_between_rods"))
    ->Unit(benchmark::kMillisecond);
FABKIT_API_BENCH("/api/solve", toothbrush_holder);
FABKIT_API_BENCH("/api/solve", charger_holder);
FABKIT_API_BENCH("/api/solve", soap_bottle_holder);
FABKIT_API_BENCH("/api/solve", soap_bottle_one_eyehook);
FABKIT_API_BENCH("/api/solve", mug_hanger);
FABKIT_API_BENCH("/api/solve", paper_towel_holder);
FABKIT_API_BENCH("/api/solve", diaper_caddy);
FABKIT_API_BENCH("/api/solve", basket_between_rods);
FABKIT_API_BENCH("/api/solve", bird_feeder);
FABKIT_API_BENCH("/api/solve", demo);
FABKIT_API_BENCH("/api/solve", clip_light_xs);
FABKIT_API_BENCH("/api/solve", clip_light_s);
FABKIT_API_BENCH("/api/solve", clip_light_m);
FABKIT_API_BENCH("/api/solve", clip_light_l);
FABKIT_API_BENCH("/api/solve", reading_nook);

}  // namespace

BENCHMARK_MAIN();

// The Rods workspace's live path through the server (issue 15): POST /api/rods/preview of the
// 52-rod model over loopback, answer read whole (target: the round trip of one edit under
// 50 ms, of which the library under 16 ms — the library alone is in rods_bench.cpp).
#include <benchmark/benchmark.h>
#include <httplib.h>

#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include "fabkit/server/editor_server.h"

namespace {

std::string read_rods(const std::string& example) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/rods/" + example + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

struct Running {
  std::unique_ptr<fabkit::server::EditorServer> server;
  std::thread thread;
  Running() {
    fabkit::server::ServerOptions o;
    o.port = 0;
    server = std::make_unique<fabkit::server::EditorServer>(o);
    server->bind();
    thread = std::thread([this] { server->listen(); });
  }
  ~Running() {
    server->stop();
    thread.join();
  }
};

void preview(benchmark::State& state, const std::string& example, const char* accept_encoding) {
  static Running running;
  const std::string body = read_rods(example);
  httplib::Client client("127.0.0.1", running.server->port());
  client.set_keep_alive(true);
  client.set_tcp_nodelay(true);
  const httplib::Headers headers = {{"Accept-Encoding", accept_encoding}};
  std::size_t bytes = 0;
  for (auto _ : state) {
    const auto r = client.Post("/api/rods/preview", headers, body, "application/x-yaml");
    if (!r || r->status != 200) {
      state.SkipWithError("request failed");
      break;
    }
    bytes = r->body.size();
    benchmark::DoNotOptimize(r->body);
  }
  state.counters["answer_kB"] = static_cast<double>(bytes) / 1024;
}

}  // namespace

// as a browser asks (it accepts brotli; the preview is sent uncompressed anyway)
BENCHMARK_CAPTURE(preview, wolf_head_52, "wolf_head_52", "gzip, deflate, br")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(preview, coffee_table, "coffee_table", "gzip, deflate, br")
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

BENCHMARK_MAIN();

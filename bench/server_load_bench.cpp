// The editor's light requests while the server is loaded with solves (issue 10 target: GET
// /api/parts under 50 ms at the 95th percentile while 60 reading-nook solves run). Each run
// posts 60 solves at once from 60 clients, and GETs /api/parts every 20 ms from another client
// until every solve has been answered; the counters are the GET latencies' percentiles (ms),
// how many solves were answered 200 / 503 (busy or deadline), and the solves' wall time (s).
//   build/bin/fabkit_bench_server_load
#include <benchmark/benchmark.h>
#include <httplib.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <future>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "fabkit/server/editor_server.h"

namespace {

using Clock = std::chrono::steady_clock;

std::string read(const std::string& example) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + example + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t k = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
  return v[std::min(k, v.size() - 1)];
}

// state.range(0): solves posted at once; state.range(1): job workers (0: the server's default).
void get_parts_under_solve_load(benchmark::State& state) {
  const int solves = static_cast<int>(state.range(0));
  fabkit::server::ServerOptions o;
  o.port = 0;
  o.job_workers = static_cast<int>(state.range(1));
  o.queue_timeout_s = 600;  // every solve is answered, none refused for waiting
  fabkit::server::EditorServer server(o);
  if (!server.bind()) {
    state.SkipWithError(server.error().c_str());
    return;
  }
  std::thread listening([&] { server.listen(); });
  const int port = server.port();
  const std::string design = read("reading_nook");

  for (auto _ : state) {
    std::atomic<int> left{solves}, ok{0}, busy{0};
    std::vector<std::future<void>> clients;
    const auto started = Clock::now();
    for (int i = 0; i < solves; ++i) {
      clients.push_back(std::async(std::launch::async, [&] {
        httplib::Client c("127.0.0.1", port);
        c.set_read_timeout(900, 0);
        const auto r = c.Post("/api/solve", design, "application/x-yaml");
        if (r && r->status == 200) ++ok;
        if (r && r->status == 503) ++busy;
        if (!r || (r->status != 200 && r->status != 503)) {
          std::fprintf(stderr,
                       "solve after %.1f s: %d %s\n",
                       std::chrono::duration<double>(Clock::now() - started).count(),
                       r ? r->status : -1,
                       r ? r->body.substr(0, 200).c_str() : httplib::to_string(r.error()).c_str());
        }
        --left;
      }));
    }
    std::vector<double> ms;
    httplib::Client c("127.0.0.1", port);
    c.set_keep_alive(true);
    c.set_tcp_nodelay(true);
    while (left > 0) {
      const auto t = Clock::now();
      const auto r = c.Get("/api/parts");
      if (!r || r->status != 200) {
        state.SkipWithError("GET /api/parts failed under load");
        break;
      }
      benchmark::DoNotOptimize(r->body);
      ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t).count());
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    for (auto& f : clients) f.get();
    const double wall = std::chrono::duration<double>(Clock::now() - started).count();
    state.SetIterationTime(percentile(ms, 0.95) / 1000);
    state.counters["get_p50_ms"] = percentile(ms, 0.50);
    state.counters["get_p95_ms"] = percentile(ms, 0.95);
    state.counters["get_p99_ms"] = percentile(ms, 0.99);
    state.counters["get_max_ms"] = percentile(ms, 1.0);
    state.counters["gets"] = static_cast<double>(ms.size());
    state.counters["solves_ok"] = ok.load();
    state.counters["solves_503"] = busy.load();
    state.counters["solves_wall_s"] = wall;
  }
  server.stop();
  listening.join();
}

// The same GET with no load, for comparison.
void get_parts_idle(benchmark::State& state) {
  fabkit::server::ServerOptions o;
  o.port = 0;
  fabkit::server::EditorServer server(o);
  server.bind();
  std::thread listening([&] { server.listen(); });
  httplib::Client c("127.0.0.1", server.port());
  c.set_keep_alive(true);
  c.set_tcp_nodelay(true);
  for (auto _ : state) {
    const auto r = c.Get("/api/parts");
    if (!r || r->status != 200) state.SkipWithError("GET /api/parts failed");
    benchmark::DoNotOptimize(r->body);
  }
  server.stop();
  listening.join();
}

}  // namespace

BENCHMARK(get_parts_idle)->Unit(benchmark::kMillisecond);
BENCHMARK(get_parts_under_solve_load)
    ->Args({60, 0})
    ->Args({60, 2})
    ->Iterations(1)
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

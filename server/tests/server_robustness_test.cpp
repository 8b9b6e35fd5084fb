// The server against hostile and careless clients, over loopback with raw sockets and bounded
// loops: requests addressed to other names (DNS rebinding) and cross-site posts, chunked and
// compressed bodies past the cap, slow clients, more connections than allowed, many
// concurrent solves with a deadline, designs that name files, and answers that would reveal
// where files are on this machine.
// clang-format off
#include "kit_api.h"  // before httplib (see there); for without_machine_paths
// clang-format on

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace fabkit::server {
namespace {

using Clock = std::chrono::steady_clock;
using namespace std::chrono_literals;

std::string read_hacks_example(const std::string& name) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + name + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// A TCP connection to the server that sends exactly the bytes a test writes.
class RawClient {
 public:
  explicit RawClient(int port) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof(a)) == 0;
  }
  ~RawClient() { close(); }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  bool connected() const { return connected_; }
  void close() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
  }
  // False once the server has closed or reset the connection (or it would block 2 s).
  bool send(std::string_view bytes) {
    while (!bytes.empty()) {
      pollfd p{fd_, POLLOUT, 0};
      if (::poll(&p, 1, 2000) <= 0 || (p.revents & (POLLERR | POLLHUP))) return false;
      const ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (n <= 0) return false;
      bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
  }
  // Everything the server sends until it closes the connection or `timeout` passes.
  std::string receive(std::chrono::milliseconds timeout = 5000ms) {
    std::string out;
    const auto until = Clock::now() + timeout;
    while (Clock::now() < until) {
      pollfd p{fd_, POLLIN, 0};
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now());
      if (::poll(&p, 1, static_cast<int>(std::max<long long>(1, left.count()))) <= 0) break;
      char buf[8192];
      const ssize_t n = ::recv(fd_, buf, sizeof(buf), 0);
      if (n <= 0) break;
      out.append(buf, static_cast<std::size_t>(n));
      // One whole response with a Content-Length is enough.
      const auto head_end = out.find("\r\n\r\n");
      if (head_end != std::string::npos) {
        const auto cl = out.find("Content-Length: ");
        if (cl != std::string::npos && cl < head_end) {
          const std::size_t len = std::stoul(out.substr(cl + 16));
          if (out.size() >= head_end + 4 + len) break;
        }
      }
    }
    return out;
  }
  // Whether the server has closed this connection (waits up to `timeout`).
  bool closed_by_server(std::chrono::milliseconds timeout) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(timeout.count())) <= 0) return false;
    char c;
    return ::recv(fd_, &c, 1, MSG_PEEK) <= 0 || (p.revents & POLLHUP);
  }

 private:
  int fd_ = -1;
  bool connected_ = false;
};

// One chunk of a chunked body.
std::string fmt_chunk(const std::string& data) {
  char size[32];
  std::snprintf(size, sizeof(size), "%zx\r\n", data.size());
  return size + data + "\r\n";
}

int status_of(const std::string& response) {
  if (response.rfind("HTTP/1.", 0) != 0 || response.size() < 12) return -1;
  return std::stoi(response.substr(9, 3));
}

std::string body_of(const std::string& response) {
  const auto at = response.find("\r\n\r\n");
  return at == std::string::npos ? "" : response.substr(at + 4);
}

class Robustness : public ::testing::Test {
 protected:
  void TearDown() override { shutdown(); }

  void start(ServerOptions o) {
    o.host = "127.0.0.1";
    o.port = 0;
    server_ = std::make_unique<EditorServer>(o);
    ASSERT_TRUE(server_->bind()) << server_->error();
    port_ = server_->port();
    thread_ = std::thread([this] { server_->listen(); });
    httplib::Client c("127.0.0.1", port_);
    for (int i = 0; i < 100 && !c.Get("/api/kits"); ++i) std::this_thread::sleep_for(20ms);
  }
  void shutdown() {
    if (server_) server_->stop();
    if (thread_.joinable()) thread_.join();
    server_.reset();
  }
  std::string host() const { return "127.0.0.1:" + std::to_string(port_); }
  // One raw request on a fresh connection; the whole response.
  std::string exchange(const std::string& request) {
    RawClient c(port_);
    EXPECT_TRUE(c.connected());
    c.send(request);
    return c.receive();
  }
  std::string post(const std::string& path,
                   const std::string& body,
                   const std::string& extra_headers,
                   const std::string& type = "application/x-yaml") {
    return exchange("POST " + path + " HTTP/1.1\r\nHost: " + host() + "\r\nContent-Type: " + type +
                    "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n" + extra_headers +
                    "\r\n" + body);
  }
  void expect_alive() {
    httplib::Client c("127.0.0.1", port_);
    const auto r = c.Get("/api/parts/DoubleHook/mesh");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }

  std::unique_ptr<EditorServer> server_;
  std::thread thread_;
  int port_ = 0;
};

TEST_F(Robustness, AnswersOnlyRequestsAddressedToIt) {
  start({});
  const std::string get = "GET /api/kits HTTP/1.1\r\nHost: ";
  EXPECT_EQ(status_of(exchange(get + host() + "\r\n\r\n")), 200);
  EXPECT_EQ(status_of(exchange(get + "localhost:" + std::to_string(port_) + "\r\n\r\n")), 200);
  EXPECT_EQ(status_of(exchange(get + "[::1]:" + std::to_string(port_) + "\r\n\r\n")), 200);
  // DNS rebinding: the attacker's name resolves to 127.0.0.1, the browser sends that name.
  const std::string rebound = exchange(get + "evil.example:" + std::to_string(port_) + "\r\n\r\n");
  EXPECT_EQ(status_of(rebound), 403);
  EXPECT_NE(body_of(rebound).find("not to this server"), std::string::npos) << rebound;
  EXPECT_TRUE(nlohmann::json::accept(body_of(rebound)));
  EXPECT_EQ(status_of(exchange(get + "127.0.0.1:1\r\n\r\n")), 403);       // another port
  EXPECT_EQ(status_of(exchange(get + "127.0.0.1\r\n\r\n")), 403);         // port 80 implied
  EXPECT_EQ(status_of(exchange("GET /api/kits HTTP/1.0\r\n\r\n")), 403);  // no Host at all
  EXPECT_EQ(status_of(exchange(get + "127.0.0.1:" + std::to_string(port_) + "@evil\r\n\r\n")), 403);
  // Static files and the design are guarded alike.
  EXPECT_EQ(status_of(exchange("GET /api/design HTTP/1.1\r\nHost: evil.example\r\n\r\n")), 403);
  EXPECT_EQ(status_of(exchange("GET / HTTP/1.1\r\nHost: evil.example\r\n\r\n")), 403);
  expect_alive();
}

TEST_F(Robustness, ExtraNamesAreAnsweredWhenAllowed) {
  ServerOptions o;
  o.allowed_hosts = {"workshop.lan"};
  start(o);
  EXPECT_EQ(status_of(exchange("GET /api/kits HTTP/1.1\r\nHost: workshop.lan:" +
                               std::to_string(port_) + "\r\n\r\n")),
            200);
  EXPECT_EQ(status_of(exchange(
                "GET /api/kits HTTP/1.1\r\nHost: other.lan:" + std::to_string(port_) + "\r\n\r\n")),
            403);
}

TEST_F(Robustness, CrossSitePostsAreRefusedBeforeAnyWork) {
  start({});
  const std::string design = read_hacks_example("bird_feeder");
  // "Simple" requests a page on any site may send without asking: refused by type.
  for (const char* type : {"text/plain",
                           "text/plain;charset=UTF-8",
                           "application/x-www-form-urlencoded",
                           "multipart/form-data; boundary=x"}) {
    const std::string r = post("/api/solve", design, "", type);
    EXPECT_EQ(status_of(r), 415) << type;
    EXPECT_NE(body_of(r).find("YAML"), std::string::npos) << r;
  }
  EXPECT_EQ(status_of(exchange("POST /api/check HTTP/1.1\r\nHost: " + host() +
                               "\r\nContent-Length: 2\r\n\r\n{}")),
            415);  // no type at all
  // A page elsewhere: its Origin gives it away.
  EXPECT_EQ(status_of(post("/api/check", design, "Origin: http://evil.example\r\n")), 403);
  EXPECT_EQ(status_of(post("/api/check", design, "Origin: null\r\n")), 403);
  EXPECT_EQ(status_of(post("/api/check", design, "Origin: https://" + host() + "\r\n")), 403);
  // The editor itself, from its own page or from a script without a page.
  EXPECT_EQ(status_of(post("/api/check", design, "Origin: http://" + host() + "\r\n")), 200);
  EXPECT_EQ(status_of(post("/api/check", design, "")), 200);
  EXPECT_EQ(status_of(post("/api/check", design, "", "application/json")), 200);  // JSON is YAML
  expect_alive();
}

TEST_F(Robustness, ChunkedBodiesPastTheCapAreRefused) {
  ServerOptions o;
  o.max_body_bytes = 256 << 10;
  start(o);
  // A chunked upload twice the cap: 413, and the server still answers.
  {
    RawClient c(port_);
    ASSERT_TRUE(c.connected());
    c.send("POST /api/check HTTP/1.1\r\nHost: " + host() +
           "\r\nContent-Type: application/x-yaml\r\nTransfer-Encoding: chunked\r\n\r\n");
    const std::string chunk(16 << 10, '#');
    for (int i = 0; i < 32 && c.send(fmt_chunk(chunk)); ++i) {
    }
    c.send("0\r\n\r\n");
    const std::string r = c.receive();
    EXPECT_EQ(status_of(r), 413) << r.substr(0, 300);
  }
  // An endless chunked upload: the server stops reading long before 256 MiB arrive.
  {
    RawClient c(port_);
    c.send("POST /api/solve HTTP/1.1\r\nHost: " + host() +
           "\r\nContent-Type: application/x-yaml\r\nTransfer-Encoding: chunked\r\n\r\n");
    const std::string chunk = fmt_chunk(std::string(64 << 10, 'x'));
    std::size_t sent = 0;
    while (sent < (std::size_t{256} << 20) && c.send(chunk)) sent += chunk.size();
    EXPECT_LT(sent, std::size_t{256} << 20) << "the server read the whole body";
  }
  // Compressed bodies (a small gzip can expand to gigabytes) are not read at all.
  EXPECT_EQ(status_of(post("/api/check", "\x1f\x8b", "Content-Encoding: gzip\r\n")), 415);
  // Content-Length past the cap, or not a number, or both length and chunks: refused unread.
  EXPECT_EQ(status_of(exchange("POST /api/check HTTP/1.1\r\nHost: " + host() +
                               "\r\nContent-Type: application/x-yaml\r\nContent-Length: "
                               "99999999999\r\n\r\nenvironment:")),
            413);
  EXPECT_EQ(
      status_of(exchange("POST /api/check HTTP/1.1\r\nHost: " + host() +
                         "\r\nContent-Type: application/x-yaml\r\nContent-Length: -1\r\n\r\n")),
      400);
  EXPECT_EQ(status_of(exchange("POST /api/check HTTP/1.1\r\nHost: " + host() +
                               "\r\nContent-Type: application/x-yaml\r\nContent-Length: 5\r\n"
                               "Transfer-Encoding: chunked\r\n\r\n0\r\n\r\n")),
            400);
  // A body without a length (read until the client closes): refused.
  EXPECT_EQ(status_of(exchange("POST /api/check HTTP/1.1\r\nHost: " + host() +
                               "\r\nContent-Type: application/x-yaml\r\n\r\nparts: []")),
            411);
  expect_alive();
}

TEST_F(Robustness, EndlessHeadersAreCut) {
  start({});
  RawClient c(port_);
  c.send("GET /api/kits HTTP/1.1\r\nHost: " + host() + "\r\n");
  const std::string header = "X-Padding: " + std::string(1000, 'p') + "\r\n";
  std::size_t sent = 0;
  while (sent < (std::size_t{64} << 20) && c.send(header)) sent += header.size();
  EXPECT_LT(sent, std::size_t{64} << 20) << "the server kept reading headers";
  // A request line without an end, likewise.
  RawClient d(port_);
  d.send("GET /");
  const std::string path(4096, 'a');
  sent = 0;
  while (sent < (std::size_t{64} << 20) && d.send(path)) sent += path.size();
  EXPECT_LT(sent, std::size_t{64} << 20) << "the server kept reading the request line";
  expect_alive();
}

TEST_F(Robustness, SlowClientsCannotStarveOthers) {
  ServerOptions o;
  o.read_timeout_s = 1;
  o.max_open_connections = 32;
  start(o);
  // More trickling clients than httplib's 8 default threads: one byte every 100 ms.
  std::vector<std::unique_ptr<RawClient>> slow;
  for (int i = 0; i < 16; ++i) slow.push_back(std::make_unique<RawClient>(port_));
  const std::string request = "GET /api/parts HTTP/1.1\r\nHost: " + host() + "\r\n\r\n";
  const auto started = Clock::now();
  std::atomic<bool> done{false};
  std::thread trickle([&] {
    for (std::size_t k = 0; k < request.size() - 2 && !done; ++k) {
      for (auto& c : slow) c->send(request.substr(k, 1));
      std::this_thread::sleep_for(100ms);
    }
  });
  std::this_thread::sleep_for(200ms);
  // Someone else is served meanwhile.
  const auto asked = Clock::now();
  httplib::Client c("127.0.0.1", port_);
  const auto r = c.Get("/api/parts");
  const double waited = ms_since(asked);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_LT(waited, 1000) << "a normal request waited behind slow clients";
  // The slow ones are cut off once their request has taken longer than the read timeout.
  int closed = 0;
  for (auto& s : slow) closed += s->closed_by_server(3000ms) ? 1 : 0;
  done = true;
  trickle.join();
  EXPECT_EQ(closed, 16);
  EXPECT_LT(ms_since(started), 6000);
  expect_alive();
}

TEST_F(Robustness, ConnectionsPastTheLimitAreRefusedAtOnce) {
  ServerOptions o;
  o.max_open_connections = 4;
  o.keep_alive_s = 5;
  start(o);
  std::vector<std::unique_ptr<RawClient>> idle;
  for (int i = 0; i < 4; ++i) {
    idle.push_back(std::make_unique<RawClient>(port_));
    // One answered request each, then the connection stays open (keep-alive).
    idle.back()->send("GET /api/kits HTTP/1.1\r\nHost: " + host() + "\r\n\r\n");
    EXPECT_EQ(status_of(idle.back()->receive()), 200);
  }
  const auto asked = Clock::now();
  const std::string refused = exchange("GET /api/kits HTTP/1.1\r\nHost: " + host() + "\r\n\r\n");
  EXPECT_EQ(status_of(refused), 503) << refused;
  EXPECT_NE(body_of(refused).find("connections open"), std::string::npos) << refused;
  EXPECT_LT(ms_since(asked), 1000);
  idle.clear();
  // Room again once they are gone.
  bool served = false;
  for (int i = 0; i < 50 && !served; ++i) {
    served = status_of(exchange("GET /api/kits HTTP/1.1\r\nHost: " + host() + "\r\n\r\n")) == 200;
    if (!served) std::this_thread::sleep_for(20ms);
  }
  EXPECT_TRUE(served);
}

TEST_F(Robustness, ABurstOfClientsIsServedWithoutRetries) {
  start({});
  // 80 clients connecting at once: httplib's listen backlog of 5 dropped most of them (the
  // kernel retries a dropped connection after a second, and httplib's client gave up reading).
  std::vector<std::future<int>> clients;
  for (int i = 0; i < 80; ++i) {
    clients.push_back(std::async(std::launch::async, [&] {
      httplib::Client c("127.0.0.1", port_);
      const auto r = c.Get("/api/kits");
      return r ? r->status : -1;
    }));
  }
  int ok = 0;
  for (auto& f : clients) ok += f.get() == 200 ? 1 : 0;
  EXPECT_EQ(ok, 80);
}

TEST_F(Robustness, ConcurrentSolvesMeetTheirDeadlineAndLeaveGetsFast) {
  ServerOptions o;
  o.solve_timeout_s = 0.5;
  o.job_workers = 1;
  o.max_queued_jobs = 6;
  start(o);
  const std::string design = read_hacks_example("reading_nook");
  constexpr int kSolves = 10;
  std::vector<std::future<std::pair<int, double>>> solves;
  const auto started = Clock::now();
  for (int i = 0; i < kSolves; ++i) {
    solves.push_back(std::async(std::launch::async, [&] {
      httplib::Client c("127.0.0.1", port_);
      c.set_read_timeout(60, 0);
      const auto t = Clock::now();
      const auto r = c.Post("/api/solve", design, "application/x-yaml");
      return std::make_pair(r ? r->status : -1, ms_since(t));
    }));
  }
  std::this_thread::sleep_for(100ms);
  double slowest_get = 0;
  httplib::Client c("127.0.0.1", port_);
  for (int i = 0; i < 10; ++i) {
    const auto t = Clock::now();
    const auto r = c.Get("/api/parts");
    slowest_get = std::max(slowest_get, ms_since(t));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }
  int busy = 0, answered = 0;
  for (auto& f : solves) {
    const auto [status, ms] = f.get();
    EXPECT_TRUE(status == 200 || status == 503) << status;
    busy += status == 503 ? 1 : 0;
    answered += status > 0 ? 1 : 0;
  }
  EXPECT_EQ(answered, kSolves);
  EXPECT_GE(busy, kSolves - 6) << "the queue holds 6; the rest are told the server is busy";
  // One worker, 6 jobs of at most 0.5 s each (+10 % and start-up): everything answered by then.
  EXPECT_LT(ms_since(started), 6 * 0.55 * 1000 + 3000);
  EXPECT_LT(slowest_get, 500) << "GET waited behind solves";
  expect_alive();
}

TEST_F(Robustness, DesignsThatNameFilesAreRefusedAndRevealNothing) {
  // A part file of the user's, loaded at start from an absolute path: usable, never shown.
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / "fabkit_robustness_private_dir";
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(std::string(FABKIT_SOURCE_DIR) + "/examples/parts/wall_bracket.yaml",
                             dir / "wall_bracket.yaml",
                             std::filesystem::copy_options::overwrite_existing);
  std::filesystem::copy_file(std::string(FABKIT_SOURCE_DIR) + "/examples/parts/wall_bracket.obj",
                             dir / "wall_bracket.obj",
                             std::filesystem::copy_options::overwrite_existing);
  ServerOptions o;
  o.hacks_part_files = {std::filesystem::absolute(dir / "wall_bracket.yaml")};
  start(o);
  const std::string secret_dir = dir.string();
  std::vector<std::string> answers;
  for (const char* files : {"[/etc/passwd]",
                            "[/etc/shadow]",
                            "['../../../../etc/passwd']",
                            "[/dev/zero]",
                            "[/proc/self/environ]",
                            "[wall_bracket.yaml]"}) {
    const std::string r = post(
        "/api/check",
        std::string("part_files: ") + files + "\nenvironment:\n  - {name: w, part: WallBracket}\n",
        "");
    EXPECT_EQ(status_of(r), 400) << files;
    EXPECT_NE(r.find("may not name files"), std::string::npos) << r;
    answers.push_back(r);
  }
  // A design naming parts by path, and the part from the private directory used wrongly.
  answers.push_back(post("/api/check", "environment:\n  - {name: e, part: /etc/passwd}\n", ""));
  answers.push_back(post("/api/check",
                         "environment:\n  - {name: w, part: WallBracket}\nparts:\n  - {name: h, "
                         "part: DoubleHook}\nconnections:\n  - connect: [h.hook1, w.nothing]\n",
                         ""));
  answers.push_back(exchange("GET /api/parts HTTP/1.1\r\nHost: " + host() + "\r\n\r\n"));
  answers.push_back(
      exchange("GET /api/parts/WallBracket/mesh HTTP/1.1\r\nHost: " + host() + "\r\n\r\n"));
  for (const std::string& a : answers) {
    EXPECT_EQ(a.find("root:"), std::string::npos);
    EXPECT_EQ(a.find(secret_dir), std::string::npos) << a.substr(0, 400);
    EXPECT_EQ(a.find("/etc/"), std::string::npos) << a.substr(0, 400);
    EXPECT_EQ(a.find(std::filesystem::current_path().string() + "/"), std::string::npos);
  }
  EXPECT_NE(answers[answers.size() - 3].find("(WallBracket) has no primitive 'nothing'"),
            std::string::npos)
      << answers[answers.size() - 3].substr(0, 400);
  std::filesystem::remove_all(dir);
  expect_alive();
}

TEST(MachinePaths, AreCutFromMessages) {
  EXPECT_EQ(without_machine_paths("cannot read part file '/home/me/parts/rack.yaml': no such file"),
            "cannot read part file 'rack.yaml': no such file");
  EXPECT_EQ(without_machine_paths("/etc/passwd"), "passwd");
  EXPECT_EQ(without_machine_paths("see http://127.0.0.1:8080/api/parts"),
            "see http://127.0.0.1:8080/api/parts");
  EXPECT_EQ(without_machine_paths("rods.rod1 / 2 mm, 3/4 turn"), "rods.rod1 / 2 mm, 3/4 turn");
  EXPECT_EQ(without_machine_paths("{\"file\":\"/tmp/x/design.yaml\"}"),
            "{\"file\":\"design.yaml\"}");
}

}  // namespace
}  // namespace fabkit::server

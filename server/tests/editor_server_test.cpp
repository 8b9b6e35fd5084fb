// The editor's HTTP API, end to end over loopback: answers, diagnostics, and that the server
// stays up and correct after malformed, oversized and hostile requests.
#include "fabkit/server/editor_server.h"

#include <gtest/gtest.h>
#include <httplib.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

namespace fabkit::server {
namespace {

using nlohmann::json;

std::string read_example(const std::string& name) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + name + ".yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class ServerTest : public ::testing::Test {
 protected:
  void SetUp() override { start({}); }
  void TearDown() override { shutdown(); }

  void start(ServerOptions o) {
    root_ = std::filesystem::temp_directory_path() / "fabkit_server_test_root";
    std::filesystem::create_directories(root_);
    std::ofstream(root_ / "index.html") << "<html>editor</html>";
    // A secret next to (not under) the web root: it must never be served.
    std::ofstream(root_.parent_path() / "fabkit_server_secret.txt") << "TOP-SECRET-CONTENT-42";
    o.host = "127.0.0.1";
    o.port = 0;
    o.web_root = root_;
    if (o.initial_design.empty()) o.initial_design = read_example("demo");
    server_ = std::make_unique<EditorServer>(o);
    ASSERT_TRUE(server_->bind()) << server_->error();
    thread_ = std::thread([this] { server_->listen(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
    // Wait until it answers.
    for (int i = 0; i < 100 && !client_->Get("/api/design"); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }

  void shutdown() {
    if (server_) server_->stop();
    if (thread_.joinable()) thread_.join();
    server_.reset();
  }

  httplib::Result post(const std::string& path, const std::string& body) {
    return client_->Post(path.c_str(), body, "application/x-yaml");
  }

  // The server still answers correctly.
  void expect_alive() {
    const auto r = client_->Get("/api/parts/DoubleHook/mesh");
    ASSERT_TRUE(r);
    EXPECT_EQ(r->status, 200);
  }

  std::filesystem::path root_;
  std::unique_ptr<EditorServer> server_;
  std::thread thread_;
  std::unique_ptr<httplib::Client> client_;
};

TEST_F(ServerTest, PartsLibrary) {
  const auto r = client_->Get("/api/parts");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json parts = json::parse(r->body);
  ASSERT_GE(parts.size(), 50u);
  bool found = false;
  for (const json& p : parts) {
    if (p["name"] != "DoubleHook") continue;
    found = true;
    ASSERT_EQ(p["primitives"].size(), 2u);
    EXPECT_EQ(p["primitives"][0]["name"], "hook1");
    EXPECT_EQ(p["primitives"][0]["type"], "hook");
    EXPECT_EQ(p["primitives"][0]["shape"]["arc_radius"], 11.6);
    EXPECT_EQ(p["primitives"][0]["connects_to"], json({"rod", "hook", "ring", "tube"}));
  }
  EXPECT_TRUE(found);
}

TEST_F(ServerTest, PartMeshesAndParameters) {
  auto r = client_->Get("/api/parts/DoubleHook/mesh");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  json m = json::parse(r->body);
  EXPECT_GT(m["body"]["vertices"].size(), 9u);
  EXPECT_EQ(m["body"]["faces"].size() % 3, 0u);
  EXPECT_TRUE(m["primitives"].contains("hook1"));
  r = client_->Get("/api/parts/ParamTurnbuckle/mesh?extended_length=25");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  r = client_->Get("/api/parts/ParamTurnbuckle/mesh?extended_length=-4");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("extended_length"), std::string::npos);
  r = client_->Get("/api/parts/ParamTurnbuckle/mesh?extended_length=abc");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  r = client_->Get("/api/parts/NoSuchPart/mesh");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  EXPECT_NE(json::parse(r->body)["error"].get<std::string>().find("unknown part 'NoSuchPart'"),
            std::string::npos);
}

TEST_F(ServerTest, LoosePrimitiveMeshes) {
  auto r = client_->Get("/api/primitives/surface/mesh?width=400&length=400");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  EXPECT_GT(json::parse(r->body)["mesh"]["faces"].size(), 0u);
  r = client_->Get("/api/primitives/rod/mesh?radius=-5&length=100");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("must be positive"), std::string::npos);
  r = client_->Get("/api/primitives/rod/mesh?colour=3");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  r = client_->Get("/api/primitives/spring/mesh");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
}

TEST_F(ServerTest, InitialDesign) {
  const auto r = client_->Get("/api/design");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("curtainring"), std::string::npos);
}

TEST_F(ServerTest, CheckReportsEveryStep) {
  const auto r = post("/api/check", read_example("basket_between_rods"));
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json j = json::parse(r->body);
  EXPECT_TRUE(j["valid"].get<bool>());
  ASSERT_EQ(j["steps"].size(), 6u);
  EXPECT_TRUE(j["steps"][4]["closes_cycle"].get<bool>());
  EXPECT_EQ(j["parts"].size(), 4u);
}

TEST_F(ServerTest, CheckShowsWhyAConnectFails) {
  const std::string design = R"(environment:
  - {name: rods, part: LongTensionRod}
parts:
  - {name: s, part: DoubleHook}
connections:
  - connect: [s.hook1, rods.rod]
)";
  const auto r = post("/api/check", design);
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json j = json::parse(r->body);
  EXPECT_FALSE(j["valid"].get<bool>());
  EXPECT_FALSE(j["steps"][1]["accepted"].get<bool>());
  EXPECT_NE(j["steps"][1]["diagnostics"][0]["message"].get<std::string>().find(
                "hook opening 9.6 mm is smaller than rod radius 12.7 mm"),
            std::string::npos);
  EXPECT_EQ(j["steps"][1]["diagnostics"][0]["line"], 6);
}

TEST_F(ServerTest, SolveReturnsResultJsonAndGlb) {
  auto r = post("/api/solve", read_example("bird_feeder"));
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json j = json::parse(r->body);
  EXPECT_TRUE(j["stable"].get<bool>());
  EXPECT_LT(j["target"]["pos_error_mm"].get<double>(), 5.0);
  r = post("/api/solve?format=glb", read_example("bird_feeder"));
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(r->body.substr(0, 4), "glTF");
}

TEST_F(ServerTest, MalformedAndInfeasibleDesigns) {
  auto r = post("/api/check", "environment:\n  - {name: door, part: [\n");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("YAML syntax error"), std::string::npos);
  r = post("/api/solve", "environment:\n  - {name: e, part: NoSuchPart}\n");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("unknown part 'NoSuchPart'"), std::string::npos);
  r = post("/api/solve", "{\"not\": \"a design\"");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  r = post("/api/solve", std::string("\0\xff\xfe garbage", 12));
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  r = post("/api/solve", R"(environment:
  - {name: rods, part: LongTensionRod}
parts:
  - {name: s, part: DoubleHook}
connections:
  - connect: [s.hook1, rods.rod]
)");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 422);
  expect_alive();
}

// Positions beyond 1 km or not finite are a unit mistake or garbage: refused like absurd
// sizes, naming the part and the quantity, before anything is solved.
TEST_F(ServerTest, AbsurdPositionsAreRefused) {
  for (const auto& [pos, message] :
       {std::pair<std::string, std::string>{"2e6", "rods pos 2e+06 mm is out of range"},
        {".nan", "rods pos is .nan, not a finite number"},
        {"-.inf", "rods pos is -.inf, not a finite number"}}) {
    for (const char* route : {"/api/check", "/api/solve"}) {
      const auto r = post(route,
                          "fabkit: hacks/1\nenvironment:\n  - {name: rods, part: TowelRackRods, "
                          "frame: {pos: [0, " +
                              pos + ", 0], rot: [0, 0, 0]}}\n");
      ASSERT_TRUE(r);
      EXPECT_EQ(r->status, 400) << route << " " << pos;
      EXPECT_NE(r->body.find(message), std::string::npos) << route << ": " << r->body;
    }
  }
  expect_alive();
}

TEST_F(ServerTest, OversizedBodiesAndDesignsAreRefused) {
  const std::string huge(2 << 20, 'x');
  auto r = post("/api/check", huge);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 413);
  std::string many =
      "environment:\n  - {name: e, primitives: {rod: {type: rod, radius: 5, length: "
      "500}}}\nparts:\n";
  for (int i = 0; i < 600; ++i)
    many += "  - {name: p" + std::to_string(i) + ", part: DoubleHook}\n";
  r = post("/api/check", many);
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  EXPECT_NE(r->body.find("the limit here is 500"), std::string::npos);
  expect_alive();
}

// The editor's files are sent as they are, whatever the browser accepts: compressed with
// httplib's brotli, its 920 kB script cost 1.7 s on every page load.
TEST_F(ServerTest, FilesAndAnswersAreSentUncompressed) {
  std::ofstream(root_ / "app.js") << std::string(200000, 'x');
  const httplib::Headers accepts{{"Accept-Encoding", "gzip, deflate, br"}};
  for (const char* path : {"/app.js", "/index.html", "/api/parts"}) {
    const auto r = client_->Get(path, accepts);
    ASSERT_TRUE(r) << path;
    EXPECT_EQ(r->status, 200) << path;
    EXPECT_FALSE(r->has_header("Content-Encoding")) << path;
  }
  EXPECT_EQ(client_->Get("/app.js", accepts)->body.size(), 200000u);
}

TEST_F(ServerTest, NoPathTraversal) {
  auto r = client_->Get("/index.html");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  for (const char* path : {"/../fabkit_server_secret.txt",
                           "/%2e%2e/fabkit_server_secret.txt",
                           "/..%2ffabkit_server_secret.txt",
                           "/%2e%2e%2f%2e%2e%2fetc%2fpasswd",
                           "/../../../../etc/passwd",
                           "/api/parts/..%2f..%2fetc%2fpasswd/mesh"}) {
    r = client_->Get(path);
    if (r) {
      EXPECT_NE(r->status, 200) << path;
      EXPECT_EQ(r->body.find("TOP-SECRET-CONTENT-42"), std::string::npos) << path;
      EXPECT_EQ(r->body.find("root:"), std::string::npos) << path;
    }
  }
  expect_alive();
}

TEST_F(ServerTest, CompatibilityForTwoWayFiltering) {
  const json request = {{"a", {{"part", "DoubleHook"}, {"primitive", "hook1"}}},
                        {"b",
                         {{{"part", "LongTensionRod"}, {"primitive", "rod"}},
                          {{"part", "ClosetRods"}, {"primitive", "rod1"}},
                          {{"part", "SoapBottle"}, {"primitive", "surface"}},
                          {{"part", "NoSuchPart"}, {"primitive", "x"}}}}};
  const auto r = client_->Post("/api/compatible", request.dump(), "application/json");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json j = json::parse(r->body);
  ASSERT_EQ(j.size(), 4u);
  EXPECT_FALSE(j[0]["ok"].get<bool>());
  EXPECT_NE(j[0]["reason"].get<std::string>().find(
                "hook opening 9.6 mm is smaller than rod radius 12.7 mm"),
            std::string::npos);
  EXPECT_TRUE(j[1]["ok"].get<bool>());
  EXPECT_FALSE(j[2]["ok"].get<bool>());
  EXPECT_NE(j[2]["reason"].get<std::string>().find("Table 1"), std::string::npos);
  EXPECT_FALSE(j[3]["ok"].get<bool>());
  const auto bad = client_->Post("/api/compatible", "{not json", "application/json");
  ASSERT_TRUE(bad);
  EXPECT_EQ(bad->status, 400);
  expect_alive();
}

TEST_F(ServerTest, UnknownRoutesAnswerJson) {
  const auto r = client_->Get("/api/nothing");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 404);
  EXPECT_NO_THROW(json::parse(r->body));
}

TEST(ServerTimeout, SlowSolvesStopCleanly) {
  ServerOptions o;
  o.host = "127.0.0.1";
  o.port = 0;
  o.solve_timeout_s = 1e-6;  // nothing finishes in a microsecond
  EditorServer server(o);
  ASSERT_TRUE(server.bind());
  std::thread t([&] { server.listen(); });
  httplib::Client c("127.0.0.1", server.port());
  for (int i = 0; i < 100 && !c.Get("/api/parts/DoubleHook/mesh"); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  auto r = c.Post("/api/solve", read_example("reading_nook"), "application/x-yaml");
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->status == 503 || r->status == 422) << r->status << " " << r->body;
  r = c.Get("/api/parts/DoubleHook/mesh");
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 200);
  server.stop();
  t.join();
}

TEST(ServerBind, BadAddressIsAClearError) {
  ServerOptions o;
  o.host = "256.1.1.1";
  o.port = 0;
  EditorServer server(o);
  EXPECT_FALSE(server.bind());
  EXPECT_NE(server.error().find("cannot listen on 256.1.1.1"), std::string::npos) << server.error();
}

}  // namespace
}  // namespace fabkit::server

// The seam (kit_api.h) protects every kit: a kit that does nothing about security — plain
// handlers, no job queue, paths and exception texts in what it would answer — still gets the
// Host and Content-Type checks, its POSTs on the job queue, its exceptions hidden and machine
// paths cut out of its answers. Kits added later (rods, flatpack, templates) get the same.
// clang-format off
#include "kit_api.h"  // before httplib (see there)
// clang-format on

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace fabkit::server {
namespace {

KitApi careless_kit(const ApiContext&) {
  KitApi kit;
  kit.kit = "careless";
  using M = ApiRoute::Method;
  auto where = [](const httplib::Request&, httplib::Response& res) {
    reply(res,
          200,
          Json{{"on_job_queue", JobQueue::on_worker_thread()},
               {"message", "cannot read '/home/someone/private/parts.yaml'"}});
  };
  kit.routes.push_back({M::kPost, "work", where});
  kit.routes.push_back({M::kPost, "quick", where, ApiRoute::Load::kLight});
  kit.routes.push_back({M::kGet, "look", where});
  kit.routes.push_back({M::kGet, "heavy-look", where, ApiRoute::Load::kHeavy});
  // Not through reply(): plain "application/json", which httplib compresses for a client
  // that accepts it.
  kit.routes.push_back({M::kGet, "plain", [](const httplib::Request&, httplib::Response& res) {
                          Json lines = Json::array();
                          for (int i = 0; i < 200; ++i) {
                            lines.push_back(fmt::format(
                                "line {}: cannot read '/home/someone/private/parts.yaml'", i));
                          }
                          res.set_content(dump_json(Json{{"lines", lines}}), "application/json");
                        }});
  kit.routes.push_back({M::kGet, "boom", [](const httplib::Request&, httplib::Response&) {
                          throw std::runtime_error("cannot open /etc/shadow");
                        }});
  kit.routes.push_back({M::kPost,
                        R"(items/([a-z]{1,8})/echo)",
                        [](const httplib::Request& req, httplib::Response& res) {
                          reply(res, 200, Json{{"item", req.matches[1].str()}, {"body", req.body}});
                        }});
  kit.routes.push_back({M::kPost, "boom", [](const httplib::Request&, httplib::Response&) {
                          throw std::runtime_error("cannot open /etc/shadow");
                        }});
  return kit;
}

class KitSeam : public testing::Test {
 protected:
  static void SetUpTestSuite() { add_kit_for_tests(careless_kit); }
  static void TearDownTestSuite() { clear_kits_for_tests(); }
  KitSeam() {
    ServerOptions o;
    o.host = "127.0.0.1";
    o.port = 8080;  // never bound: the Host requests must carry
    o.job_workers = 1;
    server_ = std::make_unique<EditorServer>(o);
  }
  std::string get(const std::string& path, const std::string& host = "127.0.0.1:8080") {
    return server_->answer_raw("GET " + path + " HTTP/1.1\r\nHost: " + host + "\r\n\r\n");
  }
  std::string post(const std::string& path,
                   const std::string& body,
                   const std::string& type = "application/x-yaml",
                   const std::string& host = "127.0.0.1:8080") {
    return server_->answer_raw(
        "POST " + path + " HTTP/1.1\r\nHost: " + host + "\r\nContent-Type: " + type +
        "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
  }
  std::unique_ptr<EditorServer> server_;
};

bool has(const std::string& answer, const std::string& text) {
  return answer.find(text) != std::string::npos;
}

TEST_F(KitSeam, PostsRunOnTheJobQueueUnlessTheRouteIsLight) {
  const std::string work = post("/api/careless/work", "a: 1\n");
  EXPECT_TRUE(has(work, "HTTP/1.1 200")) << work;
  EXPECT_TRUE(has(work, R"("on_job_queue":true)")) << work;
  EXPECT_TRUE(has(post("/api/careless/quick", "a: 1\n"), R"("on_job_queue":false)"));
  EXPECT_TRUE(has(get("/api/careless/look"), R"("on_job_queue":false)"));
  EXPECT_TRUE(has(get("/api/careless/heavy-look"), R"("on_job_queue":true)"));
  // The job gets the request's body and its path's matches.
  const std::string echo = post("/api/careless/items/abc/echo", "x: [1, 2]\n");
  EXPECT_TRUE(has(echo, R"("item":"abc")")) << echo;
  EXPECT_TRUE(has(echo, R"("body":"x: [1, 2]\n")")) << echo;
}

TEST_F(KitSeam, RequestPolicyAppliesToTheKit) {
  EXPECT_TRUE(has(get("/api/careless/look", "evil.example:8080"), "HTTP/1.1 403"));
  EXPECT_TRUE(has(post("/api/careless/work", "a: 1\n", "text/plain"), "HTTP/1.1 415"));
  EXPECT_TRUE(has(post("/api/careless/work", std::string(2 << 20, 'a')), "HTTP/1.1 413"));
  const std::string work = post("/api/careless/work", "a: 1\n");
  EXPECT_TRUE(has(work, "X-Content-Type-Options: nosniff")) << work;
}

TEST_F(KitSeam, NoMachinePathsOrExceptionTextsInTheKitsAnswers) {
  for (const std::string& a : {post("/api/careless/work", "a: 1\n"), get("/api/careless/look")}) {
    EXPECT_TRUE(has(a, "cannot read 'parts.yaml'")) << a;
    EXPECT_FALSE(has(a, "/home/someone")) << a;
  }
  for (const std::string& a : {get("/api/careless/boom"), post("/api/careless/boom", "a: 1\n")}) {
    EXPECT_TRUE(has(a, "HTTP/1.1 500")) << a;
    EXPECT_TRUE(has(a, "internal error while answering")) << a;
    EXPECT_FALSE(has(a, "shadow")) << a;
  }
}

// The body of an answer as a client reads it: Content-Length bytes after the headers; empty if
// the length does not match.
std::string body_as_read(const std::string& answer) {
  const std::size_t split = answer.find("\r\n\r\n");
  if (split == std::string::npos) return {};
  const std::string head = answer.substr(0, split);
  const std::string body = answer.substr(split + 4);
  const std::size_t at = head.find("Content-Length: ");
  if (at == std::string::npos || std::stoul(head.substr(at + 16)) != body.size()) return {};
  return body;
}

// Answers are never compressed, whatever the client accepts (over loopback it saves nothing,
// and httplib's brotli took 1.7 s for the editor's script), and machine paths are cut from
// what a handler answered before httplib fixes the body's length: cut afterwards, from the
// compressed bytes, an answer was corrupt now and then (the browser's
// ERR_CONTENT_DECODING_FAILED) and its paths stayed in.
TEST_F(KitSeam, AnswersAreNeverCompressedAndAlwaysCleaned) {
  for (const char* accepts : {"gzip", "br", "gzip, deflate, br", "identity"}) {
    SCOPED_TRACE(accepts);
    const std::string raw = server_->answer_raw(
        std::string("GET /api/careless/plain HTTP/1.1\r\nHost: 127.0.0.1:8080\r\n"
                    "Accept-Encoding: ") +
        accepts + "\r\n\r\n");
    EXPECT_FALSE(has(raw, "Content-Encoding")) << raw.substr(0, 400);
    const std::string body = body_as_read(raw);
    ASSERT_FALSE(body.empty()) << raw.substr(0, 400);
    const Json j = Json::parse(body);
    ASSERT_EQ(j["lines"].size(), 200u);
    EXPECT_EQ(j["lines"][7], "line 7: cannot read 'parts.yaml'");
    EXPECT_FALSE(has(body, "/home/someone"));
  }
  const std::string raw = server_->answer_raw(
      "POST /api/careless/work HTTP/1.1\r\nHost: 127.0.0.1:8080\r\nAccept-Encoding: gzip, br\r\n"
      "Content-Type: application/x-yaml\r\nContent-Length: 5\r\n\r\na: 1\n");
  EXPECT_FALSE(has(raw, "Content-Encoding")) << raw;
  EXPECT_TRUE(has(raw, "cannot read 'parts.yaml'")) << raw;
}

}  // namespace
}  // namespace fabkit::server

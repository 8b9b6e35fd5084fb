#pragma once
// A real editor server on a free loopback port, started for each test and stopped after it,
// with a keep-alive client: the fixture the kits' API tests share.

#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>

#include "fabkit/server/editor_server.h"

namespace fabkit::server::testing {

/// A file of the source tree (examples/…), whole; a missing file fails the test.
inline std::string read_source_file(const std::string& relative) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/" + relative);
  EXPECT_TRUE(in) << relative;
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class LiveServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ServerOptions o;
    o.host = "127.0.0.1";
    o.port = 0;
    server_ = std::make_unique<EditorServer>(o);
    ASSERT_TRUE(server_->bind()) << server_->error();
    thread_ = std::thread([this] { server_->listen(); });
    client_ = std::make_unique<httplib::Client>("127.0.0.1", server_->port());
    client_->set_read_timeout(60, 0);
    for (int i = 0; i < 100 && !client_->Get("/api/kits"); ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  void TearDown() override {
    server_->stop();
    if (thread_.joinable()) thread_.join();
  }

  std::unique_ptr<EditorServer> server_;
  std::thread thread_;
  std::unique_ptr<httplib::Client> client_;
};

}  // namespace fabkit::server::testing

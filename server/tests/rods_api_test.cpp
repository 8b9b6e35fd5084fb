// The rods routes over loopback (issue 15): the preview the designer draws, the checks it
// colours, OBJ import, and a background build whose files are downloaded by name.
#include <gtest/gtest.h>
#include <httplib.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <thread>

#include "fabkit/server/editor_server.h"
#include "live_server.h"

namespace fabkit::server {
namespace {

using nlohmann::json;

std::string read_rods_example(const std::string& name) {
  return testing::read_source_file("examples/rods/" + name + ".yaml");
}

class RodsApiTest : public testing::LiveServerTest {
 protected:
  json post_json(const std::string& path, const std::string& body, int expected_status) {
    auto r = client_->Post(path.c_str(), body, "application/x-yaml");
    EXPECT_TRUE(r);
    if (!r) return {};
    EXPECT_EQ(r->status, expected_status) << r->body.substr(0, 400);
    return json::parse(r->body);
  }
};

TEST_F(RodsApiTest, KitsListRods) {
  auto r = client_->Get("/api/kits");
  ASSERT_TRUE(r);
  EXPECT_NE(json::parse(r->body)["kits"].dump().find("\"rods\""), std::string::npos);
}

TEST_F(RodsApiTest, PreviewHasEveryJointRodAndCheck) {
  const json p = post_json("/api/rods/preview", read_rods_example("guitar_stand"), 200);
  ASSERT_EQ(p["joints"].size(), 6u);
  ASSERT_EQ(p["rods"].size(), 8u);
  for (const json& j : p["joints"]) {
    EXPECT_GT(j["mesh"]["vertices"].size(), 9u);
    EXPECT_EQ(j["mesh"]["faces"].size() % 3, 0u);
  }
  // ℓ = edge length − both offsets (Eq. 7), per rod
  for (const json& r : p["rods"]) {
    const double g = r["offsets"][0].get<double>() + r["offsets"][1].get<double>();
    EXPECT_NEAR(r["length"].get<double>(), r["edge_length"].get<double>() - g, 2e-3) << r["name"];
  }
  EXPECT_TRUE(p["passed"].get<bool>());
  EXPECT_TRUE(p["balance"]["stands"].get<bool>());
  EXPECT_NEAR(p["balance"]["margin"].get<double>(), 22.3, 0.05);  // as `fabkit check` prints
  EXPECT_EQ(p["assembly"].size(), 14u);
  EXPECT_TRUE(p["frame"]["solved"].get<bool>());
}

TEST_F(RodsApiTest, PreviewNamesTheCrossingRods) {
  const json p = post_json("/api/rods/preview", read_rods_example("failing/rods_intersect"), 200);
  ASSERT_EQ(p["intersections"].size(), 1u);
  bool named = false;
  for (const json& f : p["findings"]) {
    if (f["code"] == "rods-intersect" && f["severity"] == "error") {
      named = true;
      ASSERT_EQ(f["rods"].size(), 2u) << f.dump();
      EXPECT_EQ(p["rods"][f["rods"][0].get<int>()]["name"], "rod 03-04");
      EXPECT_EQ(p["rods"][f["rods"][1].get<int>()]["name"], "rod 05-06");
    }
  }
  EXPECT_TRUE(named);
  EXPECT_FALSE(p["passed"].get<bool>());
}

TEST_F(RodsApiTest, BadDesignsAreRefusedWithTheLine) {
  json e = post_json("/api/rods/preview",
                     "fabkit: rods/1\nnodes:\n  - [0, 0, 0]\n  - [1, nan, 0]\nedges:\n  - [1, 2]\n",
                     400);
  EXPECT_NE(e["error"].get<std::string>().find("design.yaml:4"), std::string::npos) << e.dump();
  // a posted design may not name files
  e = post_json("/api/rods/preview", "fabkit: rods/1\nnetwork: /etc/passwd\n", 400);
  EXPECT_NE(e["error"].get<std::string>().find("network"), std::string::npos) << e.dump();
  e = post_json("/api/rods/build", "fabkit: rods/1\nnetwork: shape.obj\n", 400);
  // the server is still up
  EXPECT_EQ(post_json("/api/rods/preview", read_rods_example("stool"), 200)["rods"].size(), 12u);
}

TEST_F(RodsApiTest, ImportObjMergesAndNumbers) {
  const json r =
      post_json("/api/rods/import-obj", "v 0 0 0\nv 100 0 0\nv 0 100 0\nf 1 2 3\nl 3 1\n", 200);
  EXPECT_EQ(r["nodes"].size(), 3u);
  EXPECT_EQ(r["edges"].size(), 3u);  // the l repeats a face edge: one rod
  const json e = post_json("/api/rods/import-obj", "v 0 0 0\nl 1 7\n", 400);
  EXPECT_NE(e["error"].get<std::string>().find("import.obj:2"), std::string::npos) << e.dump();
}

TEST_F(RodsApiTest, BuildRunsInTheBackgroundAndServesItsFiles) {
  const json start = post_json("/api/rods/build", read_rods_example("guitar_stand"), 202);
  const int id = start["job"].get<int>();
  EXPECT_EQ(start["total"].get<int>(), 6);
  json job;
  for (int i = 0; i < 1200; ++i) {
    auto r = client_->Get(("/api/rods/build/" + std::to_string(id)).c_str());
    ASSERT_TRUE(r);
    job = json::parse(r->body);
    if (job["state"] != "running") break;
    EXPECT_LE(job["done"].get<int>(), job["total"].get<int>());
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(job["state"], "done") << job.dump();
  EXPECT_EQ(job["done"].get<int>(), 6);
  EXPECT_EQ(job["result"]["joints"].size(), 6u);
  for (const json& j : job["result"]["joints"]) EXPECT_TRUE(j["closed"].get<bool>());
  std::set<std::string> names;
  for (const json& f : job["result"]["files"]) names.insert(f["name"].get<std::string>());
  for (const char* f : {"joint_01.stl",
                        "joint_06.stl",
                        "joints.3mf",
                        "cut_plan.svg",
                        "cut_list.csv",
                        "assembly.json",
                        "report.json",
                        "scene.glb"}) {
    EXPECT_TRUE(names.count(f)) << f;
  }
  auto stl =
      client_->Get(("/api/rods/build/" + std::to_string(id) + "/files/joint_01.stl").c_str());
  ASSERT_TRUE(stl);
  ASSERT_EQ(stl->status, 200);
  // binary STL: 80-byte header, count, 50 bytes per triangle
  ASSERT_GT(stl->body.size(), 84u);
  std::uint32_t triangles = 0;
  std::memcpy(&triangles, stl->body.data() + 80, 4);
  EXPECT_EQ(stl->body.size(), 84u + 50u * triangles);
  // names are keys of the job's files, never paths
  auto missing =
      client_->Get(("/api/rods/build/" + std::to_string(id) + "/files/report.jsonx").c_str());
  ASSERT_TRUE(missing);
  EXPECT_EQ(missing->status, 404);
  auto traversal = client_->Get(
      ("/api/rods/build/" + std::to_string(id) + "/files/..%2F..%2Fetc%2Fpasswd").c_str());
  ASSERT_TRUE(traversal);
  EXPECT_EQ(traversal->status, 404);
  auto nojob = client_->Get("/api/rods/build/999999");
  ASSERT_TRUE(nojob);
  EXPECT_EQ(nojob->status, 404);
}

}  // namespace
}  // namespace fabkit::server

// The flat-pack routes of the editor's API over loopback: the component registry, the assembled
// model of a posted design (pieces, joints, residuals, sheets, diagnostics with the pieces they
// concern) and the build downloads, and that bad requests get a 400 naming the problem.
#include <gtest/gtest.h>
#include <httplib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "fabkit/server/editor_server.h"
#include "live_server.h"

namespace fabkit::server {
namespace {

using nlohmann::json;

std::string read_flatpack_example(const std::string& name) {
  return testing::read_source_file("examples/flatpack/" + name + ".yaml");
}

class FlatpackApiTest : public testing::LiveServerTest {
 protected:
  httplib::Result post(const std::string& path, const std::string& body) {
    return client_->Post(path.c_str(), body, "application/x-yaml");
  }
};

TEST_F(FlatpackApiTest, KitsListFlatpackAndTheRegistryHasEveryComponentType) {
  const auto kits = json::parse(client_->Get("/api/kits")->body)["kits"];
  EXPECT_NE(std::find(kits.begin(), kits.end(), "flatpack"), kits.end()) << kits;
  const auto r = client_->Get("/api/flatpack/components");
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200);
  const json types = json::parse(r->body);
  ASSERT_EQ(types.size(), 10u);
  EXPECT_EQ(types[0]["name"], "Rectangle");
  EXPECT_EQ(types[0]["edges"], json::array({"b", "r", "t", "l"}));
  EXPECT_EQ(types[0]["params"][0]["name"], "l");
  EXPECT_EQ(types[0]["params"][0]["kind"], "length");
  EXPECT_TRUE(types[1]["constraints"][0].get<std::string>().starts_with("w = l"));  // Square
}

// The simple table (paper Fig. 11(g)): five pieces, four finger–hole joints from its four
// connections, one sheet; every component's edges in world coordinates.
TEST_F(FlatpackApiTest, AssembleTheSimpleTable) {
  const auto r = post("/api/flatpack/assemble", read_flatpack_example("simple_table"));
  ASSERT_TRUE(r);
  ASSERT_EQ(r->status, 200) << r->body;
  const json a = json::parse(r->body);
  EXPECT_TRUE(a["placed"].get<bool>());
  ASSERT_EQ(a["pieces"].size(), 5u);
  ASSERT_EQ(a["joints"].size(), 4u);
  for (const json& j : a["joints"]) {
    EXPECT_EQ(j["kind"], "finger-hole");
    EXPECT_FALSE(j["automatic"].get<bool>());
  }
  EXPECT_EQ(a["sheets"]["count"], 1);
  EXPECT_EQ(a["sheets"]["list"][0]["pieces"].size(), 5u);
  // The top is 300 × 180 mm: its edge b runs 300 mm in the world.
  for (const json& c : a["components"]) {
    if (c["name"] != "top") continue;
    const json& e = c["edges"][0];
    EXPECT_EQ(e["name"], "b");
    double len = 0;
    for (int k = 0; k < 3; ++k) {
      const double d = e["end"][k].get<double>() - e["start"][k].get<double>();
      len += d * d;
    }
    EXPECT_NEAR(std::sqrt(len), 300, 1e-6);
  }
  EXPECT_EQ(a["meta"].size(), 4u);
  EXPECT_TRUE(a["diagnostics"].empty()) << a["diagnostics"];
}

TEST_F(FlatpackApiTest, WarningsNameThePiecesTheyConcernAndResidualsAreNumbers) {
  // Two unconnected rectangles are laid side by side (not merged) and the warning names B.
  auto r = post("/api/flatpack/assemble",
                "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 30, w: 60}\n"
                "  - {name: B, type: Rectangle, l: 30, w: 60}\n");
  ASSERT_EQ(r->status, 200) << r->body;
  json a = json::parse(r->body);
  EXPECT_EQ(a["pieces"].size(), 2u);
  ASSERT_EQ(a["diagnostics"].size(), 1u);
  EXPECT_EQ(a["diagnostics"][0]["code"], "not-connected");
  EXPECT_EQ(a["diagnostics"][0]["pieces"],
            json::array({"B"}));  // not A, the one B is not connected to
  EXPECT_NE(
      std::find(a["diagnostics"][0]["pieces"].begin(), a["diagnostics"][0]["pieces"].end(), "B"),
      a["diagnostics"][0]["pieces"].end());
  // A cycle that does not close: not placed, the residual with its numbers.
  r = post(
      "/api/flatpack/assemble",
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 30, w: 30}\n"
      "  - {name: B, type: Rectangle, l: 30, w: 30}\n  - {name: C, type: Rectangle, l: 30, w: 30}\n"
      "connections:\n  - {connect: [B.l, A.r]}\n  - {connect: [C.l, B.r]}\n"
      "  - {connect: [C.b, A.t], offset: [0, 0, 5], name: closing}\n");
  ASSERT_EQ(r->status, 200) << r->body;
  a = json::parse(r->body);
  EXPECT_FALSE(a["placed"].get<bool>());
  ASSERT_EQ(a["residuals"].size(), 1u);
  EXPECT_NEAR(a["residuals"][0]["position_mm"].get<double>(), std::sqrt(4525.0), 1e-3);
  EXPECT_EQ(a["residuals"][0]["piece"], "C");
  ASSERT_EQ(a["diagnostics"].size(), 1u);
  EXPECT_EQ(a["diagnostics"][0]["code"], "cycle-mismatch");
  EXPECT_EQ(a["diagnostics"][0]["pieces"], json::array({"C"}));  // not B, also named in it
  EXPECT_FALSE(a["residuals"][0]["closes"].get<bool>());
}

TEST_F(FlatpackApiTest, BadDesignsAndUsesAreRefusedWithTheReason) {
  // A file that cannot be read: 400 with the reader's diagnostics.
  auto r = post("/api/flatpack/assemble", "fabkit: flatpack/1\ncomponents: [{name: A, type");
  ASSERT_EQ(r->status, 400) << r->body;
  EXPECT_FALSE(json::parse(r->body)["diagnostics"].empty());
  // A readable design the library refuses: 200, not placed, the diagnostic with did-you-mean.
  r = post("/api/flatpack/assemble",
           "fabkit: flatpack/1\ncomponents: [{name: A, type: Rectangel}]\n");
  ASSERT_EQ(r->status, 200) << r->body;
  const json a = json::parse(r->body);
  EXPECT_FALSE(a["placed"].get<bool>());
  ASSERT_FALSE(a["diagnostics"].empty());
  EXPECT_EQ(a["diagnostics"][0]["code"], "unknown-component");
  EXPECT_NE(a["diagnostics"][0]["message"].get<std::string>().find("'Rectangle'"),
            std::string::npos);
  // A posted design may not read other files.
  r = post("/api/flatpack/assemble", read_flatpack_example("bookshelf"));
  ASSERT_EQ(r->status, 400) << r->body;
  EXPECT_NE(r->body.find("uses"), std::string::npos) << r->body;
  r = post("/api/flatpack/build?file=../../etc/passwd", read_flatpack_example("bookend"));
  ASSERT_EQ(r->status, 400) << r->body;
  EXPECT_NE(r->body.find("sheet-1.dxf"), std::string::npos) << r->body;  // lists what it has
}

TEST_F(FlatpackApiTest, BuildReturnsEachDownload) {
  const std::string yaml = read_flatpack_example("bookend");
  auto r = post("/api/flatpack/build?file=sheet-1.svg", yaml);
  ASSERT_EQ(r->status, 200) << r->body;
  EXPECT_NE(r->body.find("width=\"600mm\""), std::string::npos);
  r = post("/api/flatpack/build?file=sheet-1.dxf", yaml);
  ASSERT_EQ(r->status, 200);
  EXPECT_NE(r->body.find("LWPOLYLINE"), std::string::npos);
  r = post("/api/flatpack/build?file=model.stl", yaml);
  ASSERT_EQ(r->status, 200);
  ASSERT_GE(r->body.size(), 84u);
  std::uint32_t triangles = 0;
  std::memcpy(&triangles, r->body.data() + 80, 4);
  EXPECT_EQ(r->body.size(), 84u + 50u * triangles);
  r = post("/api/flatpack/build?file=scene.glb", yaml);
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(r->body.substr(0, 4), "glTF");
  r = post("/api/flatpack/build?file=report.json", yaml);
  ASSERT_EQ(r->status, 200);
  EXPECT_EQ(json::parse(r->body)["counts"]["pieces"], 2);
}

}  // namespace
}  // namespace fabkit::server

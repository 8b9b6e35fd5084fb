#include "fabkit/rods/design_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fabkit/rods/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::rods {
namespace {

Design read(const std::string& yaml, const std::filesystem::path& base = {}) {
  return load_design_text(yaml, "d.yaml", base);
}

const char* kHeader = "fabkit: rods/1\nname: t\n";

TEST(DesignFile, ReadsParametersMaterialsAndNetwork) {
  const Design d = read(std::string(kHeader) +
                        "rod: {diameter: 12.7, profile: square, material: oak}\n"
                        "joint: {wall: 3, socket: 25, tolerance: -0.05, material: petg}\n"
                        "stock: {length: 2400, end_padding: 5, kerf: 3}\n"
                        "min_rod_length: 40\n"
                        "nodes:\n  - [0, 0, 0]\n  - [300, 0, 0]\n  - [0, 300, 0]\n"
                        "edges:\n  - [1, 2]\n  - [1, 3]\n  - [2, 3]\n"
                        "loads:\n  - {node: 2, force: [0, 0, -50]}\n"
                        "assembly_start: 3\n");
  ASSERT_TRUE(d.readable) << d.diagnostics.format();
  const Parameters& p = d.parameters;
  EXPECT_EQ(p.radius, 6.35);
  EXPECT_EQ(p.sides, 4);
  EXPECT_EQ(p.rod_material.name, "oak");
  EXPECT_EQ(p.wall, 3);
  EXPECT_EQ(p.socket, 25);
  EXPECT_EQ(p.tolerance, -0.05);
  EXPECT_EQ(p.joint_material.name, "petg");
  EXPECT_EQ(p.stock.length, 2400);
  EXPECT_EQ(p.stock.kerf, 3);
  EXPECT_EQ(p.min_rod_length, 40);
  ASSERT_EQ(d.loads.size(), 1u);
  EXPECT_EQ(d.loads[0].node, 1);
  EXPECT_EQ(d.assembly_start, 2);
  EXPECT_EQ(d.structure.rods.size(), 3u);
  EXPECT_EQ(d.structure.rods[2].where.line, 14);
}

TEST(DesignFile, ErrorsNameFileLineAndWhatIsWrong) {
  auto errors = [](const std::string& body) {
    return read(std::string(kHeader) + body).diagnostics.format();
  };
  const std::string net = "nodes:\n  - [0, 0, 0]\n  - [100, 0, 0]\nedges:\n  - [1, 2]\n";
  EXPECT_NE(errors("rod: {radius: .nan}\n" + net)
                .find("d.yaml:3:15: error: rod radius is .nan, not a finite number"),
            std::string::npos)
      << errors("rod: {radius: .nan}\n" + net);
  EXPECT_NE(
      errors("rod: {radius: -2}\n" + net)
          .find("d.yaml:3:15: error: rod radius -2 mm is out of range: it must be more than 0"),
      std::string::npos)
      << errors("rod: {radius: -2}\n" + net);
  EXPECT_NE(
      errors("rod: {profile: pentagram}\n" + net).find("rod profile 'pentagram' is not circle"),
      std::string::npos);
  EXPECT_NE(errors("rod: {material: oack}\n" + net)
                .find("unknown rod material 'oack'; did you mean 'oak'?"),
            std::string::npos)
      << errors("rod: {material: oack}\n" + net);
  EXPECT_NE(errors("rod: {radus: 3}\n" + net).find("did you mean 'radius'"), std::string::npos);
  EXPECT_NE(
      errors("joint: {tolerance: 5, wall: 2}\n" + net)
          .find("d.yaml:3:20: error: tolerance ε is 5; it must be smaller than the wall σ = 2 mm"),
      std::string::npos)
      << errors("joint: {tolerance: 5, wall: 2}\n" + net);
  EXPECT_NE(
      errors("nodes:\n  - [0, 0]\nedges:\n  - [1, 2]\n").find("d.yaml:4:5: error: node 1 must be"),
      std::string::npos)
      << errors("nodes:\n  - [0, 0]\nedges:\n  - [1, 2]\n");
  EXPECT_NE(errors("nodes:\n  - [0, 0, 0]\n  - [1, 0, 0]\nedges:\n  - [1, 2, 3]\n")
                .find("d.yaml:7:5: error: edge 1 must be a pair"),
            std::string::npos);
  EXPECT_NE(
      errors(net + "loads:\n  - {node: 9, force: [0, 0, -1]}\n").find("load node names node 9"),
      std::string::npos);
  EXPECT_NE(errors("edges:\n  - [1, 2]\n").find("needs nodes and edges"), std::string::npos);
  EXPECT_NE(read("fabkit: rods/2\n" + net).diagnostics.format().find("unsupported format 'rods/2'"),
            std::string::npos);
  EXPECT_FALSE(read(std::string(kHeader) + "rod: {radius: -2}\n" + net).readable);
}

TEST(DesignFile, UnexpectedShapesAreFindingsNotAborts) {
  // Found by fuzz/rods_design_fuzzer: `rod:` as a scalar made yaml-cpp throw BadSubscript
  // (an abort) where the parameter checks look up rod.radius.
  const std::string net = "nodes:\n  - [0, 0, 0]\n  - [100, 0, 0]\nedges:\n  - [1, 2]\n";
  for (const std::string& body : {std::string("rod: 0, 0, 0]\n") + net,
                                  std::string("joint: [1, 2]\nrod: {radius: -1}\n") + net,
                                  std::string("stock: 5\nrod: {radius: 0}\n") + net}) {
    const Design d = read(std::string(kHeader) + body);
    EXPECT_FALSE(d.readable) << body;
    EXPECT_TRUE(d.diagnostics.has_errors()) << body;
    for (const Diagnostic& x : d.diagnostics) EXPECT_EQ(x.where.file, "d.yaml") << x.message;
  }
}

TEST(DesignFile, NetworkFromObjLinesAndFaces) {
  const auto dir = std::filesystem::temp_directory_path() / "fabkit_rods_obj_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream obj(dir / "tet.obj");
    obj << "# a tetrahedron as faces: each shared edge becomes one rod\n"
           "v 0 0 0\nv 200 0 0\nv 0 200 0\nv 0 0 200\n"
           "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
    std::ofstream lines(dir / "path.obj");
    lines << "v 0 0 0\nv 100 0 0\nv 100 100 0\nl 1 2 3\nl 3 1\n";
    std::ofstream bad(dir / "bad.obj");
    bad << "v 0 0 0\nv 1 0\nl 1 2\n";
  }
  const Design tet = read(std::string(kHeader) + "network: tet.obj\n", dir);
  ASSERT_TRUE(tet.readable) << tet.diagnostics.format();
  EXPECT_EQ(tet.structure.nodes.size(), 4u);
  EXPECT_EQ(tet.structure.rods.size(), 6u);
  const Design path = read(std::string(kHeader) + "network: path.obj\nscale: 2\n", dir);
  ASSERT_TRUE(path.readable) << path.diagnostics.format();
  EXPECT_EQ(path.structure.rods.size(), 3u);
  EXPECT_EQ(path.structure.nodes[1].position.x(), 200);
  const Design bad = read(std::string(kHeader) + "network: bad.obj\n", dir);
  EXPECT_FALSE(bad.readable);
  EXPECT_NE(
      bad.diagnostics.format().find("bad.obj:2:1: error: a vertex needs three finite numbers"),
      std::string::npos)
      << bad.diagnostics.format();
  const Design missing = read(std::string(kHeader) + "network: nothere.obj\n", dir);
  EXPECT_NE(missing.diagnostics.format().find("cannot read network file"), std::string::npos)
      << missing.diagnostics.format();
  DesignOptions server;
  server.files = FilePolicy::kRefuse;
  const Design refused =
      load_design_text(std::string(kHeader) + "network: tet.obj\n", "d.yaml", dir, server);
  EXPECT_NE(refused.diagnostics.format().find("network files are not accepted here"),
            std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(DesignFile, EveryExampleReads) {
  for (const auto& entry : std::filesystem::recursive_directory_iterator(
           std::string(FABKIT_SOURCE_DIR) + "/examples/rods")) {
    if (entry.path().extension() != ".yaml") continue;
    const Design d = load_design(entry.path());
    EXPECT_TRUE(d.readable) << entry.path() << ": " << d.diagnostics.format();
    EXPECT_FALSE(d.name.empty()) << entry.path();
  }
}

TEST(DesignFile, FromListsUsesZeroBasedEdges) {
  Parameters p;
  const Design d =
      design_from_lists({{0, 0, 0}, {100, 0, 0}, {0, 100, 0}}, {{0, 1}, {1, 2}, {2, 0}}, p);
  ASSERT_TRUE(d.readable) << d.diagnostics.format();
  EXPECT_EQ(d.structure.joint_name(0), "joint 01");
  const Design bad = design_from_lists({{0, 0, 0}, {100, 0, 0}}, {{0, 2}}, p);
  EXPECT_FALSE(bad.readable);
  EXPECT_NE(bad.diagnostics.format().find("edge 1 names node 2, but the nodes are numbered 0 to 1"),
            std::string::npos);
}

}  // namespace
}  // namespace fabkit::rods

// PartsLibrary lookup and user part files (load_yaml): valid files load; malformed ones report
// the right code at the right 1-based line and add nothing.

#include "fabkit/hacks/parts_library.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "fabkit/hacks/diagnostic_codes.h"

namespace fabkit::hacks {
namespace {

namespace fs = std::filesystem;

// A fresh directory per test for the YAML and mesh files.
class PartFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    dir_ = fs::temp_directory_path() /
           ("fabkit_parts_test_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }

  // A 10 mm cube from (0,0,0) to (10,10,10), quads wound counter-clockwise seen from outside.
  fs::path write_cube(const std::string& name) const {
    return write(name,
                 "# unit test cube\n"
                 "v 0 0 0\nv 10 0 0\nv 10 10 0\nv 0 10 0\n"
                 "v 0 0 10\nv 10 0 10\nv 10 10 10\nv 0 10 10\n"
                 "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n");
  }

  // Loads `text` into a copy of the built-in library and expects exactly the failure
  // `code` at `line`, with nothing added.
  void expect_error(const std::string& text, DiagnosticCode code, int line) {
    PartsLibrary lib = PartsLibrary::builtin();
    const std::size_t before = lib.generators().size();
    const fs::path file = write("bad.yaml", text);
    Diagnostics diags;
    EXPECT_FALSE(lib.load_yaml(file, diags));
    EXPECT_TRUE(diags.has_errors());
    ASSERT_FALSE(diags.empty());
    const Diagnostic& d = diags.items().front();
    EXPECT_EQ(to_string(d.code), to_string(code)) << diags.format();
    EXPECT_EQ(d.where.line, line) << diags.format();
    EXPECT_EQ(d.where.file, file.string());
    EXPECT_EQ(lib.generators().size(), before);
    EXPECT_EQ(lib.find("GoodPart"), nullptr) << "a valid part of a bad file was added";
  }

  fs::path dir_;
};

// A valid part placed before the broken one in several cases: it must not be added either.
const std::string kGood =
    "  - name: GoodPart\n"
    "    primitives:\n"
    "      - {name: peg, type: rod, radius: 2, length: 30}\n";

TEST_F(PartFiles, ValidFileLoadsAndMakesParts) {
  write_cube("cube.obj");
  const fs::path file = write("parts.yaml",
                              "parts:\n"
                              "  - name: TestBracket\n"
                              "    description: a test bracket\n"
                              "    mesh: cube.obj\n"
                              "    category: hack\n"
                              "    primitives:\n"
                              "      - name: hook\n"
                              "        type: hook\n"
                              "        arc_radius: 12\n"
                              "        arc_angle: 180\n"
                              "        thickness: 2\n"
                              "        frame: {pos: [0, 0, -20], rot: [90, 0, 0]}\n"
                              "        flex: true\n"
                              "        theta_range: [0, 200]\n"
                              "      - name: back\n"
                              "        type: surface\n"
                              "        length: 20\n"
                              "        width: 20\n"
                              "  - name: TestPeg\n"
                              "    mass: 55.5\n"
                              "    center_of_mass: [1, 2, 3]\n"
                              "    primitives:\n"
                              "      - name: hole1\n"
                              "        type: hole\n"
                              "        arc_radius: 5\n"
                              "        thickness: 1\n"
                              "      - name: peg\n"
                              "        type: rod\n"
                              "        radius: 3\n"
                              "        length: 40\n"
                              "        is_open: false\n");
  PartsLibrary lib = PartsLibrary::builtin();
  const std::size_t before = lib.generators().size();
  Diagnostics diags;
  ASSERT_TRUE(lib.load_yaml(file, diags)) << diags.format();
  EXPECT_TRUE(diags.empty()) << diags.format();
  EXPECT_EQ(lib.generators().size(), before + 2);

  auto bracket = lib.make("TestBracket", {}, diags);
  ASSERT_NE(bracket, nullptr) << diags.format();
  EXPECT_EQ(bracket->type_name, "TestBracket");
  EXPECT_EQ(bracket->description, "a test bracket");
  EXPECT_EQ(bracket->category, PartCategory::kHack);
  EXPECT_NEAR(bracket->mass, 1000, 1e-9);  // default: mesh volume at density 1
  EXPECT_NEAR((bracket->center_of_mass - Vec3(5, 5, 5)).norm(), 0, 1e-9);
  EXPECT_EQ(bracket->mesh.faces.size(), 12u);
  ASSERT_EQ(bracket->primitives.size(), 2u);
  const Primitive& h = bracket->primitives[0];
  EXPECT_EQ(h.type, PrimitiveType::kHook);
  EXPECT_DOUBLE_EQ(h.shape.arc_radius, 12);
  EXPECT_DOUBLE_EQ(h.shape.arc_angle, 180);
  EXPECT_DOUBLE_EQ(h.shape.thickness, 2);
  EXPECT_TRUE(h.flex);
  EXPECT_TRUE(h.is_open);
  ASSERT_TRUE(h.theta_range.has_value());
  EXPECT_DOUBLE_EQ((*h.theta_range)[1], 200);
  EXPECT_TRUE(h.frame.pos.isApprox(Vec3(0, 0, -20)));
  EXPECT_TRUE(h.frame.rot.isApprox(Vec3(90, 0, 0)));
  const Primitive& s = bracket->primitives[1];
  EXPECT_EQ(s.type, PrimitiveType::kSurface);
  EXPECT_FALSE(s.is_open);  // the type's default

  auto peg = lib.make("testpeg", {}, diags);  // case-insensitive lookup
  ASSERT_NE(peg, nullptr) << diags.format();
  EXPECT_DOUBLE_EQ(peg->mass, 55.5);
  EXPECT_TRUE(peg->center_of_mass.isApprox(Vec3(1, 2, 3)));
  EXPECT_FALSE(peg->mesh.empty());  // drawn from the primitives
  EXPECT_EQ(peg->find_primitive("ring1").value, 0);
  EXPECT_EQ(peg->primitives[0].type, PrimitiveType::kRing);
  EXPECT_FALSE(peg->primitives[1].is_open);
  EXPECT_FALSE(peg->primitives[1].open_for_connect);  // follows is_open, as in the reference
  EXPECT_FALSE(diags.has_errors()) << diags.format();

  // A part without mesh or mass weighs its primitives' volume.
  const fs::path file2 = write("more.yaml", "parts:\n" + kGood);
  ASSERT_TRUE(lib.load_yaml(file2, diags)) << diags.format();
  auto good = lib.make("GoodPart", {}, diags);
  ASSERT_NE(good, nullptr);
  EXPECT_NEAR(good->mass, good->mesh.volume(), 1e-9);
  EXPECT_GT(good->mass, 0.9 * 3.14159 * 4 * 30);
}

TEST_F(PartFiles, YamlSyntaxError) {
  expect_error(
      "parts:\n"
      "  - name: Broken\n"
      "    description: a: b\n",
      codes::kMalformedInput,
      3);
}

TEST_F(PartFiles, MissingPrimitives) {
  expect_error("parts:\n" + kGood +
                   "  - name: NoPrims\n"
                   "    description: nothing to connect\n",
               codes::kMalformedInput,
               5);
}

// A category that is none of the four is named with its line; one in another case is read.
TEST_F(PartFiles, UnknownCategory) {
  expect_error("parts:\n" + kGood +
                   "  - name: Widget\n"
                   "    category: gadget\n"
                   "    primitives:\n"
                   "      - {name: peg, type: rod, radius: 2, length: 30}\n",
               codes::kUnknownName,
               6);
  PartsLibrary lib;
  Diagnostics diags;
  ASSERT_TRUE(
      lib.load_yaml_text("parts:\n"
                         "  - name: Hanger\n"
                         "    category: Hack\n"
                         "    primitives:\n"
                         "      - {name: peg, type: rod, radius: 2, length: 30}\n",
                         "hack.yaml",
                         dir_,
                         diags))
      << diags.format();
  EXPECT_EQ(lib.find("Hanger")->category, PartCategory::kHack);
}

TEST_F(PartFiles, UnknownPrimitiveType) {
  expect_error(
      "parts:\n"
      "  - name: BadType\n"
      "    primitives:\n"
      "      - name: p\n"
      "        type: spring\n"
      "        radius: 3\n",
      codes::kUnknownName,
      5);
}

TEST_F(PartFiles, NegativeRadius) {
  expect_error("parts:\n" + kGood +
                   "  - name: NegRadius\n"
                   "    primitives:\n"
                   "      - name: peg\n"
                   "        type: rod\n"
                   "        length: 10\n"
                   "        radius: -3\n",
               codes::kInvalidValue,
               10);
}

TEST_F(PartFiles, NotANumber) {
  expect_error(
      "parts:\n"
      "  - name: NanHook\n"
      "    primitives:\n"
      "      - name: hook\n"
      "        type: hook\n"
      "        arc_radius: 10\n"
      "        arc_angle: .nan\n"
      "        thickness: 1\n",
      codes::kInvalidValue,
      7);
}

TEST_F(PartFiles, DuplicatePrimitiveName) {
  expect_error(
      "parts:\n"
      "  - name: Dup\n"
      "    primitives:\n"
      "      - name: peg\n"
      "        type: rod\n"
      "        radius: 1\n"
      "        length: 5\n"
      "      - name: peg\n"
      "        type: rod\n"
      "        radius: 1\n"
      "        length: 5\n",
      codes::kDuplicateName,
      8);
}

TEST_F(PartFiles, MissingMeshFile) {
  expect_error("parts:\n" + kGood +
                   "  - name: NoMesh\n"
                   "    mesh: missing.stl\n"
                   "    primitives:\n"
                   "      - {name: peg, type: rod, radius: 1, length: 5}\n",
               codes::kUnreadableFile,
               6);
}

TEST_F(PartFiles, UnknownKey) {
  expect_error("parts:\n" + kGood +
                   "  - name: Extra\n"
                   "    colour: red\n"
                   "    primitives:\n"
                   "      - {name: peg, type: rod, radius: 1, length: 5}\n",
               codes::kUnknownName,
               6);
}

TEST_F(PartFiles, FieldOfAnotherPrimitiveType) {
  expect_error(
      "parts:\n"
      "  - name: RodWithArc\n"
      "    primitives:\n"
      "      - name: peg\n"
      "        type: rod\n"
      "        radius: 1\n"
      "        length: 5\n"
      "        arc_angle: 90\n",
      codes::kUnknownName,
      8);
}

TEST_F(PartFiles, MissingShapeField) {
  expect_error(
      "parts:\n"
      "  - name: Short\n"
      "    primitives:\n"
      "      - name: peg\n"
      "        type: rod\n"
      "        radius: 1\n",
      codes::kMalformedInput,
      4);
}

TEST_F(PartFiles, WrongNodeType) {
  expect_error(
      "parts:\n"
      "  - name: Listy\n"
      "    primitives: {name: peg}\n",
      codes::kMalformedInput,
      3);
}

TEST_F(PartFiles, NameClashesWithBuiltin) {
  expect_error(
      "parts:\n"
      "  - name: DoubleHook\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: 1, length: 5}\n",
      codes::kDuplicateName,
      2);
}

TEST_F(PartFiles, WireThickerThanItsArc) {
  // Primitive::validate's relational checks report at the primitive's line.
  expect_error(
      "parts:\n"
      "  - name: FatHook\n"
      "    primitives:\n"
      "      - name: hook\n"
      "        type: hook\n"
      "        arc_radius: 2\n"
      "        arc_angle: 180\n"
      "        thickness: 3\n",
      codes::kInvalidValue,
      4);
}

TEST_F(PartFiles, UnreadableFile) {
  PartsLibrary lib;
  Diagnostics diags;
  EXPECT_FALSE(lib.load_yaml(dir_ / "does_not_exist.yaml", diags));
  ASSERT_EQ(diags.size(), 1u);
  EXPECT_EQ(diags.items()[0].code, codes::kUnreadableFile);
  EXPECT_TRUE(lib.generators().empty());
}

TEST(PartsLibrary, ExampleWallBracketLoads) {
  const fs::path file = fs::path(FABKIT_SOURCE_DIR) / "examples/parts/wall_bracket.yaml";
  PartsLibrary lib = PartsLibrary::builtin();
  Diagnostics diags;
  ASSERT_TRUE(lib.load_yaml(file, diags)) << diags.format();
  EXPECT_TRUE(diags.empty()) << diags.format();
  auto part = lib.make("WallBracket", {}, diags);
  ASSERT_NE(part, nullptr) << diags.format();
  EXPECT_GE(part->primitives.size(), 2u);
  EXPECT_GT(part->mass, 0);
  EXPECT_GT(part->mesh.volume(), 0);
  const Vec3 lo = part->mesh.bounds_min();
  const Vec3 hi = part->mesh.bounds_max();
  for (const Primitive& p : part->primitives) {
    EXPECT_TRUE((p.frame.pos.array() >= lo.array() - 1).all() &&
                (p.frame.pos.array() <= hi.array() + 1).all())
        << p.name;
  }
}

TEST(PartsLibrary, FindAddAndSuggest) {
  PartsLibrary lib;
  PartGenerator g;
  g.name = "Widget";
  g.aliases = {"Gadget"};
  g.build = [](const ParamValues&) {
    Part p;
    PrimitiveShape s;
    s.radius = 1;
    s.length = 10;
    p.primitives.push_back(Primitive::make("rod", PrimitiveType::kRod, s));
    return p;
  };
  lib.add(g);
  ASSERT_NE(lib.find("Widget"), nullptr);
  ASSERT_NE(lib.find("Gadget"), nullptr);
  ASSERT_NE(lib.find("wIDGET"), nullptr);
  ASSERT_NE(lib.find("gadget"), nullptr);
  EXPECT_EQ(lib.find("Gizmo"), nullptr);
  EXPECT_EQ(lib.suggest("Widgte"), "Widget");
  EXPECT_EQ(lib.suggest("Gadgt"), "Gadget");
  EXPECT_EQ(lib.suggest("Zebra"), "");
  // Same name replaces.
  g.description = "second";
  lib.add(g);
  EXPECT_EQ(lib.generators().size(), 1u);
  EXPECT_EQ(lib.find("Widget")->description, "second");

  Diagnostics diags;
  auto part = lib.make("gadget", {}, diags);
  ASSERT_NE(part, nullptr);
  EXPECT_EQ(part->type_name, "Widget");
  EXPECT_TRUE(part->params.empty());
}

TEST(PartsLibrary, BuiltinIsBuiltOnce) {
  EXPECT_EQ(&PartsLibrary::builtin(), &PartsLibrary::builtin());
  EXPECT_EQ(PartsLibrary::builtin().suggest("doublehok"), "DoubleHook");
  EXPECT_EQ(PartsLibrary::builtin().suggest("Turnbukle"), "Turnbuckle");
}

// A file read with PartLoading::kOnFirstUse gives the same parts as an eager read; mistakes in
// a part's identity are still reported at once, mistakes in its contents when it is first made
// (the contract of the built-in file, which is tested to load).
TEST_F(PartFiles, OnFirstUseBuildsTheSamePartsWhenTheyAreMade) {
  write_cube("cube.obj");
  const std::string text =
      "parts:\n"
      "  - name: TestBracket\n"
      "    description: a test bracket\n"
      "    mesh: cube.obj\n"
      "    category: hack\n"
      "    primitives:\n"
      "      - {name: hook, type: hook, arc_radius: 8, arc_angle: 200, thickness: 1.5}\n"
      "  - name: BoxedPeg\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: 2, length: 30}\n"
      "    body:\n"
      "      - box: {min: [-5, -5, -20], max: [5, 5, -15]}\n";
  PartsLibrary eager, later;
  Diagnostics d1, d2;
  ASSERT_TRUE(eager.load_yaml_text(text, "parts.yaml", dir_, d1)) << d1.format();
  ASSERT_TRUE(later.load_yaml_text(
      text, "parts.yaml", dir_, d2, PartCategory::kOther, PartLoading::kOnFirstUse))
      << d2.format();
  ASSERT_EQ(eager.generators().size(), later.generators().size());
  for (const PartGenerator& g : eager.generators()) {
    SCOPED_TRACE(g.name);
    const PartGenerator* h = later.find(g.name);
    ASSERT_NE(h, nullptr);
    EXPECT_EQ(h->description, g.description);
    EXPECT_EQ(h->category, g.category);
    for (int twice = 0; twice < 2; ++twice) {
      const Part a = g.build({});
      const Part b = h->build({});
      ASSERT_EQ(a.primitives.size(), b.primitives.size());
      for (std::size_t i = 0; i < a.primitives.size(); ++i) {
        EXPECT_EQ(a.primitives[i].describe(), b.primitives[i].describe());
      }
      EXPECT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
      EXPECT_EQ(a.mesh.faces.size(), b.mesh.faces.size());
      EXPECT_EQ(a.collision_pieces.size(), b.collision_pieces.size());
      EXPECT_DOUBLE_EQ(a.mass, b.mass);
      EXPECT_LT((a.center_of_mass - b.center_of_mass).norm(), 1e-12);
    }
  }

  // Identity mistakes: reported at load, nothing added.
  PartsLibrary dup;
  Diagnostics d3;
  EXPECT_FALSE(dup.load_yaml_text("parts:\n" + kGood + kGood,
                                  "dup.yaml",
                                  dir_,
                                  d3,
                                  PartCategory::kOther,
                                  PartLoading::kOnFirstUse));
  ASSERT_FALSE(d3.empty());
  EXPECT_EQ(d3.items().front().code, codes::kDuplicateName);
  EXPECT_TRUE(dup.generators().empty());

  // A contents mistake surfaces when the part is made, naming the file, the part and the value.
  PartsLibrary bad;
  Diagnostics d4;
  ASSERT_TRUE(
      bad.load_yaml_text("parts:\n  - name: NegRadius\n    primitives:\n"
                         "      - {name: peg, type: rod, radius: -3, length: 10}\n",
                         "neg.yaml",
                         dir_,
                         d4,
                         PartCategory::kOther,
                         PartLoading::kOnFirstUse));
  try {
    bad.find("NegRadius")->build({});
    ADD_FAILURE() << "a part with a negative radius was built";
  } catch (const std::logic_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("neg.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("NegRadius"), std::string::npos) << what;
    EXPECT_NE(what.find("-3"), std::string::npos) << what;
  }
}

// A file laid out as the built-in one (a header, `parts:`, entries opening with their identity
// keys) is read entry by entry on first use: identities at load, each entry's contents when its
// part is first made, and a mistake there names the file's own line.
TEST_F(PartFiles, OnFirstUseReadsEachEntryAtItsOwnLines) {
  const std::string text =
      "# built-in style\n"
      "fabkit: hacks/1\n"
      "parts:\n"
      "  - name: GoodPeg\n"
      "    # a peg\n"
      "    description: a peg\n"
      "    category: hack\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: 2, length: 30}\n"
      "    mass: 120\n"
      "  - name: BadPeg\n"
      "    aliases:\n"
      "      - WrongPeg\n"
      "    description: >\n"
      "      a peg whose radius\n"
      "      is wrong\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: -3, length: 10}\n"
      "  - name: HashPeg\n"
      "    description: |\n"
      "      # not a comment: a block scalar's line\n"
      "      ends here\n"
      "    primitives:\n"
      "    # a comment between a key and its list\n"
      "      - {name: peg, type: rod, radius: 2, length: 30}\n";
  PartsLibrary lib;
  Diagnostics diags;
  ASSERT_TRUE(lib.load_yaml_text(
      text, "split.yaml", dir_, diags, PartCategory::kOther, PartLoading::kOnFirstUse))
      << diags.format();
  const PartGenerator* good = lib.find("GoodPeg");
  ASSERT_NE(good, nullptr);
  EXPECT_EQ(good->description, "a peg");
  EXPECT_EQ(good->category, PartCategory::kHack);
  EXPECT_EQ(lib.find("WrongPeg"), lib.find("BadPeg"));
  EXPECT_EQ(lib.find("BadPeg")->description, "a peg whose radius is wrong\n");
  // Comment lines are left out of what yaml-cpp reads; a block scalar's '#' lines are not.
  ASSERT_NE(lib.find("HashPeg"), nullptr);
  EXPECT_EQ(lib.find("HashPeg")->description,
            "# not a comment: a block scalar's line\nends here\n");
  EXPECT_EQ(lib.find("HashPeg")->build({}).primitives.size(), 1u);
  const Part peg = good->build({});
  ASSERT_EQ(peg.primitives.size(), 1u);
  EXPECT_DOUBLE_EQ(peg.primitives[0].shape.radius, 2);
  EXPECT_DOUBLE_EQ(peg.mass, 120);
  try {
    lib.find("BadPeg")->build({});
    ADD_FAILURE() << "a part with a negative radius was built";
  } catch (const std::logic_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("split.yaml:18"), std::string::npos) << what;
    EXPECT_NE(what.find("-3"), std::string::npos) << what;
  }
  // An identity mistake is still reported at load, at its line.
  PartsLibrary dup;
  Diagnostics d2;
  EXPECT_FALSE(
      dup.load_yaml_text("parts:\n  - name: Twice\n    primitives: []\n"
                         "  - name: twice\n    primitives: []\n",
                         "dup.yaml",
                         dir_,
                         d2,
                         PartCategory::kOther,
                         PartLoading::kOnFirstUse));
  ASSERT_FALSE(d2.empty());
  EXPECT_EQ(d2.items().front().code, codes::kDuplicateName);
  EXPECT_NE(d2.format().find("dup.yaml:4"), std::string::npos) << d2.format();
}

// Each entry read on first use is a document of the file's header and that entry's lines
// alone (not the whole file with the other lines blank): a syntax error in it still names the
// file's own line, past other entries and comments.
TEST_F(PartFiles, OnFirstUseSyntaxErrorNamesTheFilesLine) {
  const std::string text =
      "# a header comment\n"
      "fabkit: hacks/1\n"
      "parts:\n"
      "  - name: FirstPeg\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: 2, length: 30}\n"
      "  # a comment between entries\n"
      "  - name: BrokenPeg\n"
      "    description: its length is not YAML\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: 2, length: `30}\n"
      "  - name: OpenPeg\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: 2, length: 30\n"
      "  - name: LastPeg\n"
      "    primitives:\n"
      "      - {name: peg, type: rod, radius: 2, length: 30}\n";
  PartsLibrary lib;
  Diagnostics diags;
  ASSERT_TRUE(lib.load_yaml_text(
      text, "broken.yaml", dir_, diags, PartCategory::kOther, PartLoading::kOnFirstUse))
      << diags.format();
  EXPECT_EQ(lib.find("LastPeg")->build({}).primitives.size(), 1u);
  try {
    lib.find("BrokenPeg")->build({});
    ADD_FAILURE() << "a part with a syntax error was built";
  } catch (const std::logic_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("broken.yaml:11"), std::string::npos) << what;
  }
  try {
    lib.find("OpenPeg")->build({});
    ADD_FAILURE() << "a part with an unclosed mapping was built";
  } catch (const std::logic_error& e) {
    // Found where the entry ends: the file's next line, where the next entry begins.
    const std::string what = e.what();
    EXPECT_NE(what.find("broken.yaml:15"), std::string::npos) << what;
  }
}

// The built-in parts are built on first use, under one lock: threads that make them at once
// (the server's workers) get the same parts.
TEST(PartsLibrary, BuiltinPartsMadeFromTwoThreadsAreTheSame) {
  const PartsLibrary& lib = PartsLibrary::builtin();
  auto describe_all = [&] {
    std::vector<std::string> out;
    for (const PartGenerator& g : lib.generators()) {
      if (!g.params.empty()) continue;
      const Part p = g.build({});
      std::string d = g.name + fmt::format(" {:.12g}", p.mass);
      for (const Primitive& prim : p.primitives) {
        d += ' ';
        d += prim.describe();
      }
      out.push_back(std::move(d));
    }
    return out;
  };
  std::vector<std::string> first, second;
  std::thread a([&] { first = describe_all(); });
  std::thread b([&] { second = describe_all(); });
  a.join();
  b.join();
  EXPECT_EQ(first.size(), 54u);
  EXPECT_EQ(first, second);
}

}  // namespace
}  // namespace fabkit::hacks

// Hierarchical composition (paper §4.2): design files used as components by other designs,
// through the bundled composites (bookshelf of three stools, bunk bed = desk + bed + ladder,
// TV console) and through small designs written here. Parameters flow into sub-designs,
// names are prefixed by the instance, exported interfaces connect, and a design that would
// contain itself is refused with a message naming the chain of files.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "fabkit/flatpack/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

const std::filesystem::path kExampleDir =
    std::filesystem::path(FABKIT_SOURCE_DIR) / "examples" / "flatpack";

// A design text that may use the bundled examples as components.
Analysis check_with_examples(const std::string& yaml, Diagnostics* read = nullptr) {
  Diagnostics d;
  const Design design = load_design_text(yaml, "composite.yaml", d, kExampleDir);
  if (read) *read = d;
  if (d.has_errors()) {
    Analysis a;
    a.diagnostics = d;
    return a;
  }
  return check(design);
}

const PlacedComponent* component(const Analysis& a, const std::string& name) {
  for (const PlacedComponent& c : a.components) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

const Piece* piece(const Analysis& a, const std::string& name) {
  for (const Piece& p : a.pieces) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

const Joint* joint_between(const Analysis& a, const std::string& x, const std::string& y) {
  for (const Joint& j : a.joints) {
    const std::string& p = a.pieces[static_cast<std::size_t>(j.piece_a)].name;
    const std::string& q = a.pieces[static_cast<std::size_t>(j.piece_b)].name;
    if ((p == x && q == y) || (p == y && q == x)) return &j;
  }
  return nullptr;
}

TEST(Composition, BookshelfStacksThreeStoolsWithPrefixedNamesAndItsParameters) {
  Design d = test::example("bookshelf");
  const Analysis a = check(d);
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  ASSERT_EQ(a.components.size(), 12u);  // 3 stools × (seat, two sides, apron)
  for (const char* stool : {"bottom", "middle", "upper"}) {
    for (const char* part : {"seat", "side_left", "side_right", "apron"}) {
      EXPECT_NE(component(a, std::string(stool) + "." + part), nullptr) << stool << "." << part;
    }
    // The bookshelf's size and shelf height reach every stool (box_stool.yaml says 180/150).
    EXPECT_NEAR(a.values.at(std::string(stool) + ".size"), 180, 1e-9);
    EXPECT_NEAR(a.values.at(std::string(stool) + ".height"), 150, 1e-9);
  }
  // Stacked one shelf apart, each a quarter turn from the one below.
  const Mat4& bottom = piece(a, "bottom.seat")->frame;
  const Mat4& middle = piece(a, "middle.seat")->frame;
  const Mat4& upper = piece(a, "upper.seat")->frame;
  EXPECT_NEAR(middle(2, 3) - bottom(2, 3), 150, 1e-9);
  EXPECT_NEAR(upper(2, 3) - middle(2, 3), 150, 1e-9);
  const Vec3 side_bottom = piece(a, "bottom.side_left")->frame.block<3, 1>(0, 2);
  const Vec3 side_middle = piece(a, "middle.side_left")->frame.block<3, 1>(0, 2);
  EXPECT_NEAR(std::abs(side_bottom.dot(side_middle)), 0, 1e-9);
  // Each upper stool's side panels go into the seat below: one through the connection that
  // stacks it, the other found automatically.
  const Joint* through_connection = joint_between(a, "middle.side_left", "bottom.seat");
  const Joint* found = joint_between(a, "middle.side_right", "bottom.seat");
  ASSERT_NE(through_connection, nullptr);
  ASSERT_NE(found, nullptr);
  EXPECT_EQ(through_connection->kind, JointKind::kFingerHole);
  EXPECT_FALSE(through_connection->automatic());
  EXPECT_TRUE(found->automatic());

  // One number in the bookshelf re-sizes all three stools.
  for (DesignParameter& p : d.parameters) {
    if (p.name == "size") p.value = 200;
  }
  const Analysis wider = check(d);
  ASSERT_FALSE(wider.diagnostics.has_errors()) << wider.diagnostics.format();
  for (const char* stool : {"bottom", "middle", "upper"}) {
    EXPECT_NEAR(wider.values.at(std::string(stool) + ".seat.l"), 200, 1e-9);
    EXPECT_NEAR(wider.values.at(std::string(stool) + ".side_left.l"), 200, 1e-9);
  }
}

TEST(Composition, ADesignUsingTheBookshelfReachesTwoLevelsDownThroughItsInterface) {
  // A name board standing on the bookshelf's top front edge (exported as top_front, which is
  // the upper stool's seat_front, which is that stool's seat.b).
  const Analysis a = check_with_examples(
      "fabkit: flatpack/1\nuses: {Shelf: bookshelf.yaml}\ncomponents:\n"
      "  - {name: shelf, type: Shelf, size: 190}\n"
      "  - {name: sign, type: Rectangle, l: 190, w: 30}\n"
      "connections:\n  - {connect: [sign.b, shelf.top_front], rotation: [90, 0, 0]}\n");
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_EQ(a.components.size(), 13u);
  EXPECT_NEAR(a.values.at("shelf.upper.seat.l"), 190, 1e-9);
  const Joint* j = joint_between(a, "sign", "shelf.upper.seat");
  ASSERT_NE(j, nullptr) << a.diagnostics.format();
  EXPECT_EQ(j->kind, JointKind::kFingerFinger);  // edge on edge
  EXPECT_FALSE(j->automatic());
  EXPECT_NEAR(j->length_mm, 190, 1e-6);
}

TEST(Composition, BunkBedSetsItsSubDesignsAndFindsTheJointsBetweenThem) {
  Design d = test::example("bunk_bed");
  ASSERT_EQ(d.library.size(), 3u);  // Desk, Bed, Ladder
  const Analysis a = check(d);
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  // The desk is made as long as the bed's deck, so its top reaches both end boards.
  EXPECT_NEAR(a.values.at("desk.top.l"), 300, 1e-9);
  EXPECT_NEAR(a.values.at("bed.deck.l"), 300, 1e-9);
  EXPECT_NEAR(a.values.at("desk.top.w"), 120, 1e-9);           // width - 30
  EXPECT_NEAR(a.values.at("ladder.stile_left.w"), 280, 1e-9);  // deck_height + 60
  const Joint* head = joint_between(a, "desk.top", "bed.head");
  const Joint* foot = joint_between(a, "desk.top", "bed.foot");
  ASSERT_TRUE(head && foot);
  EXPECT_FALSE(head->automatic());  // the connection placing the desk
  EXPECT_TRUE(foot->automatic());
  EXPECT_EQ(foot->kind, JointKind::kFingerHole);
  const Joint* stile_left = joint_between(a, "ladder.stile_left", "bed.foot");
  const Joint* stile_right = joint_between(a, "ladder.stile_right", "bed.foot");
  ASSERT_TRUE(stile_left && stile_right);
  EXPECT_FALSE(stile_left->automatic());
  EXPECT_TRUE(stile_right->automatic());
  // The desk and the bed stand on the same floor.
  EXPECT_NEAR(piece(a, "desk.leg_left")->frame(2, 3), 0, 1e-9);
  EXPECT_NEAR(piece(a, "bed.head")->frame(2, 3), 0, 1e-9);

  // The ladder is built first and goes in as one: its five pieces are consecutive in the
  // assembly order, in one sub-assembly (no three pieces of it could go in alone).
  std::vector<int> ladder_steps;
  for (std::size_t k = 0; k < a.assembly.size(); ++k) {
    const std::string& name = a.pieces[static_cast<std::size_t>(a.assembly[k].piece)].name;
    if (name.rfind("ladder.", 0) == 0) ladder_steps.push_back(static_cast<int>(k));
  }
  ASSERT_EQ(ladder_steps.size(), 5u);
  EXPECT_EQ(ladder_steps.back() - ladder_steps.front(), 4);
  const int group = a.assembly[static_cast<std::size_t>(ladder_steps.front())].group;
  EXPECT_NE(group, 0);
  for (int k : ladder_steps) EXPECT_EQ(a.assembly[static_cast<std::size_t>(k)].group, group);

  // Changing the bunk bed's length changes the desk with the bed.
  for (DesignParameter& p : d.parameters) {
    if (p.name == "length") p.value = 320;
  }
  const Analysis longer = check(d);
  ASSERT_FALSE(longer.diagnostics.has_errors()) << longer.diagnostics.format();
  EXPECT_NEAR(longer.values.at("desk.top.l"), 320, 1e-9);
  EXPECT_NEAR(longer.values.at("bed.deck.l"), 320, 1e-9);
  EXPECT_NEAR(longer.values.at("bed.rail.l"), 320, 1e-9);
}

TEST(Composition, TvConsoleUsesOneCabinetFileTwice) {
  const Analysis a = check(test::example("tv_console"));
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_EQ(a.components.size(), 11u);
  EXPECT_NEAR(a.values.at("left.width"), 150, 1e-9);
  EXPECT_NEAR(a.values.at("right.height"), 180, 1e-9);
  // The top rests on both cabinets' sides.
  for (const char* side :
       {"left.side_left", "left.side_right", "right.side_left", "right.side_right"}) {
    const Joint* j = joint_between(a, side, "top");
    ASSERT_NE(j, nullptr) << side;
    EXPECT_EQ(j->kind, JointKind::kFingerHole) << side;
  }
}

TEST(Composition, ThicknessInExpressionsIsTheMaterials) {
  Design d = test::example("box_with_lid");
  Analysis a = check(d);
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_NEAR(a.values.at("thickness"), 3, 1e-9);
  EXPECT_NEAR(a.values.at("rim_front.l"), 200 - 2 * (3 + 0.5), 1e-9);
  d.material.thickness_mm = 6;
  a = check(d);
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_NEAR(a.values.at("rim_front.l"), 200 - 2 * (6 + 0.5), 1e-9);
  // The lid rests on the walls (its mid-plane half a board above their top edges).
  EXPECT_NEAR(piece(a, "lid")->frame(2, 3) - piece(a, "front")->frame(2, 3), 80 + 3, 1e-9);
  // A sub-design's thickness is its material's and cannot be set like a parameter.
  const Analysis b = check_with_examples(
      "fabkit: flatpack/1\nuses: {Stool: box_stool.yaml}\ncomponents:\n"
      "  - {name: s, type: Stool, thickness: 6}\n");
  EXPECT_NE(b.diagnostics.format().find("s.thickness is the board thickness of the material (3 "
                                        "mm) and cannot be constrained"),
            std::string::npos)
      << b.diagnostics.format();
}

TEST(Composition, MistakesInUsingADesignAreNamed) {
  const Analysis a = check_with_examples(
      "fabkit: flatpack/1\nuses: {Stool: box_stool.yaml}\ncomponents:\n"
      "  - {name: s, type: Stool, heigth: 100}\n");
  EXPECT_NE(a.diagnostics.format().find("composite.yaml:4:"), std::string::npos)
      << a.diagnostics.format();
  EXPECT_NE(a.diagnostics.format().find("s (Stool) has no parameter 'heigth'; did you mean "
                                        "'height'?; its parameters are size, height, inset"),
            std::string::npos)
      << a.diagnostics.format();
  const Analysis b = check_with_examples(
      "fabkit: flatpack/1\nuses: {Stool: box_stool.yaml}\ncomponents:\n"
      "  - {name: s, type: Stool}\n  - {name: b, type: Rectangle, l: 10, w: 10}\n"
      "connections:\n  - {connect: [b.b, s.seat_frnt]}\n");
  EXPECT_TRUE(test::has_code(b.diagnostics, codes::kUnknownEdge)) << b.diagnostics.format();
  EXPECT_NE(b.diagnostics.format().find("s (Stool) exports no interface 'seat_frnt'; did you "
                                        "mean 'seat_front'?; it exports foot_left, foot_right,"),
            std::string::npos)
      << b.diagnostics.format();
  Diagnostics read;
  check_with_examples(
      "fabkit: flatpack/1\nuses: {Stool: no_such_stool.yaml}\ncomponents:\n"
      "  - {name: s, type: Stool}\n",
      &read);
  EXPECT_NE(read.format().find("composite.yaml:2:15: error: cannot read design file"),
            std::string::npos)
      << read.format();
  EXPECT_NE(read.format().find("no_such_stool.yaml"), std::string::npos) << read.format();
}

class Files : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = std::filesystem::temp_directory_path() /
          ("fabkit-flatpack-uses-" +
           std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(dir);
  }
  void TearDown() override { std::filesystem::remove_all(dir); }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
  }
  std::filesystem::path dir;
};

TEST_F(Files, ADesignThatUsesItselfIsRefused) {
  write(
      "me.yaml",
      "fabkit: flatpack/1\nname: me\nuses: {Me: me.yaml}\ncomponents:\n  - {name: a, type: Me}\n");
  Diagnostics d;
  load_design(dir / "me.yaml", d);
  ASSERT_TRUE(d.has_errors());
  EXPECT_NE(d.format().find("me.yaml:3:12: error: component type Me (me.yaml) would contain "
                            "itself: me.yaml uses me.yaml; a design cannot be a component of "
                            "itself"),
            std::string::npos)
      << d.format();
}

TEST_F(Files, DesignsThatUseEachOtherAreRefusedWithTheChain) {
  write("a.yaml", "fabkit: flatpack/1\nuses: {B: b.yaml}\ncomponents:\n  - {name: x, type: B}\n");
  write("b.yaml", "fabkit: flatpack/1\nuses: {A: ./a.yaml}\ncomponents:\n  - {name: y, type: A}\n");
  Diagnostics d;
  load_design(dir / "a.yaml", d);
  ASSERT_TRUE(d.has_errors());
  EXPECT_NE(d.format().find("would contain itself: a.yaml uses b.yaml uses a.yaml"),
            std::string::npos)
      << d.format();
  // Read as text (the command line reads the file first), the same refusal once the file is
  // named; without it, one level later, naming the same chain.
  Diagnostics e;
  DesignFileOptions named;
  named.file = dir / "a.yaml";
  load_design_text("fabkit: flatpack/1\nuses: {B: b.yaml}\ncomponents:\n  - {name: x, type: B}\n",
                   (dir / "a.yaml").string(),
                   e,
                   dir,
                   named);
  EXPECT_NE(e.format().find("a.yaml uses b.yaml uses a.yaml"), std::string::npos) << e.format();
}

TEST_F(Files, NestingDeeperThanTheLimitIsRefused) {
  write("c.yaml",
        "fabkit: flatpack/1\ncomponents:\n  - {name: p, type: Rectangle, l: 10, w: 10}\n"
        "interfaces: {edge: p.b}\n");
  write("b.yaml", "fabkit: flatpack/1\nuses: {C: c.yaml}\ncomponents:\n  - {name: c, type: C}\n");
  write("a.yaml", "fabkit: flatpack/1\nuses: {B: b.yaml}\ncomponents:\n  - {name: b, type: B}\n");
  Diagnostics fine;
  const Design d = load_design(dir / "a.yaml", fine);
  ASSERT_FALSE(fine.has_errors()) << fine.format();
  const Analysis a = check(d);
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_EQ(a.components.front().name, "b.c.p");
  Diagnostics limited;
  DesignFileOptions o;
  o.max_depth = 1;
  load_design(dir / "a.yaml", limited, o);
  EXPECT_TRUE(test::has_code(limited, codes::kLimitExceeded)) << limited.format();
  EXPECT_NE(limited.format().find("nest deeper than 1 levels"), std::string::npos)
      << limited.format();
  // Servers refuse `uses:` altogether.
  Diagnostics refused;
  o.allow_uses = false;
  load_design(dir / "a.yaml", refused, o);
  EXPECT_NE(refused.format().find("may not read other files"), std::string::npos)
      << refused.format();
}

}  // namespace
}  // namespace fabkit::flatpack

#include "fabkit/flatpack/design_file.h"

#include <gtest/gtest.h>

#include "test_support.h"

namespace fabkit::flatpack {
namespace {

TEST(DesignFile, RoundTripGivesTheSameDesign) {
  const Design d = test::example("reading_desk");
  const std::string yaml = to_yaml(d);
  Diagnostics diags;
  const Design again = load_design_text(yaml, "round-trip.yaml", diags);
  ASSERT_FALSE(diags.has_errors()) << diags.format() << yaml;
  EXPECT_EQ(to_yaml(again), yaml);
  const Analysis a = check(d), b = check(again);
  ASSERT_EQ(a.pieces.size(), b.pieces.size());
  EXPECT_EQ(a.joints.size(), b.joints.size());
  for (std::size_t i = 0; i < a.pieces.size(); ++i) {
    EXPECT_TRUE(a.pieces[i].frame.isApprox(b.pieces[i].frame, 1e-12));
    EXPECT_NEAR(area(a.pieces[i].cut), area(b.pieces[i].cut), 1e-9);
  }
}

// The newer keys survive the round trip too: joint: none, expressions with the built-in
// thickness, and uses: of other files (read back next to the bundled examples).
TEST(DesignFile, RoundTripKeepsPlacesOnlyConnectionsAndUses) {
  for (const char* name : {"box_with_lid", "bunk_bed", "picnic_table_locked"}) {
    SCOPED_TRACE(name);
    const Design d = test::example(name);
    const std::string yaml = to_yaml(d);
    Diagnostics diags;
    const Design again = load_design_text(
        yaml, "round-trip.yaml", diags, std::string(FABKIT_SOURCE_DIR) + "/examples/flatpack");
    ASSERT_FALSE(diags.has_errors()) << diags.format() << yaml;
    EXPECT_EQ(to_yaml(again), yaml);
    const Analysis a = check(d), b = check(again);
    ASSERT_EQ(a.pieces.size(), b.pieces.size());
    EXPECT_EQ(a.joints.size(), b.joints.size());
    EXPECT_EQ(a.not_insertable, b.not_insertable);
    for (std::size_t i = 0; i < a.pieces.size(); ++i) {
      EXPECT_TRUE(a.pieces[i].frame.isApprox(b.pieces[i].frame, 1e-12));
      EXPECT_NEAR(area(a.pieces[i].cut), area(b.pieces[i].cut), 1e-9);
    }
  }
  const std::string lid = to_yaml(test::example("box_with_lid"));
  EXPECT_NE(lid.find("joint: none"), std::string::npos) << lid;
  Diagnostics d;
  load_design_text(
      "fabkit: flatpack/1\nconnections:\n  - {connect: [A.b, B.t], joint: glue}\n", "bad.yaml", d);
  EXPECT_NE(d.format().find("bad.yaml:3:34: error: joint: 'glue' is not known"), std::string::npos)
      << d.format();
}

TEST(DesignFile, ErrorsNameFileLineAndWhatWasExpected) {
  Diagnostics d;
  load_design_text(
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 3}\nconections: []\n",
      "bad.yaml",
      d);
  EXPECT_NE(d.format().find("bad.yaml:4:1"), std::string::npos) << d.format();
  EXPECT_NE(d.format().find("did you mean 'connections'"), std::string::npos) << d.format();
  Diagnostics e;
  load_design_text("fabkit: flatpack/1\nconnections:\n  - {connect: [A, B.b]}\n", "bad.yaml", e);
  EXPECT_NE(e.format().find("bad.yaml:3:"), std::string::npos) << e.format();
  EXPECT_NE(e.format().find("component.edge"), std::string::npos) << e.format();
  Diagnostics f;
  load_design_text("fabkit: hacks/1\n", "other.yaml", f);
  EXPECT_NE(f.format().find("the flatpack kit reads flatpack/1"), std::string::npos) << f.format();
}

TEST(DesignFile, UnknownEdgeGetsDidYouMean) {
  const Analysis a = test::check_yaml(
      "fabkit: flatpack/1\ncomponents:\n  - {name: A, type: Rectangle, l: 3, w: 3}\n  - {name: B, "
      "type: Rectangle, l: 3, w: 3}\n"
      "connections:\n  - {connect: [A.top, B.b]}\n");
  EXPECT_NE(a.diagnostics.format().find("A (Rectangle) has no edge 'top'"), std::string::npos)
      << a.diagnostics.format();
}

}  // namespace
}  // namespace fabkit::flatpack

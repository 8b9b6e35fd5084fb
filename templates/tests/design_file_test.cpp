// The kit's YAML files: every kind of bad input gets a diagnostic with file:line, never a crash.
#include "fabkit/templates/design_file.h"

#include <gtest/gtest.h>

#include <chrono>
#include <fstream>
#include <sstream>

#include "fabkit/templates/check.h"
#include "fabkit/templates/database.h"
#include "fabkit/templates/diagnostic_codes.h"
#include "fabkit/templates/extract.h"
#include "test_support.h"

namespace fabkit::templates {
namespace {

using testing::has_diagnostic;

constexpr const char* kHeader = "fabkit: templates/1\n";

int line_of(const Diagnostics& d, DiagnosticCode code) {
  for (const Diagnostic& x : d) {
    if (x.code == code) return x.where.line;
  }
  return -1;
}

TEST(DesignFile, ShorthandsExpandIntoParts) {
  Diagnostics d;
  const auto design =
      read_source_design(std::string(kHeader) +
                             "design: legs\n"
                             "parts:\n"
                             "  - name: leg\n"
                             "    item: LUM-PINE-2x2\n"
                             "    min: [100, 100, 0]\n"
                             "    size: [38, 38, 700]\n"
                             "    mirror: [x, y]\n"
                             "    names: [a, b, c, d]\n"
                             "  - {name: s, item: SCR-4x40, role: connecting, center: [0, 0, 0], "
                             "size: [8, 8, 40], repeat: {count: [3, 1, 1], step: [20, 0, 0]}}\n",
                         "legs.yaml",
                         d);
  ASSERT_TRUE(design) << d.format();
  ASSERT_EQ(design->parts.size(), 7u);
  EXPECT_EQ(design->find("d")->box.center, Vec3(-119, -119, 350));
  EXPECT_EQ(design->find("s_3")->box.center, Vec3(40, 0, 0));
  EXPECT_EQ(design->find("s_1")->role, PartRole::kConnecting);
}

TEST(DesignFile, BadDesignsNameLineAndValue) {
  Diagnostics d;
  EXPECT_FALSE(read_source_design(
      std::string(kHeader) +
          "design: x\n"
          "parts:\n"
          "  - {name: a, item: LUM-PINE-2x2, centre: [0, 0, 0], size: [38, 38, 100]}\n"
          "  - {name: b, item: LUM-PINE-2x2, center: [0, 0, 0]}\n"
          "  - {name: c, item: LUM-PINE-2x2, center: [0, 0, 0], size: [38, -38, 100]}\n"
          "  - {name: e, item: X, role: glue, center: [0, 0, 0], size: [1, 1, 1]}\n"
          "  - {name: e, item: X, center: [0, 0, 0], size: [1, 1, 1]}\n"
          "articulations:\n"
          "  - {name: door, type: slide, parts: [doorr], axis: q, limits: [0, 90]}\n",
      "x.yaml",
      d));
  EXPECT_TRUE(has_diagnostic(
      d, codes::kUnknownName, "unknown key 'centre' in a part; did you mean 'center'?"));
  EXPECT_TRUE(has_diagnostic(d, codes::kMalformedInput, "a part's box is 'center' + 'size'"));
  EXPECT_TRUE(has_diagnostic(d, codes::kInvalidValue, "size"));
  EXPECT_TRUE(
      has_diagnostic(d, codes::kInvalidValue, "role 'glue' must be principal or connecting"));
  EXPECT_TRUE(has_diagnostic(d, codes::kDuplicateName, "part 'e' is defined twice"));
  EXPECT_TRUE(has_diagnostic(
      d, codes::kInvalidValue, "joint type 'slide' must be prismatic, hinge or ball"));
  EXPECT_TRUE(has_diagnostic(d, codes::kInvalidValue, "axis 'q' must be x, y or z"));
  EXPECT_TRUE(
      has_diagnostic(d, codes::kUnknownName, "articulation 'door' moves unknown part 'doorr'"));
  EXPECT_EQ(line_of(d, codes::kDuplicateName), 8);
}

// Keys that take a mapping given a scalar or a list (the fuzzer found `repeat: op_screw`,
// which aborted the reader): a diagnostic at the key's line, never a crash.
TEST(DesignFile, AMappingKeyGivenAScalarOrAListIsReported) {
  for (const char* repeat : {"op_screw", "[1, 2, 3]", "3"}) {
    SCOPED_TRACE(repeat);
    Diagnostics d;
    read_source_design(std::string(kHeader) +
                           "design: x\n"
                           "parts:\n"
                           "  - name: shelf\n"
                           "    item: PLY-BIRCH-18\n"
                           "    center: [0, 0, 518]\n"
                           "    size: [764, 300, 18]\n"
                           "    repeat: " +
                           std::string(repeat) + "\n",
                       "x.yaml",
                       d);
    ASSERT_TRUE(d.has_errors()) << d.format();
    EXPECT_TRUE(has_diagnostic(d, codes::kMalformedInput, "repeat")) << d.format();
    EXPECT_EQ(line_of(d, codes::kMalformedInput), 8) << d.format();
  }
}

TEST(DesignFile, ItemsMustMakeTheParts) {
  Diagnostics d;
  const auto design = read_source_design(
      std::string(kHeader) +
          "design: x\n"
          "parts:\n"
          "  - {name: a, item: LUM-PINE-2x4, center: [0, 0, 0], size: [40, 89, 500]}\n"
          "  - {name: b, item: LUM-PINE-2x4, center: [0, 0, 600], size: [38, 89, 4000]}\n"
          "  - {name: c, item: LUM-PINE-2x5, center: [0, 0, 900], size: [38, 89, 100]}\n",
      "x.yaml",
      d);
  ASSERT_TRUE(design) << d.format();
  EXPECT_FALSE(make_template(*design, &ItemCatalog::bundled(), d));
  EXPECT_TRUE(
      has_diagnostic(d,
                     codes::kItemMismatch,
                     "part 'a': a 40 x 89 x 500 mm piece cannot be made from item LUM-PINE-2x4"));
  EXPECT_TRUE(has_diagnostic(d, codes::kItemMismatch, "part 'b': a 38 x 89 x 4000 mm piece"));
  EXPECT_TRUE(has_diagnostic(
      d, codes::kUnknownItem, "part 'c': unknown item 'LUM-PINE-2x5'; did you mean 'LUM-PINE-2x"));
  EXPECT_EQ(line_of(d, codes::kUnknownItem), 6);
}

TEST(DesignFile, HingeRestPosesMustBeQuarterTurns) {
  Diagnostics d;
  const auto design = read_source_design(
      std::string(kHeader) +
          "design: x\n"
          "parts:\n"
          "  - {name: door, item: PLY-BIRCH-18, center: [0, 0, 400], size: [600, 18, 800]}\n"
          "articulations:\n"
          "  - {name: hinge, type: hinge, parts: [door], axis: z, pivot: [-300, 0, 0], limits: [0, "
          "110]}\n",
      "x.yaml",
      d);
  ASSERT_TRUE(design);
  ASSERT_TRUE(make_template(*design, &ItemCatalog::bundled(), d));
  EXPECT_TRUE(has_diagnostic(
      d, codes::kInvalidValue, "the rest poses differ by 110°, not a multiple of 90°"));
}

TEST(ModelFile, BadModelsNameLineAndValue) {
  Diagnostics d;
  EXPECT_FALSE(read_model_file(std::string(kHeader) +
                                   "model:\n"
                                   "  - {use: dining_table, as: t, set: {width: 5}}\n"
                                   "  - {use: bench, as: t}\n"
                                   "adjust:\n"
                                   "  - {node: t, control: size_x}\n"
                                   "loads:\n"
                                   "  - {part: top, at: [0, 0, 0], force: [0, 0, .nan]}\n"
                                   "frction: 0.4\n",
                               "m.yaml",
                               d));
  EXPECT_TRUE(has_diagnostic(d, codes::kUnknownName, "unknown control 'width'"));
  EXPECT_TRUE(has_diagnostic(d, codes::kDuplicateName, "'t' is already in the model"));
  EXPECT_TRUE(has_diagnostic(d, codes::kMalformedInput, "an adjustment needs 'to'"));
  EXPECT_TRUE(has_diagnostic(d, codes::kInvalidValue, "not a finite number"));
  EXPECT_TRUE(has_diagnostic(
      d, codes::kUnknownName, "unknown key 'frction' in a model; did you mean 'friction'?"));
  EXPECT_EQ(line_of(d, codes::kDuplicateName), 4);
}

// `remove:` deletes a node after composition (paper §4.3): the leg's brackets and screws go with
// it; on three legs the table still stands at rest (a tripod), but someone leaning on the corner
// above the missing leg (300 N) tips it.
TEST(ModelFile, RemovingALegMakesTheTableTip) {
  const std::string base = std::string(kHeader) +
                           "model:\n  - {use: dining_table, as: table}\n"
                           "loads:\n  - {part: top, at: [-780, -430, 750], force: [0, 0, -300]}\n";
  const ComposedModel whole = compose_model(base, "m.yaml", TemplateDatabase::bundled());
  const ComposedModel three_legs =
      compose_model(base + "remove: [leg_fl]\n", "m.yaml", TemplateDatabase::bundled());
  ASSERT_TRUE(whole.readable) << whole.diagnostics.format();
  ASSERT_TRUE(three_legs.readable) << three_legs.diagnostics.format();
  const Template& t = three_legs.model.model();
  EXPECT_FALSE(t.find_node_or_element("leg_fl").valid());
  // One 4x4 leg, plus the connectors that held it (two L-brackets with four screws each).
  EXPECT_GE(whole.model.model().part_count() - t.part_count(), 1 + 2 * 5);
  EXPECT_EQ(three_legs.steps.back().text, "remove leg_fl");
  EXPECT_EQ(t.max_violation(), t.max_violation());  // finite
  EXPECT_LT(t.max_violation(), 1e-6);
  const CheckResult ok = check(whole, TemplateDatabase::bundled());
  const CheckResult tips = check(three_legs, TemplateDatabase::bundled());
  EXPECT_TRUE(ok.stability.stable) << ok.diagnostics.format();
  EXPECT_FALSE(tips.stability.stable);
  EXPECT_EQ(tips.verdict, "unstable");
  const ComposedModel at_rest = compose_model(std::string(kHeader) +
                                                  "model:\n  - {use: dining_table, as: table}\n"
                                                  "remove: [leg_fl]\n",
                                              "m.yaml",
                                              TemplateDatabase::bundled());
  EXPECT_TRUE(check(at_rest, TemplateDatabase::bundled()).stability.stable);

  const ComposedModel bad =
      compose_model(base + "remove: [leg_xx]\n", "m.yaml", TemplateDatabase::bundled());
  EXPECT_TRUE(has_diagnostic(bad.diagnostics, codes::kUnknownName, "no node 'leg_xx' to remove"));
  EXPECT_EQ(line_of(bad.diagnostics, codes::kUnknownName), 6);
}

TEST(ModelFile, UnknownControlNamesAreEchoedShortAndReadable) {
  // Found by fuzz/templates_model_fuzzer: a control name with control characters and invalid
  // UTF-8 was echoed as it was.
  Diagnostics d;
  EXPECT_FALSE(read_model_file(std::string(kHeader) +
                                   "model:\n"
                                   "  - {use: bench, as: b, set: {si\xffze: 5}}\n"
                                   "  - {use: bench, as: c, set: {" +
                                   std::string(1000, 'w') + ": 5}}\n",
                               "m.yaml",
                               d));
  EXPECT_TRUE(has_diagnostic(d, codes::kUnknownName, "unknown control 'si\uFFFDze'")) << d.format();
  EXPECT_TRUE(has_diagnostic(d, codes::kUnknownName, "(940 more bytes)")) << d.format();
  for (const Diagnostic& x : d) EXPECT_LT(x.message.size(), 400u) << x.message;
}

TEST(ModelFile, ComposingReportsUnknownTemplatesNodesAndParts) {
  const ComposedModel cm = compose_model(std::string(kHeader) +
                                             "model:\n"
                                             "  - {use: dining_table, as: table}\n"
                                             "  - {use: bookshelf/shelvs, as: shelf}\n"
                                             "adjust:\n"
                                             "  - {node: tabel, control: size_x, to: 1200}\n"
                                             "  - {node: top, control: size_z, to: 40}\n"
                                             "loads:\n"
                                             "  - {part: tpo, at: [0, 0, 0], force: [0, 0, -10]}\n",
                                         "m.yaml",
                                         TemplateDatabase::bundled());
  EXPECT_FALSE(cm.readable);
  EXPECT_TRUE(has_diagnostic(cm.diagnostics,
                             codes::kUnknownTemplate,
                             "design 'bookshelf' has no node 'shelvs'; did you mean 'shelves'?"));
  EXPECT_EQ(line_of(cm.diagnostics, codes::kUnknownTemplate), 4);
  EXPECT_TRUE(has_diagnostic(
      cm.diagnostics, codes::kUnknownName, "the model has no node 'tabel'; did you mean 'table'?"));
  EXPECT_TRUE(
      has_diagnostic(cm.diagnostics, codes::kFixedControl, "size_z of 'top' cannot change"));
  EXPECT_TRUE(has_diagnostic(
      cm.diagnostics,
      codes::kUnknownName,
      "a load names part 'tpo', which the model does not have; did you mean 'top'?"));
}

TEST(ModelFile, NotYamlOrNotTemplates) {
  Diagnostics d;
  EXPECT_FALSE(templates_file_kind("fabkit: hacks/1\nparts: []\n", "h.yaml", d));
  EXPECT_TRUE(has_diagnostic(d, codes::kUnknownKit, "unknown kit 'hacks/1'"));
  Diagnostics d2;
  EXPECT_FALSE(templates_file_kind(std::string(kHeader) + "name: x\n", "x.yaml", d2));
  EXPECT_TRUE(has_diagnostic(d2, codes::kMalformedInput, "needs 'model:'"));
  Diagnostics d3;
  EXPECT_FALSE(read_model_file("fabkit: templates/1\nmodel: [\n", "x.yaml", d3));
  EXPECT_TRUE(has_diagnostic(d3, codes::kMalformedInput, "YAML syntax error"));
}

// Wherever a deadline falls in a composition or its check — between steps, inside a snap or a
// connect, inside the stability solve — what is reported is the time limit, never an
// infeasibility or an unknown name the cut left behind (issue 10). The deadline is placed at
// fractions of the unlimited run's time; no time is asserted.
TEST(DesignFile, ADeadlineAnywhereReportsOnlyTheTimeLimit) {
  using Clock = std::chrono::steady_clock;
  for (const char* example : {"bench_with_backrest", "table_with_shelf", "cabinet_on_wheels"}) {
    std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/examples/templates/" + example + ".yaml");
    std::stringstream text;
    text << in.rdbuf();
    ASSERT_FALSE(text.str().empty()) << example;
    const auto start = Clock::now();
    const ComposedModel whole = compose_model(text.str(), example, TemplateDatabase::bundled());
    const CheckResult checked = check(whole, TemplateDatabase::bundled());
    const auto full = Clock::now() - start;
    ASSERT_FALSE(whole.diagnostics.has_errors()) << example << whole.diagnostics.format();
    ASSERT_FALSE(checked.diagnostics.has_errors()) << example << checked.diagnostics.format();
    for (int k = 0; k <= 10; ++k) {
      CheckOptions o;
      o.deadline = Clock::now() + full * k / 10;
      const ComposedModel cm = compose_model(text.str(), example, TemplateDatabase::bundled(), o);
      const CheckResult r = check(cm, TemplateDatabase::bundled(), o);
      for (const Diagnostic& d : r.diagnostics) {  // the composition's, then the checks'
        if (d.severity != Severity::kError) continue;
        EXPECT_EQ(d.kind(), DiagnosticClass::kTimeout)
            << example << " at " << k << "/10 of its time: " << d.message << "\n"
            << r.diagnostics.format();
      }
    }
  }
}

}  // namespace
}  // namespace fabkit::templates

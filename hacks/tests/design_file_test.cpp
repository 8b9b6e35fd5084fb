// Design files: every kind of bad input gets a clear diagnostic with file:line, never a crash.
#include "fabkit/hacks/design_file.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "fabkit/hacks/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::has_diagnostic;
using testing::load_text;

constexpr const char* kEnv = R"(environment:
  - {name: door, primitives: {rod: {type: rod, radius: 5, length: 500}}, frame: {pos: [0, 0, 500], rot: [90, 0, 90]}}
)";

TEST(DesignFile, MinimalDesignBuilds) {
  const Design d = load_text(std::string(kEnv) + R"(parts:
  - {name: s, part: DoubleHook}
target: {name: mug, part: Mug, primitive: hook, frame: {pos: [0, 0, 400], rot: [0, 0, 0]}}
connections:
  - connect: [s.hook1, door.rod]
  - {connect: [mug.hook, s.hook2], alignment: flip}
)");
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  EXPECT_EQ(d.assembly.part_count(), 3);
  EXPECT_EQ(d.assembly.connections()[1].alignment, AlignmentChoice::kFlip);
  ASSERT_TRUE(d.assembly.target());
  EXPECT_EQ(d.assembly.target()->part, d.parts.at("mug"));
  EXPECT_EQ(d.steps.size(), 4u);  // add, two connects, end_with
}

TEST(DesignFile, YamlSyntaxErrorHasLine) {
  const Design d = load_text("environment:\n  - {name: door, part: [\n");
  EXPECT_FALSE(d.readable);
  ASSERT_FALSE(d.diagnostics.empty());
  EXPECT_EQ(d.diagnostics.items()[0].code, codes::kMalformedInput);
  EXPECT_EQ(d.diagnostics.items()[0].where.file, "test.yaml");
  EXPECT_GE(d.diagnostics.items()[0].where.line, 2);
  EXPECT_NE(d.diagnostics.format().find("YAML syntax error"), std::string::npos);
}

TEST(DesignFile, NotAMapping) {
  EXPECT_TRUE(has_diagnostic(load_text("- just\n- a list\n").diagnostics,
                             codes::kMalformedInput,
                             "must be a YAML mapping",
                             1));
  EXPECT_TRUE(
      has_diagnostic(load_text("").diagnostics, codes::kMalformedInput, "must be a YAML mapping"));
}

TEST(DesignFile, UnknownPartWithSuggestion) {
  const Design d = load_text(std::string(kEnv) + "parts:\n  - {name: s, part: DoubleHok}\n");
  EXPECT_FALSE(d.readable);
  EXPECT_TRUE(has_diagnostic(d.diagnostics, codes::kUnknownPart, "DoubleHok", 4));
  EXPECT_TRUE(has_diagnostic(d.diagnostics, codes::kUnknownPart, "DoubleHook"));
}

TEST(DesignFile, UnknownPrimitiveNamesTheAlternatives) {
  const Design d = load_text(std::string(kEnv) + R"(parts:
  - {name: s, part: DoubleHook}
connections:
  - connect: [s.hook3, door.rod]
)");
  EXPECT_TRUE(has_diagnostic(d.diagnostics,
                             codes::kUnknownPrimitive,
                             "s (DoubleHook) has no primitive 'hook3' (it has hook1, hook2)",
                             6));
}

TEST(DesignFile, UnknownPartNameInConnection) {
  const Design d = load_text(std::string(kEnv) + R"(parts:
  - {name: shook, part: DoubleHook}
connections:
  - connect: [shok.hook1, door.rod]
)");
  EXPECT_TRUE(has_diagnostic(d.diagnostics,
                             codes::kUnknownName,
                             "no part named 'shok' in this design; did you mean 'shook'?",
                             6));
}

TEST(DesignFile, NaNNegativeAndAbsurdSizes) {
  const Design nan = load_text(R"(environment:
  - {name: door, primitives: {rod: {type: rod, radius: .nan, length: 500}}}
)");
  EXPECT_TRUE(has_diagnostic(
      nan.diagnostics, codes::kInvalidValue, "door.rod radius is .nan, not a finite number", 2));
  const Design negative = load_text(R"(environment:
  - {name: door, primitives: {rod: {type: rod, radius: -5, length: 500}}}
)");
  EXPECT_TRUE(has_diagnostic(negative.diagnostics,
                             codes::kInvalidValue,
                             "door.rod: rod radius -5 mm must be positive",
                             2));
  const Design absurd = load_text(R"(environment:
  - {name: door, primitives: {rod: {type: rod, radius: 5, length: 5e9}}}
)");
  EXPECT_TRUE(has_diagnostic(absurd.diagnostics, codes::kInvalidValue, "absurd", 2));
  const Design far = load_text(R"(environment:
  - {name: door, primitives: {rod: {type: rod, radius: 5, length: 500}}, frame: {pos: [0, 0, 1e12]}}
)");
  EXPECT_TRUE(has_diagnostic(
      far.diagnostics, codes::kInvalidValue, "door pos 1e+12 mm is out of range", 2));
}

// A primitive that cannot be read is one error, where it is written: connects to it are not
// reported again as "has no primitive" (the environment has none it could name).
TEST(DesignFile, AnUnreadablePrimitiveIsReportedOnce) {
  const Design d = load_text(R"(environment:
  - {name: door, primitives: {rod: {type: rod, radius: -4, length: 500}}}
parts:
  - {name: s, part: DoubleHook}
connections:
  - connect: [s.hook1, door.rod]
)");
  EXPECT_TRUE(has_diagnostic(
      d.diagnostics, codes::kInvalidValue, "door.rod: rod radius -4 mm must be positive", 2));
  const auto errors = std::count_if(d.diagnostics.begin(), d.diagnostics.end(), [](const auto& x) {
    return x.severity == Severity::kError;
  });
  EXPECT_EQ(errors, 1) << d.diagnostics.format();
}

TEST(DesignFile, BadParametersOfParametricParts) {
  const Design d = load_text(std::string(kEnv) + R"(parts:
  - {name: t, part: ParamTurnbuckle, params: {extended_length: -3}}
  - {name: u, part: ParamTurnbuckle, params: {length: 3}}
  - {name: v, part: ParamTurnbuckle, params: {extended_length: abc}}
)");
  EXPECT_TRUE(has_diagnostic(d.diagnostics, codes::kInvalidValue, "extended_length", 4));
  EXPECT_TRUE(has_diagnostic(d.diagnostics, codes::kUnknownName, "length", 5));
  EXPECT_TRUE(has_diagnostic(d.diagnostics,
                             codes::kMalformedInput,
                             "parameter extended_length must be a number, not 'abc'",
                             6));
}

TEST(DesignFile, StructuralMistakes) {
  EXPECT_TRUE(has_diagnostic(
      load_text("parts: []\n").diagnostics, codes::kMalformedInput, "has no 'environment'"));
  EXPECT_TRUE(has_diagnostic(load_text(std::string(kEnv) + "colour: red\n").diagnostics,
                             codes::kUnknownName,
                             "unknown key 'colour'",
                             3));
  EXPECT_TRUE(has_diagnostic(
      load_text(std::string(kEnv) + "connections:\n  - connect: [door.rod]\n").diagnostics,
      codes::kMalformedInput,
      "connect: [part.primitive, part.primitive]",
      4));
  EXPECT_TRUE(has_diagnostic(
      load_text(std::string(kEnv) + "parts:\n  - {name: door, part: DoubleHook}\n").diagnostics,
      codes::kDuplicateName,
      "the name 'door' is used twice (first on line 2)",
      4));
  EXPECT_TRUE(has_diagnostic(
      load_text(std::string(kEnv) + "parts:\n  - {name: s, part: DoubleHook}\nconnections:\n"
                                    "  - {connect: [s.hook1, door.rod], alignment: sideways}\n")
          .diagnostics,
      codes::kUnknownName,
      "alignment must be 'default' or 'flip', not 'sideways'",
      6));
  EXPECT_TRUE(has_diagnostic(
      load_text(std::string(kEnv) + "target: {name: ghost, frame: {pos: [0, 0, 0]}}\n").diagnostics,
      codes::kUnknownName,
      "target 'ghost'",
      3));
  EXPECT_TRUE(has_diagnostic(
      load_text(std::string(kEnv) + "parts:\n  - {name: s, part: DoubleHook}\nconnections:\n"
                                    "  - {connect: [s.hook1, door.rod], fixed: maybe}\n")
          .diagnostics,
      codes::kMalformedInput,
      "fixed must be true or false",
      6));
}

TEST(DesignFile, LaterStepsAfterAFailedConnectAreSkippedWithANote) {
  const Design d = load_text(std::string(kEnv) + R"(parts:
  - {name: big, part: LongTensionRod}
  - {name: s, part: DoubleHook}
  - {name: t, part: DoubleHook}
  - {name: u, part: DoubleHook}
connections:
  - connect: [s.hook1, door.rod]
  - connect: [t.hook1, big.rod]
  - connect: [u.hook1, t.hook2]
  - connect: [t.hook2, s.hook2]
)");
  ASSERT_TRUE(d.readable);
  EXPECT_TRUE(d.steps[1].accepted);
  EXPECT_FALSE(d.steps[2].accepted);  // neither t nor big is in the assembly
  EXPECT_TRUE(has_diagnostic(
      d.diagnostics, codes::kNotInAssembly, "neither t (DoubleHook) nor big (LongTensionRod)", 10));
  EXPECT_TRUE(d.steps[3].skipped);  // u and t: t is out because of the step before
  EXPECT_FALSE(d.diagnostics.items()[1].severity == Severity::kError);
  EXPECT_NE(d.diagnostics.items()[1].message.find("skipped connect u.hook1, t.hook2: t is not in "
                                                  "the assembly because an earlier connect failed"),
            std::string::npos)
      << d.diagnostics.format();
  EXPECT_TRUE(d.steps[4].accepted);  // t comes in here instead
}

TEST(DesignFile, DirectoryIsNotADesign) {
  const Design d =
      load_design(std::string(FABKIT_SOURCE_DIR) + "/examples", PartsLibrary::builtin());
  EXPECT_FALSE(d.readable);
  EXPECT_TRUE(has_diagnostic(d.diagnostics,
                             codes::kUnreadableFile,
                             "cannot read design file '" + std::string(FABKIT_SOURCE_DIR) +
                                 "/examples': it is a directory"));
}

TEST(DesignFile, UnreadableFile) {
  const Design d = load_design("/nonexistent/dir/design.yaml", PartsLibrary::builtin());
  EXPECT_FALSE(d.readable);
  EXPECT_TRUE(
      has_diagnostic(d.diagnostics,
                     codes::kUnreadableFile,
                     "cannot read design file '/nonexistent/dir/design.yaml': no such file"));
}

TEST(DesignFile, UnconnectedPartIsAWarning) {
  const Design d = load_text(std::string(kEnv) + R"(parts:
  - {name: s, part: DoubleHook}
  - {name: spare, part: DoubleHook}
connections:
  - connect: [s.hook1, door.rod]
)");
  EXPECT_TRUE(d.feasible());
  ASSERT_FALSE(d.diagnostics.empty());
  EXPECT_EQ(d.diagnostics.items().back().severity, Severity::kWarning);
  EXPECT_EQ(d.diagnostics.items().back().where.line, 5);
}

}  // namespace
}  // namespace fabkit::hacks

namespace fabkit::hacks {
namespace {

// A user part file named by the design works like a built-in part.
TEST(DesignFile, PartFilesAddUserParts) {
  const std::string yaml = R"(part_files: [../parts/wall_bracket.yaml]
environment:
  - {name: wall, part: WallBracket}
parts:
  - {name: s, part: DoubleHook}
connections:
  - connect: [s.hook1, wall.lip]
)";
  const Design d =
      load_design_text(yaml,
                       "user.yaml",
                       PartsLibrary::builtin(),
                       {},
                       std::filesystem::path(FABKIT_SOURCE_DIR) / "examples" / "hacks");
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  EXPECT_EQ(d.assembly.part_count(), 2);
  // The built-in library is not changed by a design's part files.
  EXPECT_EQ(PartsLibrary::builtin().find("WallBracket"), nullptr);
  const Design missing = load_text("part_files: [nowhere.yaml]\nenvironment: []\n");
  EXPECT_TRUE(testing::has_diagnostic(missing.diagnostics, codes::kUnreadableFile, "nowhere.yaml"));
}

}  // namespace
}  // namespace fabkit::hacks

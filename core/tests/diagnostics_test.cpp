#include "fabkit/core/diagnostics.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "fabkit/core/text.h"

namespace fabkit {
namespace {

TEST(Diagnostics, FormatsFileLineAndSeverity) {
  Diagnostic d{Severity::kError,
               codes::kInvalidValue,
               "hook too small",
               SourceLocation{"design.yaml", 12, 5}};
  EXPECT_EQ(d.format(), "design.yaml:12:5: error: hook too small");
  d.where = {};
  EXPECT_EQ(d.format(), "error: hook too small");
  d.where = SourceLocation{"parts.yaml", 3, 0};
  d.severity = Severity::kWarning;
  EXPECT_EQ(d.format(), "parts.yaml:3: warning: hook too small");
}

TEST(Diagnostics, ErrorsAndWarnings) {
  Diagnostics ds;
  ds.warning(codes::kUnknownName, "unused part");
  EXPECT_FALSE(ds.has_errors());
  EXPECT_FALSE(ds.deciding_class().has_value());
  ds.error(codes::kUnknownName, "no such part");
  EXPECT_TRUE(ds.has_errors());
  EXPECT_EQ(ds.size(), 2u);
  EXPECT_EQ(ds.format(), "warning: unused part\nerror: no such part\n");
}

TEST(Diagnostics, CodesHaveUniqueSpellings) {
  std::set<std::string> names;
  for (const DiagnosticCode& c : core_codes()) {
    EXPECT_TRUE(names.insert(std::string(c.name)).second) << c.name;
    EXPECT_FALSE(c.name.empty());
  }
}

TEST(Diagnostics, TheClassDecidesTheOutcome) {
  // An input error outranks everything: the rest means little until the input is fixed.
  constexpr DiagnosticCode infeasible{"test-infeasible", DiagnosticClass::kInfeasible};
  constexpr DiagnosticCode falls{"test-falls", DiagnosticClass::kFallsApart};
  Diagnostics ds;
  ds.error(falls, "slides off");
  EXPECT_EQ(ds.deciding_class(), DiagnosticClass::kFallsApart);
  ds.error(infeasible, "cannot close");
  EXPECT_EQ(ds.deciding_class(), DiagnosticClass::kInfeasible);
  ds.error(codes::kTimeLimit, "stopped");
  EXPECT_EQ(ds.deciding_class(), DiagnosticClass::kTimeout);
  ds.error(codes::kWriteFailed, "disk full");
  EXPECT_EQ(ds.deciding_class(), DiagnosticClass::kIo);
  ds.error(codes::kMalformedInput, "syntax");
  EXPECT_EQ(ds.deciding_class(), DiagnosticClass::kInput);
  // Warnings never decide.
  Diagnostics w;
  w.warning(codes::kMalformedInput, "odd");
  EXPECT_FALSE(w.deciding_class().has_value());
}

TEST(Diagnostics, MessagesAreMadeValidUtf8WhereTheyAreAdded) {
  // Found by fuzz/hacks_design_fuzzer: yaml-cpp's "unknown escape character" quotes the raw
  // byte of the file, which need not be UTF-8, and JSON encoding of such a message failed.
  Diagnostics ds;
  ds.error(codes::kMalformedInput,
           "YAML syntax error: unknown escape character: \xff",
           SourceLocation{"bad\xc3.yaml", 3, 4});
  ds.warning(codes::kUnknownName, "unknown control 'si\xed\xa0\x80ze'");
  ds.add(Diagnostic{Severity::kNote, codes::kInvalidValue, "caf\xc3\xa9 \x80", {}});
  ASSERT_EQ(ds.size(), 3u);
  EXPECT_EQ(ds.items()[0].message, "YAML syntax error: unknown escape character: \uFFFD");
  EXPECT_EQ(ds.items()[0].where.file, "bad\uFFFD.yaml");
  // A surrogate's three bytes are three replacement characters; valid text is kept as it is.
  EXPECT_EQ(ds.items()[1].message, "unknown control 'si\uFFFD\uFFFD\uFFFDze'");
  EXPECT_EQ(ds.items()[2].message, "caf\u00e9 \uFFFD");
  for (const Diagnostic& d : ds) EXPECT_TRUE(is_valid_utf8(d.message)) << d.message;
}

}  // namespace
}  // namespace fabkit

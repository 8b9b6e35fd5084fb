#include "fabkit/core/diagnostics.h"

#include <gtest/gtest.h>

#include <set>
#include <string>

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

}  // namespace
}  // namespace fabkit

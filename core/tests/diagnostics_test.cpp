#include "fabkit/core/diagnostics.h"

#include <gtest/gtest.h>

namespace fabkit {
namespace {

TEST(Diagnostics, FormatsFileLineAndSeverity) {
  Diagnostic d{Severity::kError,
               DiagnosticCode::kDimensionMismatch,
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
  ds.warning(DiagnosticCode::kNotConnected, "unused part");
  EXPECT_FALSE(ds.has_errors());
  ds.error(DiagnosticCode::kUnknownPart, "no such part");
  EXPECT_TRUE(ds.has_errors());
  EXPECT_EQ(ds.size(), 2u);
  EXPECT_EQ(ds.format(), "warning: unused part\nerror: no such part\n");
}

TEST(Diagnostics, CodesRoundTripThroughStrings) {
  for (int i = 0; i <= static_cast<int>(DiagnosticCode::kNotConnected); ++i) {
    const auto code = static_cast<DiagnosticCode>(i);
    const auto parsed = diagnostic_code_from_string(to_string(code));
    ASSERT_TRUE(parsed.has_value()) << to_string(code);
    EXPECT_EQ(*parsed, code);
  }
  EXPECT_FALSE(diagnostic_code_from_string("no-such-code").has_value());
}

}  // namespace
}  // namespace fabkit

#include <gtest/gtest.h>

#include "fabkit/flatpack/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

using test::check_yaml;
using test::has_code;

const char* kHead = "fabkit: flatpack/1\nparameters:\n  l1: 30\n  l2: {value: 60, type: length}\n";

TEST(Constraints, LinearExpressionsAndOwnConstraintsSolve) {
  const Analysis a =
      check_yaml(std::string(kHead) +
                 "components:\n  - {name: A, type: Rectangle}\n  - {name: B, type: Square}\n"
                 "constraints:\n  - A.l = l1\n  - A.w = 2*l2 + 10\n  - B.l + A.l = 100\n");
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_NEAR(a.values.at("A.w"), 130, 1e-9);
  EXPECT_NEAR(a.values.at("B.l"), 70, 1e-9);
  EXPECT_NEAR(a.values.at("B.w"), 70, 1e-9);  // the square's own w = l
}

TEST(Constraints, NonlinearOwnConstraintGivesTheHypotenuse) {
  const Analysis a = check_yaml(std::string(kHead) +
                                "components:\n  - {name: T, type: RightTriangle, w: 30, c: 50}\n");
  ASSERT_FALSE(a.diagnostics.has_errors()) << a.diagnostics.format();
  EXPECT_NEAR(a.values.at("T.h"), 40, 1e-6);
}

TEST(Constraints, UnderConstrainedNamesTheFreeQuantities) {
  const Analysis a = check_yaml(
      std::string(kHead) +
      "components:\n  - {name: A, type: Rectangle, l: l1}\n  - {name: B, type: Rectangle, l: 5}\n"
      "constraints:\n  - A.w + B.w = 100\n");
  ASSERT_TRUE(has_code(a.diagnostics, codes::kUnderConstrained)) << a.diagnostics.format();
  EXPECT_NE(a.diagnostics.format().find("nothing determines A.w (in 'A.w + B.w = 100'), B.w"),
            std::string::npos)
      << a.diagnostics.format();
}

TEST(Constraints, OverConstrainedNamesTheConflictingConstraints) {
  const Analysis a = check_yaml(std::string(kHead) +
                                "components:\n  - {name: A, type: Rectangle, w: 5}\n"
                                "constraints:\n  - A.l = l1\n  - A.l = 35\n");
  ASSERT_TRUE(has_code(a.diagnostics, codes::kOverConstrained)) << a.diagnostics.format();
  EXPECT_NE(a.diagnostics.format().find("A.l = 35"), std::string::npos) << a.diagnostics.format();
  // Two-unknown conflicts are found by the linear solve.
  const Analysis b = check_yaml(std::string(kHead) +
                                "components:\n  - {name: A, type: Rectangle}\n"
                                "constraints:\n  - A.l + A.w = 10\n  - 2*A.l + 2*A.w = 30\n");
  ASSERT_TRUE(has_code(b.diagnostics, codes::kOverConstrained)) << b.diagnostics.format();
  EXPECT_NE(b.diagnostics.format().find("contradict each other"), std::string::npos)
      << b.diagnostics.format();
}

TEST(Constraints, UnknownNamesGetDidYouMean) {
  const Analysis a =
      check_yaml(std::string(kHead) + "components:\n  - {name: A, type: Rectangle, l: l3, w: 4}\n");
  EXPECT_NE(a.diagnostics.format().find(
                "'l3' in 'l3' is neither a parameter nor a component dimension; did you mean"),
            std::string::npos)
      << a.diagnostics.format();
  const Analysis b =
      check_yaml(std::string(kHead) + "components:\n  - {name: A, type: Rectangel}\n");
  EXPECT_NE(b.diagnostics.format().find("did you mean 'Rectangle'"), std::string::npos)
      << b.diagnostics.format();
}

TEST(Constraints, ANonWholeCountIsRefused) {
  const Analysis a = check_yaml(
      std::string(kHead) + "components:\n  - {name: P, type: RegularPolygon, n: 4.5, s: 10}\n");
  EXPECT_NE(a.diagnostics.format().find("P.n = 4.5 must be a whole number"), std::string::npos)
      << a.diagnostics.format();
}

}  // namespace
}  // namespace fabkit::flatpack

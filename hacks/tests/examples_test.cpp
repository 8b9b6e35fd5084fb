// Every bundled example is a valid design (issue item 9).
#include <gtest/gtest.h>

#include <filesystem>

#include "test_support.h"

namespace fabkit::hacks {
namespace {

struct Expectation {
  const char* name;
  int parts;
  int cycles;
};

// Part counts include the environment(s) and the target.
constexpr Expectation kExamples[] = {
    {"toothbrush_holder", 3, 2},
    {"charger_holder", 3, 1},
    {"soap_bottle_holder", 5, 1},
    {"soap_bottle_one_eyehook", 4, 0},
    {"mug_hanger", 6, 0},
    {"paper_towel_holder", 5, 1},
    {"diaper_caddy", 6, 1},
    {"basket_between_rods", 4, 1},
    {"bird_feeder", 7, 1},
    {"demo", 4, 0},
    {"clip_light_xs", 11, 0},
    {"clip_light_s", 11, 0},
    {"clip_light_m", 9, 0},
    {"clip_light_l", 9, 0},
    {"reading_nook", 19, 2},
};

// Readable test names and failure messages.
void PrintTo(const Expectation& e, std::ostream* os) {
  *os << e.name;
}

class ExampleTest : public ::testing::TestWithParam<Expectation> {};

TEST_P(ExampleTest, PassesCheck) {
  const Expectation& e = GetParam();
  const Design d = testing::load_example(e.name);
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  EXPECT_TRUE(d.diagnostics.empty()) << d.diagnostics.format();
  EXPECT_EQ(d.assembly.part_count(), e.parts);
  EXPECT_EQ(static_cast<int>(d.assembly.cycle_connections().size()), e.cycles);
  ASSERT_TRUE(d.assembly.target().has_value());
  EXPECT_TRUE(d.assembly.find(d.assembly.target()->part.get()).has_value());
  EXPECT_FALSE(d.name.empty());
}

INSTANTIATE_TEST_SUITE_P(Gallery,
                         ExampleTest,
                         ::testing::ValuesIn(kExamples),
                         [](const ::testing::TestParamInfo<Expectation>& p) {
                           return std::string(p.param.name);
                         });

TEST(Examples, EveryBundledFileIsListed) {
  int files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks")) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    bool listed = false;
    for (const auto& e : kExamples) listed |= entry.path().stem() == e.name;
    EXPECT_TRUE(listed) << entry.path();
  }
  EXPECT_EQ(files, static_cast<int>(std::size(kExamples)));
}

}  // namespace
}  // namespace fabkit::hacks

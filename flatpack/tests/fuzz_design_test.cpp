// Thousands of mutated flatpack design files through the reader and check(): never a crash or
// an exception, a clear error whenever the input is refused, and messages that are valid UTF-8
// and short, whatever bytes came in (the hacks kit's fuzz_readers_test does the same for its
// files).
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>

#include "fabkit/core/text.h"
#include "fabkit/flatpack/build.h"
#include "test_support.h"

namespace fabkit::flatpack {
namespace {

const std::string kDir = std::string(FABKIT_SOURCE_DIR) + "/examples/flatpack";

std::string read(const std::string& name) {
  std::ifstream in(kDir + "/" + name, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One to four random edits: flip a byte, insert a YAML-significant or hostile token, delete a
// span, duplicate a line, or cut the text short.
std::string mutate(std::string s, std::mt19937_64& rng) {
  static const char* const kTokens[] = {":",
                                        "[",
                                        "]",
                                        "{",
                                        "}",
                                        "-",
                                        ",",
                                        ".nan",
                                        "-.inf",
                                        "1e308",
                                        "-1e12",
                                        "\n",
                                        "  ",
                                        "\t",
                                        "&a",
                                        "*a",
                                        "!!str",
                                        "'",
                                        "\"",
                                        "#",
                                        "\xff",
                                        "\xc3\x28",
                                        "0",
                                        "-0",
                                        "1/0",
                                        "sqrt(-1)",
                                        "top.l",
                                        "A.b",
                                        "=",
                                        " = ",
                                        "front-back",
                                        "Polygon",
                                        "points: []",
                                        "uses: {X: x.yaml}",
                                        "rotation: [90, 0, 0]",
                                        "l: -5",
                                        "joint: none",
                                        "thickness",
                                        "fabkit: hacks/1"};
  auto pick = [&](std::size_t n) {
    return std::uniform_int_distribution<std::size_t>(0, n - 1)(rng);
  };
  const int edits = 1 + static_cast<int>(pick(4));
  for (int e = 0; e < edits && !s.empty(); ++e) {
    const std::size_t at = pick(s.size());
    switch (pick(5)) {
      case 0:
        s[at] = static_cast<char>(pick(256));
        break;
      case 1:
        s.insert(at, kTokens[pick(std::size(kTokens))]);
        break;
      case 2:
        s.erase(at, pick(16) + 1);
        break;
      case 3: {
        const std::size_t begin = s.rfind('\n', at);
        const std::size_t end = s.find('\n', at);
        const std::size_t b = begin == std::string::npos ? 0 : begin;
        s.insert(b, s.substr(b, (end == std::string::npos ? s.size() : end) - b));
        break;
      }
      default:
        s.resize(at);
    }
  }
  return s;
}

void expect_clean(const Diagnostics& d, const std::string& input) {
  for (const Diagnostic& x : d) {
    EXPECT_TRUE(is_valid_utf8(x.message)) << excerpt(x.message, 300);
    EXPECT_LT(x.message.size(), 2000u) << x.message.substr(0, 200) << "\n" << input;
  }
}

TEST(FuzzDesign, MutatedExampleFilesGiveCleanErrorsOrValidDesigns) {
  // The small examples (the composite ones read their sub-designs from the examples folder).
  const std::vector<std::string> seeds{read("bookend.yaml"),
                                       read("stool.yaml"),
                                       read("simple_table.yaml"),
                                       read("picnic_table.yaml"),
                                       read("box_with_lid.yaml"),
                                       read("bookshelf.yaml"),
                                       read("ladder.yaml")};
  std::mt19937_64 rng(12);
  CheckOptions o;
  o.max_components = 100;
  int refused = 0, checked = 0;
  for (int i = 0; i < 2500; ++i) {
    const std::string text = mutate(seeds[static_cast<std::size_t>(i) % seeds.size()], rng);
    Diagnostics d;
    Design design;
    EXPECT_NO_THROW(design = load_design_text(text, "fuzz.yaml", d, kDir)) << text;
    expect_clean(d, text);
    if (d.has_errors()) {
      ++refused;
      continue;
    }
    Analysis a;
    EXPECT_NO_THROW(a = check(design, o)) << text;
    expect_clean(a.diagnostics, text);
    // Refused or placed: never silently half done.
    EXPECT_TRUE(a.placed || a.diagnostics.has_errors()) << text;
    if (a.placed) {
      ++checked;
      for (const Piece& p : a.pieces) {
        for (const Polygon2d& poly : p.cut) {
          for (const Vec2& v : poly.outer) ASSERT_TRUE(v.allFinite()) << text;
        }
      }
    }
  }
  // The mutations reach both sides: the reader's refusals and check() on odd designs.
  EXPECT_GT(refused, 100);
  EXPECT_GT(checked, 100);
}

TEST(FuzzDesign, MutatedDesignsBuildOrFailWithoutPartialFiles) {
  const std::vector<std::string> seeds{read("bookend.yaml"), read("stool.yaml")};
  std::mt19937_64 rng(7);
  const auto dir = std::filesystem::temp_directory_path() / "fabkit-flatpack-fuzz-build";
  for (int i = 0; i < 150; ++i) {
    const std::string text = mutate(seeds[static_cast<std::size_t>(i) % seeds.size()], rng);
    Diagnostics d;
    const Design design = load_design_text(text, "fuzz.yaml", d, kDir);
    if (d.has_errors()) continue;
    std::filesystem::remove_all(dir);
    BuildOptions o;
    o.output_dir = dir;
    BuildSummary s;
    EXPECT_NO_THROW(s = build(design, o)) << text;
    expect_clean(s.diagnostics, text);
    if (s.termination == Termination::kInvalid) {
      EXPECT_TRUE(s.diagnostics.has_errors()) << text;
      EXPECT_FALSE(std::filesystem::exists(dir / "report.json")) << text;
    }
    if (std::filesystem::exists(dir)) {
      for (const auto& f : std::filesystem::directory_iterator(dir)) {
        EXPECT_EQ(f.path().filename().string().find(".tmp"), std::string::npos)
            << f.path() << " left behind";
      }
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace fabkit::flatpack

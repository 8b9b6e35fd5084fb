// Thousands of mutated inputs through every reader a user's file reaches (design files, part
// files, OBJ, STL): never a crash or an exception, a clear error whenever the input is refused,
// and messages that are valid UTF-8 and short, whatever bytes came in. (The libFuzzer
// harnesses in fuzz/ explore further; this runs in every test pass.)
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "fabkit/core/mesh_io.h"
#include "fabkit/core/text.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

std::string read(const std::string& relative) {
  std::ifstream in(std::string(FABKIT_SOURCE_DIR) + "/" + relative, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One random edit: flip a byte, insert a YAML-significant or hostile token, delete a span,
// duplicate a line, or cut the text short.
std::string mutate(std::string s, std::mt19937_64& rng) {
  static const char* const kTokens[] = {
      ":",     "[",     "]",    "{",        "}",  "-",    ",",     ".nan",    "-.inf",
      "1e308", "-1e12", "\n",   "  ",       "\t", "&a",   "*a",    "!!str",   "'",
      "\"",    "#",     "\xff", "\xc3\x28", "\0", "part", "hook1", "rod.rod", "fabkit: rods/1",
      "x.y.z", "0",     "-0"};
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

void expect_clean(const Diagnostics& d, bool refused, const std::string& input) {
  if (refused) {
    EXPECT_TRUE(d.has_errors()) << "refused without an error:\n" << input;
  }
  for (const Diagnostic& x : d) {
    EXPECT_TRUE(is_valid_utf8(x.message)) << excerpt(x.message, 300);
    EXPECT_LT(x.message.size(), 2000u) << x.message.substr(0, 200);
  }
}

TEST(FuzzReaders, MutatedDesignFiles) {
  const std::vector<std::string> seeds{read("examples/hacks/bird_feeder.yaml"),
                                       read("examples/hacks/basket_between_rods.yaml"),
                                       read("examples/hacks/toothbrush_holder.yaml"),
                                       read("examples/failing/hook_on_tilted_rod.yaml")};
  std::mt19937_64 rng(2024);
  DesignOptions options;
  options.verify.restarts = 1;
  options.verify.max_iterations = 20;
  options.part_files = PartFilePolicy::kRefuse;
  for (int i = 0; i < 1500; ++i) {
    const std::string text = mutate(seeds[static_cast<std::size_t>(i) % seeds.size()], rng);
    options.verify.deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(200);
    Design d;
    EXPECT_NO_THROW(d = load_design_text(text, "fuzz.yaml", PartsLibrary::builtin(), options))
        << text;
    expect_clean(d.diagnostics, !d.readable, text);
  }
}

TEST(FuzzReaders, MutatedPartFiles) {
  const std::string seed = read("examples/parts/wall_bracket.yaml") + "\n";
  const std::string builtin = read("hacks/data/parts.yaml").substr(0, 6000);
  std::mt19937_64 rng(99);
  for (int i = 0; i < 1500; ++i) {
    const std::string text = mutate(i % 2 ? seed : builtin, rng);
    PartsLibrary lib = PartsLibrary::builtin();
    const std::size_t before = lib.generators().size();
    Diagnostics d;
    bool ok = false;
    EXPECT_NO_THROW(ok = lib.load_yaml_text(
                        text, "fuzz.yaml", std::string(FABKIT_SOURCE_DIR) + "/examples/parts", d));
    expect_clean(d, !ok, text);
    if (!ok) {
      EXPECT_EQ(lib.generators().size(), before) << "a refused part file added parts";
    }
  }
}

TEST(FuzzReaders, MutatedMeshes) {
  const std::string obj = read("examples/parts/wall_bracket.obj");
  std::string stl;
  {
    Diagnostics d;
    const auto path = std::filesystem::temp_directory_path() / "fabkit_fuzz_seed.stl";
    ASSERT_TRUE(write_stl(shapes::cylinder(5, 10, 12), path, d));
    std::ifstream in(path, std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    stl = s.str();
    std::filesystem::remove(path);
  }
  const std::string ascii_stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\n"
      "endfacet\nendsolid t\n";
  std::mt19937_64 rng(5);
  for (int i = 0; i < 1500; ++i) {
    Diagnostics d;
    std::optional<TriangleMesh> m;
    const std::string text = mutate(i % 3 == 0 ? obj : (i % 3 == 1 ? stl : ascii_stl), rng);
    EXPECT_NO_THROW(m = i % 3 == 0 ? read_obj_text(text, "fuzz.obj", d)
                                   : read_stl_bytes(text, "fuzz.stl", d));
    expect_clean(d, !m, text.substr(0, 300));
    if (m) {
      for (const auto& f : m->faces) {
        for (int c = 0; c < 3; ++c) {
          ASSERT_GE(f[c], 0);
          ASSERT_LT(static_cast<std::size_t>(f[c]), m->vertices.size());
        }
      }
    }
  }
}

}  // namespace
}  // namespace fabkit::hacks

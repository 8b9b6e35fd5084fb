// A hacks part file (fabkit: parts/1): parts, primitives, bodies and mass properties. Mesh
// files it names resolve in an empty directory (none exist).
#include <filesystem>

#include "fabkit/hacks/parts_library.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fabkit;
  static const std::filesystem::path empty_dir = [] {
    auto p = std::filesystem::temp_directory_path() / "fabkit-fuzz-empty";
    std::filesystem::create_directories(p);
    return p;
  }();
  hacks::PartsLibrary library;
  Diagnostics d;
  const bool ok = library.load_yaml_text(fuzz::text_of(data, size), "parts.yaml", empty_dir, d);
  fuzz::require_clean(d, !ok);
  for (const hacks::PartGenerator& g : library.generators()) {
    Diagnostics made;
    if (auto part = library.make(g.name, {}, made)) {
      fuzz::require_sound(part->mesh, g.name);
    }
    fuzz::require_clean(made, false);
  }
  return 0;
}

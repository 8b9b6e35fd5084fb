// A hacks design file (fabkit: hacks/1): read, declared and verified with one start of the
// cycle-closure search and a short deadline, as `fabkit check` does.
#include <chrono>

#include "fabkit/hacks/design_file.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fabkit;
  static const hacks::PartsLibrary library = hacks::PartsLibrary::builtin();
  hacks::DesignOptions o;
  o.verify.restarts = 1;
  o.verify.deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(50);
  o.max_parts = 40;
  o.max_connections = 80;
  o.part_files = hacks::PartFilePolicy::kRefuse;  // no file system from a fuzzer
  const hacks::Design d =
      hacks::load_design_text(fuzz::text_of(data, size), "design.yaml", library, o);
  fuzz::require_clean(d.diagnostics, !d.readable);
  if (d.readable)
    fuzz::require(d.feasible() == !d.diagnostics.has_errors(), "feasible() disagrees");
  return 0;
}

// A rods design file (fabkit: rods/1): network, parameters, loads, supports. Files it names
// are refused, as a server would.
#include "fabkit/rods/design_file.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fabkit;
  rods::DesignOptions o;
  o.files = rods::FilePolicy::kRefuse;
  o.max_nodes = 2000;
  o.max_edges = 4000;
  const rods::Design d = rods::load_design_text(fuzz::text_of(data, size), "design.yaml", {}, o);
  fuzz::require_clean(d.diagnostics, !d.readable);
  return 0;
}

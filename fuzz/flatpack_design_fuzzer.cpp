// A flat-pack design file (fabkit: flatpack/1): components, parameters and constraint
// expressions (muparser), connections; then the check (placement, joints, assembly order).
#include "fabkit/flatpack/check.h"
#include "fabkit/flatpack/design_file.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fabkit;
  flatpack::DesignFileOptions o;
  o.allow_uses = false;  // no file system from a fuzzer
  Diagnostics d;
  const flatpack::Design design =
      flatpack::load_design_text(fuzz::text_of(data, size), "design.yaml", d, {}, o);
  fuzz::require_clean(d, false);
  if (d.has_errors() || size > 4096) return 0;  // large inputs: the reader only
  const flatpack::Analysis a = flatpack::check(design);
  fuzz::require_clean(a.diagnostics, false);
  return 0;
}

// A templates file (fabkit: templates/1, a model or a source design), composed against the
// bundled database: templates, controls, snapping and connecting.
#include "fabkit/templates/check.h"
#include "fabkit/templates/database.h"
#include "fuzz_support.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace fabkit;
  const templates::TemplateDatabase& db = templates::TemplateDatabase::bundled();
  const templates::ComposedModel cm =
      templates::compose_model(fuzz::text_of(data, size), "model.yaml", db);
  fuzz::require_clean(cm.diagnostics, !cm.readable);
  return 0;
}

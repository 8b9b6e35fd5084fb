#pragma once
// Shared helpers for the hacks tests.

#include <gtest/gtest.h>

#include <string>

#include "fabkit/hacks/assembly.h"
#include "fabkit/hacks/design_file.h"
#include "fabkit/hacks/parts_library.h"

namespace fabkit::hacks::testing {

/// Every design of the paper's gallery (examples/hacks/, docs/gallery.md).
inline constexpr const char* kGalleryExamples[] = {
    "toothbrush_holder",
    "charger_holder",
    "soap_bottle_holder",
    "soap_bottle_one_eyehook",
    "mug_hanger",
    "paper_towel_holder",
    "diaper_caddy",
    "basket_between_rods",
    "bird_feeder",
    "demo",
    "clip_light_xs",
    "clip_light_s",
    "clip_light_m",
    "clip_light_l",
    "reading_nook",
};

inline std::shared_ptr<Part> make_part(const std::string& name, const ParamValues& params = {}) {
  Diagnostics d;
  auto p = PartsLibrary::builtin().make(name, params, d);
  EXPECT_TRUE(p) << d.format();
  return p;
}

inline std::shared_ptr<Part> rod_environment(double radius, double length) {
  PrimitiveShape s;
  s.radius = radius;
  s.length = length;
  return std::make_shared<Part>(
      make_primitive_part({Primitive::make("rod", PrimitiveType::kRod, s)}));
}

inline Design load_example(const std::string& name) {
  return load_design(std::string(FABKIT_SOURCE_DIR) + "/examples/hacks/" + name + ".yaml",
                     PartsLibrary::builtin());
}

inline Design load_text(const std::string& yaml) {
  return load_design_text(yaml, "test.yaml", PartsLibrary::builtin());
}

/// The first error diagnostic with `code`, or a failure.
inline ::testing::AssertionResult has_diagnostic(const Diagnostics& ds,
                                                 DiagnosticCode code,
                                                 const std::string& fragment,
                                                 int line = 0) {
  for (const Diagnostic& d : ds) {
    if (d.code != code) continue;
    if (d.message.find(fragment) == std::string::npos) continue;
    if (line > 0 && d.where.line != line) {
      return ::testing::AssertionFailure() << "right diagnostic on line " << d.where.line
                                           << ", expected line " << line << ": " << d.format();
    }
    return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure()
         << "no " << to_string(code) << " diagnostic containing '" << fragment << "' in:\n"
         << ds.format();
}

}  // namespace fabkit::hacks::testing

#pragma once
// Shared helpers for the templates tests.

#include <gtest/gtest.h>

#include <string>

#include "fabkit/templates/database.h"
#include "fabkit/templates/source_design.h"
#include "fabkit/templates/template.h"

namespace fabkit::templates::testing {

/// A part of a constructed design: centre and size in mm.
inline DesignPart part(const std::string& name,
                       const std::string& item,
                       const Vec3& center,
                       const Vec3& size,
                       PartRole role = PartRole::kPrincipal,
                       const std::string& group = "") {
  DesignPart p;
  p.name = name;
  p.item = item;
  p.box.center = center;
  p.box.size = size;
  p.role = role;
  p.group = group;
  return p;
}

/// The bundled template database (built once, on first use).
inline const TemplateDatabase& db() {
  return TemplateDatabase::bundled();
}

/// The element named `name` (fails the test if missing).
inline ElementId element_named(const Template& t, const std::string& name) {
  for (int i = 0; i < t.element_count(); ++i) {
    if (t.element(ElementId(i)).name == name) return ElementId(i);
  }
  ADD_FAILURE() << "no element '" << name << "'";
  return ElementId(0);
}

/// The first diagnostic with `code` whose message contains `fragment`.
inline ::testing::AssertionResult has_diagnostic(const Diagnostics& ds,
                                                 DiagnosticCode code,
                                                 const std::string& fragment) {
  for (const Diagnostic& d : ds) {
    if (d.code == code && d.message.find(fragment) != std::string::npos) {
      return ::testing::AssertionSuccess();
    }
  }
  return ::testing::AssertionFailure()
         << "no " << to_string(code) << " diagnostic containing '" << fragment << "' in:\n"
         << ds.format();
}

}  // namespace fabkit::templates::testing

#pragma once
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "fabkit/flatpack/check.h"
#include "fabkit/flatpack/design_file.h"

namespace fabkit::flatpack::test {

inline Design parse(const std::string& yaml, Diagnostics& d) {
  return load_design_text(yaml, "test.yaml", d);
}

inline Analysis check_yaml(const std::string& yaml) {
  Diagnostics d;
  Design design = parse(yaml, d);
  if (d.has_errors()) {
    Analysis a;
    a.diagnostics = d;
    return a;
  }
  return check(design);
}

inline Design example(const std::string& name) {
  Diagnostics d;
  Design design =
      load_design(std::string(FABKIT_SOURCE_DIR) + "/examples/flatpack/" + name + ".yaml", d);
  EXPECT_FALSE(d.has_errors()) << d.format();
  return design;
}

inline bool has_code(const Diagnostics& d, const DiagnosticCode& code) {
  for (const Diagnostic& x : d) {
    if (x.code == code) return true;
  }
  return false;
}

// Every edge of a shell used once in each direction: closed and consistently oriented.
inline bool closed_and_oriented(const TriangleMesh& m) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : m.faces) {
    for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
  }
  for (const auto& [e, n] : directed) {
    auto back = directed.find({e.second, e.first});
    if (n != 1 || back == directed.end() || back->second != 1) return false;
  }
  return !m.faces.empty();
}

}  // namespace fabkit::flatpack::test

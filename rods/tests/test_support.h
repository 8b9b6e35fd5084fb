#pragma once
// Helpers shared by the rods kit's tests.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "fabkit/core/mesh_boolean.h"
#include "fabkit/rods/design_file.h"
#include "fabkit/rods/structure.h"

namespace fabkit::rods::test {

// A structure from 1-based edges; fails the test on any diagnostic error.
inline Structure make_structure(const std::vector<Vec3>& nodes,
                                const std::vector<std::pair<int, int>>& edges) {
  std::vector<NodeInput> n;
  for (const Vec3& p : nodes) n.push_back(NodeInput{p, {}});
  std::vector<EdgeInput> e;
  for (const auto& [a, b] : edges) e.push_back(EdgeInput{a, b, {}});
  Diagnostics d;
  auto s = build_structure(n, e, 1, 0.01, d);
  EXPECT_TRUE(s) << d.format();
  return s ? *s : Structure{};
}

// Two rods leaving node 1 at `angle_deg` in the xy plane, 100 mm long.
inline Structure two_rods_at(double angle_deg) {
  const double a = angle_deg * kDegToRad;
  return make_structure({{0, 0, 0}, {100, 0, 0}, {100 * std::cos(a), 100 * std::sin(a), 0}},
                        {{1, 2}, {1, 3}});
}

inline Design load_example(const std::string& name) {
  Design d = load_design(std::string(FABKIT_SOURCE_DIR) + "/examples/rods/" + name);
  EXPECT_TRUE(d.readable) << name << ": " << d.diagnostics.format();
  return d;
}

// A printable solid by CGAL's own checks: closed, manifold, no self-intersections, outward.
inline void expect_watertight(const TriangleMesh& mesh, const std::string& what) {
  const SolidCheck c = check_solid(mesh);
  EXPECT_TRUE(c.valid_solid()) << what << ": " << c.problems();
  EXPECT_EQ(c.boundary_edges, 0) << what;
}

inline bool has_code(const Diagnostics& d,
                     const DiagnosticCode& code,
                     Severity severity = Severity::kError) {
  for (const Diagnostic& x : d) {
    if (x.code == code && x.severity == severity) return true;
  }
  return false;
}

inline std::string messages(const Diagnostics& d) {
  return d.format();
}

}  // namespace fabkit::rods::test

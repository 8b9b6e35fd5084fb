#include "fabkit/rods/frame_analysis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "fabkit/rods/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::rods {
namespace {

using test::has_code;

Parameters round_rod(double radius) {
  Parameters p;
  p.radius = radius;
  p.rod_material = RodMaterial{"test", 700, 12000, 750, 80};
  return p;
}

FrameOptions point_load(int node, const Vec3& force, std::vector<Support> supports) {
  FrameOptions o;
  o.self_weight = false;
  o.loads.push_back(PointLoad{node, force, {}});
  o.supports = std::move(supports);
  return o;
}

TEST(FrameAnalysis, CantileverTipLoadMatchesTextbook) {
  const double L = 400, P = 10;
  const Structure s = test::make_structure({{0, 0, 0}, {L, 0, 0}}, {{1, 2}});
  const Parameters p = round_rod(5);
  const double E = p.rod_material.youngs_modulus, I = p.section_inertia();
  const FrameResult r = analyse_frame(
      s, p, compute_layout(s, p), point_load(1, Vec3(0, 0, -P), {Support{0, true, {}}}));
  ASSERT_TRUE(r.solved) << r.findings.format();
  EXPECT_NEAR(r.displacement[1].z(), -P * L * L * L / (3 * E * I), 1e-9);    // δ = PL³ / 3EI
  EXPECT_NEAR(std::abs(r.rotation[1].y()), P * L * L / (2 * E * I), 1e-12);  // θ = PL² / 2EI
  EXPECT_NEAR(r.rods[0].moment, P * L, 1e-6);                                // root moment
  EXPECT_NEAR(r.rods[0].stress, P * L / (I / p.radius), 1e-6);               // σ = M c / I
  EXPECT_NEAR(r.max_deflection, P * L * L * L / (3 * E * I), 1e-9);
  EXPECT_EQ(r.max_deflection_node, 1);
}

TEST(FrameAnalysis, CantileverSelfWeightMatchesWL4Over8EI) {
  const double L = 500;
  const Structure s = test::make_structure({{0, 0, 0}, {L, 0, 0}}, {{1, 2}});
  Parameters p = round_rod(4);  // leaf offsets 0: the rod is the whole edge
  FrameOptions o;
  o.supports = {Support{0, true, {}}};
  const FrameResult r = analyse_frame(s, p, compute_layout(s, p), o);
  ASSERT_TRUE(r.solved);
  const double w = p.rod_material.density * 1e-9 * p.section_area() * 9.81;  // N/mm
  EXPECT_NEAR(r.displacement[1].z(),
              -w * std::pow(L, 4) / (8 * p.rod_material.youngs_modulus * p.section_inertia()),
              1e-9);
  EXPECT_NEAR(r.rods[0].moment, w * L * L / 2, 1e-6);
  EXPECT_NEAR(r.total_load, w * L, 1e-9);
}

TEST(FrameAnalysis, ColumnShortensByPLOverEAAndBucklesAtEuler) {
  const double L = 600, P = 30;
  const Structure s = test::make_structure({{0, 0, 0}, {0, 0, L}}, {{1, 2}});
  const Parameters p = round_rod(3.175);
  const double E = p.rod_material.youngs_modulus, A = p.section_area(), I = p.section_inertia();
  FrameOptions o = point_load(1, Vec3(0, 0, -P), {Support{0, true, {}}});
  o.buckling_length_factor = 2;  // a free-standing column (fixed base, free top): K = 2
  const FrameResult r = analyse_frame(s, p, compute_layout(s, p), o);
  ASSERT_TRUE(r.solved);
  EXPECT_NEAR(r.displacement[1].z(), -P * L / (E * A), 1e-12);
  EXPECT_NEAR(r.rods[0].axial, -P, 1e-9);
  const double euler = std::numbers::pi * std::numbers::pi * E * I / (4 * L * L);
  EXPECT_NEAR(r.rods[0].buckling_load, euler, 1e-9);
  EXPECT_NEAR(r.rods[0].utilisation, std::max(P / euler, (P / A) / p.rod_material.strength), 1e-12);
  EXPECT_EQ(r.rods[0].governing, "buckling");
  // Past the Euler load: rod-overstressed, "buckles".
  FrameOptions heavy = o;
  heavy.loads[0].force = Vec3(0, 0, -2 * euler);
  const FrameResult h = analyse_frame(s, p, compute_layout(s, p), heavy);
  EXPECT_TRUE(has_code(h.findings, codes::kRodOverstressed));
  EXPECT_NE(h.findings.format().find("rod 01-02 buckles"), std::string::npos)
      << h.findings.format();
}

TEST(FrameAnalysis, BentCantileverCarriesTorsion) {
  // An L in the xy plane, fixed at the corner's far end, loaded at the tip: δ = P(a³ + b³)/3EI
  // + P a b² / GJ (the first arm twists by P b a / GJ).
  const double a = 300, b = 200, P = 5;
  const Structure s = test::make_structure({{0, 0, 0}, {a, 0, 0}, {a, b, 0}}, {{1, 2}, {2, 3}});
  const Parameters p = round_rod(5);
  const double E = p.rod_material.youngs_modulus, G = p.rod_material.shear_modulus,
               I = p.section_inertia(), J = p.section_torsion();
  const FrameResult r = analyse_frame(
      s, p, compute_layout(s, p), point_load(2, Vec3(0, 0, -P), {Support{0, true, {}}}));
  ASSERT_TRUE(r.solved);
  const double expected = P * (a * a * a + b * b * b) / (3 * E * I) + P * a * b * b / (G * J);
  EXPECT_NEAR(r.displacement[2].z(), -expected, 1e-9 * expected);
  EXPECT_NEAR(r.rods[0].torque, P * b, 1e-6);
}

TEST(FrameAnalysis, UnsupportedFrameIsAMechanism) {
  const Structure s = test::make_structure({{0, 0, 0}, {100, 0, 0}, {0, 100, 0}}, {{1, 2}, {1, 3}});
  const Parameters p = round_rod(5);
  // Pinned at one node only: free to swing about it.
  const FrameResult r = analyse_frame(
      s, p, compute_layout(s, p), point_load(1, Vec3(0, 0, -1), {Support{0, false, {}}}));
  EXPECT_FALSE(r.solved);
  EXPECT_TRUE(has_code(r.findings, codes::kMechanism));
  EXPECT_NE(r.findings.format().find("supports at joint 01"), std::string::npos)
      << r.findings.format();
}

TEST(FrameAnalysis, StandingDesignsCarryTheirLoads) {
  for (const char* name : {"guitar_stand.yaml", "coffee_table.yaml", "stool.yaml"}) {
    const Design d = test::load_example(name);
    FrameOptions o;
    o.loads = d.loads;
    const FrameResult r =
        analyse_frame(d.structure, d.parameters, compute_layout(d.structure, d.parameters), o);
    ASSERT_TRUE(r.solved) << name << ": " << r.findings.format();
    EXPECT_LT(r.max_utilisation, 1) << name;
    EXPECT_GT(r.max_utilisation, 0) << name;
    EXPECT_LT(r.max_deflection, 5) << name;
  }
}

}  // namespace
}  // namespace fabkit::rods

// Properties that hold for every design, checked on the gallery with seeded random inputs:
// connector frames are rigid transforms, the solvers' analytic derivatives are the derivatives
// (against finite differences), and a rejected connect changes nothing.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>

#include "../src/contacts.h"
#include "../src/kinematics.h"
#include "../src/solve_internal.h"
#include "../src/steps.h"
#include "fabkit/hacks/connector_frame.h"
#include "fabkit/hacks/diagnostic_codes.h"
#include "test_support.h"

namespace fabkit::hacks {
namespace {

using testing::load_example;
using testing::make_part;

const char* const kGallery[] = {"toothbrush_holder",
                                "charger_holder",
                                "soap_bottle_holder",
                                "mug_hanger",
                                "paper_towel_holder",
                                "diaper_caddy",
                                "basket_between_rods",
                                "bird_feeder",
                                "clip_light_s",
                                "reading_nook"};

// A random parameter vector inside every bound (unbounded angles anywhere in [0, 360)).
std::vector<double> random_parameters(const Assembly& a, std::mt19937_64& rng) {
  std::vector<double> x = a.values();
  for (int i = 0; i < a.parameter_count(); ++i) {
    const ParamSpec& s = a.parameters()[static_cast<std::size_t>(i)].spec;
    if (s.constant) continue;
    const double lo = s.tag == ParamTag::kUnbounded ? 0 : s.lo;
    const double hi = s.tag == ParamTag::kUnbounded ? 360 : s.hi;
    x[static_cast<std::size_t>(i)] = std::uniform_real_distribution<double>(lo, hi)(rng);
  }
  return x;
}

TEST(Properties, ConnectorFramesAreRigidForEveryPrimitiveAndParameter) {
  std::mt19937_64 rng(7);
  int checked = 0;
  for (const PartGenerator& g : PartsLibrary::builtin().generators()) {
    const auto part = make_part(g.name);
    for (const Primitive& p : part->primitives) {
      const std::vector<ParamSpec> specs = p.connector_params();
      for (int trial = 0; trial < 20; ++trial) {
        double q[3] = {0, 0, 0};
        for (std::size_t k = 0; k < specs.size(); ++k) {
          const double lo = specs[k].tag == ParamTag::kUnbounded ? -720 : specs[k].lo;
          const double hi = specs[k].tag == ParamTag::kUnbounded ? 720 : specs[k].hi;
          q[k] = std::uniform_real_distribution<double>(lo, hi)(rng);
        }
        const Mat4 m = connector_frame<double>(p, q);
        const Mat3 r = m.topLeftCorner<3, 3>();
        EXPECT_LT((r.transpose() * r - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-12)
            << g.name << "." << p.name;
        EXPECT_NEAR(r.determinant(), 1.0, 1e-12) << g.name << "." << p.name;
        EXPECT_EQ(m.row(3), Eigen::RowVector4d(0, 0, 0, 1));
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 2000);
}

// The closure search's exact Jacobian (verification and step 1's closing starts) against
// Ceres' automatic differentiation of the same rows, on random configurations of the gallery
// (cycles of every kind: hooks, rings, rods through rings, spacing rows), with the orientation
// rows at full and at the first phase's weight.
TEST(Properties, ClosureSearchJacobianMatchesAutomaticDifferentiation) {
  std::mt19937_64 rng(17);
  int designs_with_cycles = 0;
  for (const char* name : kGallery) {
    const Design d = load_example(name);
    ASSERT_TRUE(d.feasible()) << name << d.diagnostics.format();
    if (d.assembly.cycle_connections().empty()) continue;
    ++designs_with_cycles;
    for (int trial = 0; trial < 5; ++trial) {
      const std::vector<double> x = random_parameters(d.assembly, rng);
      EXPECT_LT(detail::closure_search_jacobian_mismatch(d.assembly, x), 1e-9) << name;
      EXPECT_LT(detail::closure_search_jacobian_mismatch(d.assembly, x, 0.01), 1e-9) << name;
    }
  }
  EXPECT_GE(designs_with_cycles, 5);
}

// The solvers' local twists of every connector (dL/dq · L⁻¹ of its transform L(q), recorded
// along its elementary motions) against central differences of the transform itself.
TEST(Properties, ConnectorTwistsAreTheDerivativesOfTheirFrames) {
  std::mt19937_64 rng(13);
  int checked = 0;
  for (const PartGenerator& g : PartsLibrary::builtin().generators()) {
    const auto part = make_part(g.name);
    for (const Primitive& p : part->primitives) {
      const std::vector<ParamSpec> specs = p.connector_params();
      const int dof = connector_dof(p.connector_kind());
      auto local = [&](const double* q) {
        Rigid<double> l;
        apply_connector<double>(p.connector_kind(), p.shape, q, l);
        return l;
      };
      for (int trial = 0; trial < 10; ++trial) {
        double q[3] = {0, 0, 0};
        for (std::size_t k = 0; k < specs.size(); ++k) {
          const double lo = specs[k].tag == ParamTag::kUnbounded ? -720 : specs[k].lo;
          const double hi = specs[k].tag == ParamTag::kUnbounded ? 720 : specs[k].hi;
          q[k] = std::uniform_real_distribution<double>(lo, hi)(rng);
        }
        Vec3 w[3], v[3];
        detail::local_connector_twists(p, q, w, v);
        const Rigid<double> at = local(q);
        for (int j = 0; j < dof; ++j) {
          const double h = 1e-6 * std::max(1.0, std::abs(q[j]));
          double qp[3] = {q[0], q[1], q[2]};
          double qm[3] = {q[0], q[1], q[2]};
          qp[j] += h;
          qm[j] -= h;
          const Rigid<double> plus = local(qp);
          const Rigid<double> minus = local(qm);
          const Mat3 omega = (plus.R - minus.R) / (2 * h) * at.R.transpose();
          const Vec3 w_fd(omega(2, 1), omega(0, 2), omega(1, 0));
          const Vec3 v_fd = (plus.t - minus.t) / (2 * h) - w_fd.cross(at.t);
          const std::string where = fmt::format("{}.{} q{} = {}", g.name, p.name, j, q[j]);
          EXPECT_LT((w[j] - w_fd).norm(), 1e-7 * std::max(1.0, w_fd.norm())) << where;
          EXPECT_LT((v[j] - v_fd).norm(), 1e-6 * std::max(1.0, v_fd.norm())) << where;
          ++checked;
        }
      }
    }
  }
  EXPECT_GT(checked, 1000);
}

TEST(Properties, AnalyticDerivativesMatchFiniteDifferencesOnRandomConfigurations) {
  std::mt19937_64 rng(11);
  for (const char* name : kGallery) {
    const Design d = load_example(name);
    ASSERT_TRUE(d.feasible()) << name << d.diagnostics.format();
    for (int trial = 0; trial < 5; ++trial) {
      const std::vector<double> x = random_parameters(d.assembly, rng);
      // Step 1's rows (target, closures) and step 2's (potential, closures).
      EXPECT_LT(detail::finite_difference_mismatch(d.assembly, x, false), 1e-5) << name;
      EXPECT_LT(detail::finite_difference_mismatch(d.assembly, x, true), 1e-5) << name;
    }
  }
}

// The exact Hessian of step 2's Lagrangian (the potential's, the closures' rows, and the held
// target's rows when settling) and of step 1's least squares against central differences of its
// exact gradient, on random configurations of every gallery design and of two long S-hook
// chains (connections of several kinds, branches, cycles, targets with and without symmetry).
// The 18-hook chain with a mug as its target has 76 variables: models that large compute each
// pair of variables once and mirror it (kinematics.cpp, kHalfHessianFrom).
TEST(Properties, AnalyticHessianMatchesFiniteDifferencesOnRandomConfigurations) {
  std::mt19937_64 rng(23);
  std::vector<Design> designs;
  for (const char* name : kGallery) designs.push_back(load_example(name));
  auto chain = [](int hooks, bool mug_target) {
    std::string s =
        "fabkit: hacks/1\nenvironment:\n  - {name: bar, primitives: {rod: {type: rod, radius: "
        "4, length: 300}}, frame: {pos: [0, 0, 4000], rot: [90, 0, 0]}}\nparts:\n";
    for (int i = 0; i < hooks; ++i) s += fmt::format("  - {{name: s{}, part: DoubleHook}}\n", i);
    if (mug_target) {
      s += "target: {name: mug, part: Mug, primitive: hook, frame: {pos: [30, 0, 2500], rot: [0, "
           "0, 0]}}\n";
    }
    s += "connections:\n  - connect: [s0.hook1, bar.rod]\n";
    for (int i = 1; i < hooks; ++i)
      s += fmt::format("  - connect: [s{}.hook1, s{}.hook2]\n", i, i - 1);
    if (mug_target) s += fmt::format("  - connect: [mug.hook, s{}.hook2]\n", hooks - 1);
    return s;
  };
  designs.push_back(testing::load_text(chain(12, false)));
  designs.push_back(testing::load_text(chain(18, true)));
  ASSERT_GE(designs.back().assembly.parameter_count(), 64);
  for (const Design& d : designs) {
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    for (int trial = 0; trial < 5; ++trial) {
      const std::vector<double> x = random_parameters(d.assembly, rng);
      EXPECT_LT(detail::hessian_mismatch(d.assembly, x, false), 1e-6) << d.name << " " << trial;
      // With the target held, as the settling between the steps does (random multipliers).
      EXPECT_LT(detail::hessian_mismatch(d.assembly, x, true, 100 + trial), 1e-6)
          << d.name << " holding its target, " << trial;
      // Step 1's ½‖r‖² of the target's residuals (its Newton finish).
      EXPECT_LT(detail::target_hessian_mismatch(d.assembly, x, 200 + trial), 1e-6)
          << d.name << " reaching for its target, " << trial;
    }
  }
}

// A trial step is evaluated without its Jacobian, which is filled only for the step the
// solver keeps, from what the evaluation of its values kept (the distance queries of its
// contact rows among it): the two calls must give exactly what one evaluation gives, also
// when the evaluator saw another point in between.
TEST(Properties, ValuesFirstThenJacobianIsOneEvaluation) {
  std::mt19937_64 rng(29);
  for (const char* name : kGallery) {
    const Design d = load_example(name);
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    // As built (parts touching where the design puts them), then random configurations.
    std::vector<double> x = d.assembly.values();
    for (int trial = 0; trial < 3; ++trial) {
      const std::vector<double> other = random_parameters(d.assembly, rng);
      EXPECT_EQ(detail::values_first_mismatch(d.assembly, x, other, false), 0.0)
          << name << " " << trial;
      EXPECT_EQ(detail::values_first_mismatch(d.assembly, x, other, true), 0.0)
          << name << " reaching for its target, " << trial;
      x = random_parameters(d.assembly, rng);
    }
  }
}

// Everything observable about an assembly, to compare before and after.
std::string snapshot(const Assembly& a) {
  std::string s;
  for (int i = 0; i < a.part_count(); ++i) {
    s += a.label(PartId{i}) + "@" + a.node(PartId{i}).frame.to_string() + ";";
    for (int k = 0; k < static_cast<int>(a.node(PartId{i}).part->primitives.size()); ++k) {
      for (double v : a.available_critical_dim(PartId{i}, PrimitiveId{k}))
        s += std::to_string(v) + ",";
      s += std::to_string(a.connections_of(PartId{i}, PrimitiveId{k}).size()) + ";";
    }
  }
  for (double v : a.values()) s += std::to_string(v) + " ";
  s += std::to_string(a.connections().size()) + "/" + std::to_string(a.cycle_connections().size());
  s += std::to_string(a.graph().part_count()) + "/" + std::to_string(a.graph().edge_count());
  return s;
}

TEST(Properties, RejectedConnectsChangeNothing) {
  Design d = load_example("basket_between_rods");
  ASSERT_TRUE(d.feasible());
  Assembly& a = d.assembly;
  const std::string before = snapshot(a);
  auto part_named = [&](const std::string& n) { return d.parts.at(n); };
  // One of each rejection: a pair Table 1 forbids, sizes, an already made connection, a cycle
  // that cannot close, a part connected to itself, two new parts.
  const auto bottle = make_part("SoapBottle");
  const auto big_rod = make_part("LongTensionRod");
  const auto s1 = make_part("DoubleHook");
  const auto s2 = make_part("DoubleHook");
  const std::vector<std::pair<PrimitiveRef, PrimitiveRef>> bad{
      {{bottle, "surface"}, {part_named("rods"), "rod1"}},
      {{s1, "hook1"}, {big_rod, "rod"}},
      {{part_named("eyehook1"), "hole"}, {part_named("rods"), "rod1"}},
      {{part_named("eyehook1"), "hook"}, {part_named("eyehook1"), "hole"}},
      {{s1, "hook1"}, {s2, "hook2"}},
      {{part_named("basket"), "hook"}, {part_named("rods"), "rod2"}},
  };
  for (const auto& [x, y] : bad) {
    const ConnectReport r = a.connect(x, y);
    EXPECT_FALSE(r.accepted) << r.description;
    EXPECT_TRUE(r.diagnostics.has_errors()) << r.description;
    EXPECT_EQ(snapshot(a), before) << "a rejected connect changed the assembly: " << r.description;
  }
}

// Once a candidate of a group came to rest against an environment only with its contact rows,
// the group's later candidates watch contacts from the start instead of first running without
// them (steps.h, avoiding_contacts). That must not change where they rest: from step 1's
// result, both ways end with the same potential and every part at the same height — on the
// designs whose plain relaxation passes through their wall (the mug hanger, the paper towel
// holder: both ways then run the contact rows) and, the case that tests something, on designs
// whose plain relaxation passes through nothing, so that contact rows watched from the start
// must bind nowhere and change no step.
TEST(Properties, WatchingContactsFromTheStartRestsWhereThePlainRunFirstDoes) {
  const std::set<std::string> through_wall{"mug_hanger", "paper_towel_holder"};
  for (const char* name : {"mug_hanger",
                           "paper_towel_holder",
                           "toothbrush_holder",
                           "bird_feeder",
                           "basket_between_rods",
                           "clip_light_s"}) {
    SCOPED_TRACE(name);
    const Design d = load_example(name);
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    const Assembly& a = d.assembly;
    const SolveOptions options;
    const SolveResult solved = solve(a, options);
    ASSERT_TRUE(solved.stable) << solved.summary();
    const auto contacts = std::make_shared<const detail::ContactModel>(a);
    auto relax = [&](bool contacts_first) {
      detail::Problem p = detail::make_problem(a);
      p.contacts = contacts;
      p.contacts_first = std::make_shared<bool>(contacts_first);
      const detail::Variables vars = detail::select_variables(a, /*physics=*/true, &p);
      const detail::StepResult r = detail::run_step2(p, vars, solved.step1_parameters, options);
      return std::make_pair(r, *p.contacts_first);
    };
    const auto [plain_first, learned] = relax(false);
    const auto [watching, kept] = relax(true);
    // Whether the plain run passed through an environment (the contact rows then brought it
    // to rest apart, and the flag is set); watched from the start, it stays set.
    EXPECT_EQ(learned, through_wall.count(name) == 1);
    EXPECT_TRUE(kept);
    ASSERT_TRUE(plain_first.closed && plain_first.converged);
    ASSERT_TRUE(watching.closed && watching.converged);
    const std::vector<Mat4> f1 = a.part_frames(plain_first.x);
    const std::vector<Mat4> f2 = a.part_frames(watching.x);
    double e1 = 0, e2 = 0;
    for (std::size_t i = 0; i < f1.size(); ++i) {
      const double m = a.nodes()[i].environment ? 0.0 : a.nodes()[i].part->mass;
      e1 += m * f1[i](2, 3);
      e2 += m * f2[i](2, 3);
      EXPECT_NEAR(f1[i](2, 3), f2[i](2, 3), 1e-3) << "part " << i;
    }
    EXPECT_NEAR(e1, e2, 1e-6 * std::max(1.0, std::abs(e1)));
  }
}

// A relaxation that ends at a minimum hands its last model to the stability check, which
// would otherwise make it again: where it does, the verdict is the one the check makes itself
// (the same slips, residual, curvatures and neutral count), whatever whole turns the angles
// are wrapped by.
TEST(Properties, TheStabilityCheckMayUseTheRelaxationsLastModel) {
  int lent = 0;
  for (const char* name : testing::kGalleryExamples) {
    SCOPED_TRACE(name);
    const Design d = load_example(name);
    ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
    const Assembly& a = d.assembly;
    const SolveOptions options;
    const SolveResult solved = solve(a, options);
    detail::Problem p = detail::make_problem(a);
    p.contacts = std::make_shared<const detail::ContactModel>(a);
    const detail::Variables vars = detail::select_variables(a, /*physics=*/true, &p);
    const detail::StepResult r = detail::run_step2(p, vars, solved.step1_parameters, options);
    if (!r.closed || !r.curvature) continue;
    ++lent;
    std::vector<double> x = r.x;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (a.parameters()[i].spec.tag == ParamTag::kUnbounded) x[i] = wrap_360(x[i]);
    }
    const detail::StabilityReport made = detail::check_stability(p, vars, x, options);
    const detail::StabilityReport reused = detail::check_stability(p, vars, x, options, &r);
    EXPECT_EQ(made.slips.size(), reused.slips.size());
    EXPECT_EQ(made.equilibrium_residual, reused.equilibrium_residual);
    EXPECT_EQ(made.neutral_directions.size(), reused.neutral_directions.size());
    // The same model up to the Hessian's own precision (its closure terms are differenced)
    // and the angles' whole turns: the largest curvature, which sets the threshold, to 10⁻⁶,
    // the smallest to a hundredth of the threshold, and so the same verdict.
    EXPECT_NEAR(made.neutral_threshold, reused.neutral_threshold, 1e-6 * made.neutral_threshold);
    EXPECT_NEAR(made.smallest_curvature,
                reused.smallest_curvature,
                std::max(1e-12, 0.01 * made.neutral_threshold));
    EXPECT_EQ(made.smallest_curvature < -made.neutral_threshold,
              reused.smallest_curvature < -reused.neutral_threshold);
    // Not a relaxation's end: nothing is lent, and the check makes its own.
    detail::StepResult elsewhere = r;
    elsewhere.x[static_cast<std::size_t>(vars.index.front())] += 1.0;
    const detail::StabilityReport own = detail::check_stability(p, vars, x, options, &elsewhere);
    EXPECT_EQ(own.smallest_curvature, made.smallest_curvature);
  }
  // Most of the gallery's relaxations end at a minimum without contact rows binding.
  EXPECT_GE(lent, 8);
}

// The solver leaves gauge pairs out of its large models (ManifoldSolverOptions::
// fold_gauge_from): two turns whose sum alone moves anything. What the evaluator reports as one
// must be one: every part stays where it is when the pair turns along its null direction by a
// finite angle, and moves when one of them turns alone. A chain of S-hooks has one per hook on
// a hook; a hook on the rod has none (its turns are about other axes).
TEST(Properties, GaugePairsMoveNothing) {
  std::string yaml =
      "fabkit: hacks/1\nname: chain\nenvironment:\n"
      "  - {name: bar, primitives: {rod: {type: rod, radius: 4, length: 300}}, "
      "frame: {pos: [0, 0, 3000], rot: [90, 0, 0]}}\nparts:\n";
  constexpr int kHooks = 12;
  for (int i = 1; i <= kHooks; ++i) yaml += fmt::format("  - {{name: s{}, part: DoubleHook}}\n", i);
  yaml += "connections:\n  - connect: [s1.hook1, bar.rod]\n";
  for (int i = 2; i <= kHooks; ++i) {
    yaml += fmt::format("  - connect: [s{}.hook1, s{}.hook2]\n", i, i - 1);
  }
  const Design d = load_design_text(yaml, "chain.yaml", PartsLibrary::builtin());
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const Assembly& a = d.assembly;
  const detail::Problem p = detail::make_problem(a);
  const detail::Variables vars = detail::select_variables(a, /*physics=*/true, &p);
  const detail::AnalyticEvaluator evaluator(p, vars, a.values(), detail::Objective::kEnergy);
  const auto pairs = evaluator.gauge_pairs();
  EXPECT_EQ(pairs.size(), static_cast<std::size_t>(kHooks - 1));
  auto moved = [&](const std::vector<double>& x) {
    const std::vector<Mat4> before = a.part_frames(a.values());
    const std::vector<Mat4> after = a.part_frames(x);
    double most = 0;
    for (std::size_t i = 0; i < before.size(); ++i) {
      most = std::max(most, (after[i] - before[i]).cwiseAbs().maxCoeff());
    }
    return most;
  };
  for (const auto& g : pairs) {
    const auto ia = static_cast<std::size_t>(vars.index[static_cast<std::size_t>(g.a)]);
    const auto ib = static_cast<std::size_t>(vars.index[static_cast<std::size_t>(g.b)]);
    const Connection& joint = a.connection(a.parameters()[ia].connection);
    EXPECT_EQ(a.parameters()[ib].connection.value, a.parameters()[ia].connection.value);
    EXPECT_FALSE(a.nodes()[joint.first.part.index()].environment) << "a pair on the rod";
    // z = x / scale: a step t along (null_a, null_b) in z is t·scale·null in x.
    const double sa = vars.scale[static_cast<std::size_t>(g.a)];
    const double sb = vars.scale[static_cast<std::size_t>(g.b)];
    for (double t : {-40.0, 25.0}) {
      std::vector<double> x = a.values();
      x[ia] += t * sa * g.null_a;
      x[ib] += t * sb * g.null_b;
      EXPECT_LT(moved(x), 1e-9) << a.parameters()[ia].spec.name << " and "
                                << a.parameters()[ib].spec.name;
      std::vector<double> alone = a.values();
      alone[ia] += t * sa * g.null_a;
      EXPECT_GT(moved(alone), 1e-3);
    }
  }
}

// Two S-hooks hung the same way from one rail are twins: their parameters' structural keys are
// equal (the keys know where a part hangs from what, not its name), so keyed draws gave both
// the same place on the rail on every draw. Now the second twin, by where they are, draws by a
// key of its own; the first keeps the key, so designs without twins draw as before.
TEST(Properties, TwinsOnOneRailDrawApart) {
  const Design d = testing::load_text(R"(fabkit: hacks/1
environment:
  - {name: rail, primitives: {rod: {type: rod, radius: 6, length: 900}}, frame: {pos: [0, 0, 1200], rot: [0, 90, 0]}}
parts:
  - {name: s1, part: DoubleHook}
  - {name: s2, part: DoubleHook}
connections:
  - connect: [s1.hook1, rail.rod]
  - connect: [s2.hook1, rail.rod]
)");
  ASSERT_TRUE(d.feasible()) << d.diagnostics.format();
  const Assembly& a = d.assembly;
  const detail::Problem p = detail::make_problem(a);
  const detail::Variables vars = detail::select_variables(a, /*physics=*/true, &p);
  std::vector<int> rail_t;  // where each hook hangs along the rail
  for (int v : vars.index) {
    const ParamInfo& info = a.parameters()[static_cast<std::size_t>(v)];
    if (a.node(info.part).environment && info.spec.name == "t") rail_t.push_back(v);
  }
  ASSERT_EQ(rail_t.size(), 2u);
  const std::vector<std::string> keys = a.parameter_keys();
  ASSERT_EQ(keys[static_cast<std::size_t>(rail_t[0])], keys[static_cast<std::size_t>(rail_t[1])]);
  // Ordered by where they are: the hook nearer the rail's start (the smaller t) keeps the key,
  // whichever connect made it.
  for (const bool swap : {false, true}) {
    std::vector<double> x = a.values();
    x[static_cast<std::size_t>(rail_t[0])] = swap ? 0.7 : 0.2;
    x[static_cast<std::size_t>(rail_t[1])] = swap ? 0.2 : 0.7;
    const int nearer = swap ? rail_t[1] : rail_t[0];
    const std::vector<std::string> drawn = detail::draw_keys(p, vars.index, x);
    for (std::size_t k = 0; k < vars.index.size(); ++k) {
      const std::string& plain = keys[static_cast<std::size_t>(vars.index[k])];
      if (vars.index[k] == nearer) {
        EXPECT_EQ(drawn[k], plain) << swap;
      } else if (vars.index[k] == rail_t[0] || vars.index[k] == rail_t[1]) {
        EXPECT_EQ(drawn[k], plain + "#twin1") << swap;
      }
    }
  }
  const std::vector<double> x = a.values();
  int apart = 0;
  for (int stream = 0; stream < 20; ++stream) {
    std::vector<double> y = x;
    detail::draw_keyed(p, vars.index, 1, stream, /*unbounded_only=*/false, y);
    const double spread =
        std::abs(y[static_cast<std::size_t>(rail_t[0])] - y[static_cast<std::size_t>(rail_t[1])]);
    apart += spread > 0.05 ? 1 : 0;  // 45 mm along the 900 mm rail
  }
  EXPECT_GE(apart, 15);  // uniform draws: 90 % of pairs are more than a twentieth apart
}

}  // namespace
}  // namespace fabkit::hacks

// The manifold solver on problems whose answers are known in closed form (constrained
// quadratics, a potential with a saddle), and its deadline: a called deadline stops it, and an
// iteration it cannot finish in time is not started.
#include "fabkit/core/solvers/manifold_solver.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <thread>

namespace fabkit::solvers {
namespace {

using Clock = std::chrono::steady_clock;

// f = ½ zᵀAz − bᵀz subject to Σ z = 1.
class ConstrainedQuadratic : public ManifoldProblem {
 public:
  ConstrainedQuadratic(Eigen::MatrixXd a, Eigen::VectorXd b) : a_(std::move(a)), b_(std::move(b)) {}
  int variables() const override { return static_cast<int>(b_.size()); }
  int objectives() const override { return 1; }
  int equalities() const override { return 1; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    const Eigen::Map<const Eigen::VectorXd> x(z, variables());
    const Eigen::VectorXd g = a_ * x - b_;
    values[0] = 0.5 * x.dot(a_ * x) - b_.dot(x);
    values[1] = x.sum() - 1;
    for (int k = 0; k < variables(); ++k) {
      jacobian[k] = g[k];
      jacobian[variables() + k] = 1;
    }
  }

 private:
  Eigen::MatrixXd a_;
  Eigen::VectorXd b_;
};

// A random positive definite A, b, and the minimum of ½ zᵀAz − bᵀz subject to Σ z = 1 (the
// Lagrange conditions A z − b = λ·1 and Σ z = 1).
struct RandomQuadratic {
  Eigen::MatrixXd a;
  Eigen::VectorXd b, minimum;
};

RandomQuadratic random_quadratic(int n, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = normal(rng);
  RandomQuadratic q;
  q.a = m * m.transpose() / n + Eigen::MatrixXd::Identity(n, n);
  q.b.resize(n);
  for (int i = 0; i < n; ++i) q.b[i] = 10 * normal(rng);
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + 1, n + 1);
  kkt.topLeftCorner(n, n) = q.a;
  kkt.topRightCorner(n, 1).setOnes();
  kkt.bottomLeftCorner(1, n).setOnes();
  Eigen::VectorXd rhs(n + 1);
  rhs << q.b, 1;
  q.minimum = kkt.fullPivLu().solve(rhs).head(n);
  return q;
}

// 40 variables: the eigenbasis formed; 120: factored (Eigenbasis::kFactoredFrom).
class ConstrainedQuadraticOf : public testing::TestWithParam<int> {};

TEST_P(ConstrainedQuadraticOf, RelaxReachesItsMinimum) {
  const int n = GetParam();
  std::mt19937 rng(7);
  const RandomQuadratic q = random_quadratic(n, rng);
  const Eigen::VectorXd& expected = q.minimum;

  ConstrainedQuadratic problem(q.a, q.b);
  const double inf = std::numeric_limits<double>::infinity();
  ManifoldSolver solver(
      problem, Eigen::VectorXd::Constant(n, -inf), Eigen::VectorXd::Constant(n, inf));
  const ManifoldSolver::Result r = solver.relax(Eigen::VectorXd::Constant(n, 1.0 / n), 500);
  ASSERT_TRUE(r.closed);
  EXPECT_TRUE(r.converged);
  EXPECT_FALSE(r.timed_out);
  EXPECT_LT((r.z - expected).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(r.z.sum(), 1.0, 1e-9);
}
INSTANTIATE_TEST_SUITE_P(ManifoldSolver, ConstrainedQuadraticOf, testing::Values(40, 120));

// f = ½ uᵀAu − bᵀu subject to Σ u = 1, over u_i = z_2i + 2·z_2i+1: each pair (2i, 2i+1) is a
// gauge, its null direction (2, −1).
class GaugeQuadratic : public ManifoldProblem {
 public:
  GaugeQuadratic(Eigen::MatrixXd a, Eigen::VectorXd b) : a_(std::move(a)), b_(std::move(b)) {}
  int variables() const override { return 2 * static_cast<int>(b_.size()); }
  int objectives() const override { return 1; }
  int equalities() const override { return 1; }
  int inequalities() const override { return 0; }
  Eigen::VectorXd combined(const Eigen::VectorXd& z) const {
    Eigen::VectorXd u(b_.size());
    for (int i = 0; i < u.size(); ++i) u[i] = z[2 * i] + 2 * z[2 * i + 1];
    return u;
  }
  void evaluate(const double* z, double* values, double* jacobian) override {
    const Eigen::VectorXd u = combined(Eigen::Map<const Eigen::VectorXd>(z, variables()));
    const Eigen::VectorXd g = a_ * u - b_;
    values[0] = 0.5 * u.dot(a_ * u) - b_.dot(u);
    values[1] = u.sum() - 1;
    for (int i = 0; i < u.size(); ++i) {
      jacobian[2 * i] = g[i];
      jacobian[2 * i + 1] = 2 * g[i];
      jacobian[variables() + 2 * i] = 1;
      jacobian[variables() + 2 * i + 1] = 2;
    }
  }
  std::vector<GaugePair> gauge_pairs() const override {
    std::vector<GaugePair> out;
    for (int i = 0; i < static_cast<int>(b_.size()); ++i) out.push_back({2 * i, 2 * i + 1, 2, -1});
    return out;
  }

 private:
  Eigen::MatrixXd a_;
  Eigen::VectorXd b_;
};

// A random start of the gauge problem that meets its constraint Σ u = 1.
Eigen::VectorXd closed_gauge_start(const GaugeQuadratic& problem, int m, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::VectorXd start(2 * m);
  for (int i = 0; i < 2 * m; ++i) start[i] = 0.3 * normal(rng);
  const double gap = problem.combined(start).sum() - 1;
  for (int i = 0; i < m; ++i) start[2 * i] -= gap / m;
  return start;
}

// Folded (the default from 64 free coordinates) or not, relax reaches the same minimum, and
// folded it never moves along a gauge's null direction.
TEST(ManifoldSolver, GaugePairsFoldedRestWhereTheyRestUnfolded) {
  constexpr int m = 45;  // 90 variables
  std::mt19937 rng(17);
  const RandomQuadratic q = random_quadratic(m, rng);
  const Eigen::VectorXd& expected = q.minimum;

  GaugeQuadratic problem(q.a, q.b);
  const Eigen::VectorXd start = closed_gauge_start(problem, m, rng);
  const double inf = std::numeric_limits<double>::infinity();
  for (int fold_from : {64, 1 << 30}) {
    SCOPED_TRACE(testing::Message() << "fold from " << fold_from);
    ManifoldSolverOptions o;
    o.fold_gauge_from = fold_from;
    ManifoldSolver solver(
        problem, Eigen::VectorXd::Constant(2 * m, -inf), Eigen::VectorXd::Constant(2 * m, inf), o);
    const ManifoldSolver::Result r = solver.relax(start, 500);
    ASSERT_TRUE(r.closed);
    EXPECT_TRUE(r.converged);
    EXPECT_LT((problem.combined(r.z) - expected).cwiseAbs().maxCoeff(), 1e-6);
    // Along (2, −1) per pair: 2·z_2i − z_2i+1 is where it started.
    double drift = 0;
    for (int i = 0; i < m; ++i) {
      drift = std::max(
          drift,
          std::abs((2 * r.z[2 * i] - r.z[2 * i + 1]) - (2 * start[2 * i] - start[2 * i + 1])));
    }
    // Folded, no step has a component there (unfolded, round-off of the neutral eigenvectors
    // walks it by about 1e-8).
    if (fold_from == 64) {
      EXPECT_LT(drift, 1e-11);
    }
  }
}

// A relaxation that ends at a minimum can hand back its last model as the curvature there:
// the one curvature() makes at that point (every eigenvalue, the neutral directions' span,
// the free coordinates and rows), folded or not; only when asked.
TEST(ManifoldSolver, RelaxHandsBackTheCurvatureWhereItRests) {
  constexpr int m = 45;  // 90 variables, a gauge per pair: 45 neutral directions unfolded
  std::mt19937 rng(23);
  const RandomQuadratic q = random_quadratic(m, rng);
  GaugeQuadratic problem(q.a, q.b);
  const Eigen::VectorXd start = closed_gauge_start(problem, m, rng);
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(2 * m, -inf);
  const Eigen::VectorXd hi = Eigen::VectorXd::Constant(2 * m, inf);
  for (int fold_from : {64, 1 << 30}) {
    SCOPED_TRACE(testing::Message() << "fold from " << fold_from);
    ManifoldSolverOptions o;
    o.fold_gauge_from = fold_from;
    EXPECT_FALSE(ManifoldSolver(problem, lo, hi, o).relax(start, 500).curvature.has_value());
    o.curvature_at_rest = true;
    ManifoldSolver solver(problem, lo, hi, o);
    const ManifoldSolver::Result r = solver.relax(start, 500);
    ASSERT_TRUE(r.closed && r.converged);
    ASSERT_TRUE(r.curvature.has_value());
    const ManifoldSolver::Curvature made = solver.curvature(solver.evaluate(r.z));
    const ManifoldSolver::Curvature& handed = *r.curvature;
    EXPECT_EQ(handed.free, made.free);
    EXPECT_EQ(handed.rows, made.rows);
    EXPECT_EQ(handed.binding, 0);
    ASSERT_EQ(handed.eigenvalues.size(), made.eigenvalues.size());
    const double largest = made.eigenvalues.cwiseAbs().maxCoeff();
    EXPECT_LT((handed.eigenvalues - made.eigenvalues).cwiseAbs().maxCoeff(), 1e-9 * largest);
    EXPECT_NEAR(handed.neutral_threshold, made.neutral_threshold, 1e-9 * made.neutral_threshold);
    ASSERT_EQ(handed.directions.cols(), made.directions.cols());
    EXPECT_EQ(made.directions.cols(), fold_from == 64 ? 0 : m);
    if (made.directions.cols() > 0) {
      // The same span: each handed direction lies in the made ones' (orthonormal) span.
      const Eigen::MatrixXd off =
          handed.directions - made.directions * (made.directions.transpose() * handed.directions);
      EXPECT_LT(off.cwiseAbs().maxCoeff(), 1e-8);
    }
  }
}

// Residuals r = B·z − d, fewer than the variables.
class LinearResiduals : public ManifoldProblem {
 public:
  LinearResiduals(Eigen::MatrixXd b, Eigen::VectorXd d) : b_(std::move(b)), d_(std::move(d)) {}
  int variables() const override { return static_cast<int>(b_.cols()); }
  int objectives() const override { return static_cast<int>(b_.rows()); }
  int equalities() const override { return 0; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    const Eigen::Map<const Eigen::VectorXd> x(z, variables());
    const Eigen::VectorXd r = b_ * x - d_;
    for (int i = 0; i < objectives(); ++i) {
      values[i] = r[i];
      for (int k = 0; k < variables(); ++k) jacobian[i * variables() + k] = b_(i, k);
    }
  }

 private:
  Eigen::MatrixXd b_;
  Eigen::VectorXd d_;
};

// Levenberg-Marquardt from z = 0 steps only within B's row space, so it ends at the
// minimum-norm least-squares solution B⁺·d: with 4 residuals and 8 variables (the damped
// system of the variables) and 60 (the SVD the size of the residuals), with independent
// rows, and with a row that is the sum of two others and a d no z meets (residuals left).
TEST(ManifoldSolver, FitEndsAtTheMinimumNormLeastSquaresSolution) {
  std::mt19937 rng(13);
  std::normal_distribution<double> normal;
  for (int n : {8, 60}) {
    for (bool dependent : {false, true}) {
      SCOPED_TRACE(testing::Message() << n << " variables, dependent rows " << dependent);
      Eigen::MatrixXd b(4, n);
      for (int i = 0; i < 4; ++i)
        for (int k = 0; k < n; ++k) b(i, k) = normal(rng);
      Eigen::VectorXd d(4);
      for (int i = 0; i < 4; ++i) d[i] = 10 * normal(rng);
      if (dependent) b.row(3) = b.row(0) + b.row(1);
      const Eigen::VectorXd expected = b.completeOrthogonalDecomposition().solve(d);
      LinearResiduals problem(b, d);
      const double inf = std::numeric_limits<double>::infinity();
      ManifoldSolver solver(
          problem, Eigen::VectorXd::Constant(n, -inf), Eigen::VectorXd::Constant(n, inf));
      const ManifoldSolver::Result r = solver.fit(Eigen::VectorXd::Zero(n), 200);
      ASSERT_TRUE(r.closed);
      EXPECT_LT((r.z - expected).cwiseAbs().maxCoeff(), 1e-6 * expected.norm());
      const double left = (b * expected - d).norm();
      EXPECT_NEAR((b * r.z - d).norm(), left, 1e-6 * d.norm());
      if (dependent) {
        EXPECT_GT(left, 1e-3);
      }
    }
  }
}

// f = Σ xᵢ² + (y² − 1)² over n − 1 variables x and the last, y: a saddle at the origin,
// minima at x = 0, y = ±1.
class Saddle : public ManifoldProblem {
 public:
  explicit Saddle(int n = 2) : n_(n) {}
  int variables() const override { return n_; }
  int objectives() const override { return 1; }
  int equalities() const override { return 0; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    const double y = z[n_ - 1];
    values[0] = (y * y - 1) * (y * y - 1);
    for (int i = 0; i + 1 < n_; ++i) {
      values[0] += z[i] * z[i];
      jacobian[i] = 2 * z[i];
    }
    jacobian[n_ - 1] = 4 * y * (y * y - 1);
  }

 private:
  int n_;
};

TEST(ManifoldSolver, RelaxLeavesASaddleForAMinimum) {
  Saddle problem;
  const double inf = std::numeric_limits<double>::infinity();
  ManifoldSolver solver(problem, Eigen::Vector2d(-inf, -inf), Eigen::Vector2d(inf, inf));
  const ManifoldSolver::Result r = solver.relax(Eigen::Vector2d(0.0, 0.0), 200);
  EXPECT_NEAR(r.z[0], 0.0, 1e-6);
  EXPECT_NEAR(std::abs(r.z[1]), 1.0, 1e-6) << "the balance point at y = 0 is not a rest state";
  EXPECT_GE(r.escapes, 1);
}

// The same in 100 dimensions, where the step's eigenbasis is factored.
TEST(ManifoldSolver, RelaxLeavesASaddleForAMinimumInManyDimensions) {
  constexpr int n = 100;
  Saddle problem(n);
  const double inf = std::numeric_limits<double>::infinity();
  ManifoldSolver solver(
      problem, Eigen::VectorXd::Constant(n, -inf), Eigen::VectorXd::Constant(n, inf));
  Eigen::VectorXd start = Eigen::VectorXd::Zero(n);
  for (int i = 0; i + 1 < n; ++i) start[i] = 0.01 * ((i % 7) - 3);
  const ManifoldSolver::Result r = solver.relax(start, 300);
  EXPECT_TRUE(r.converged);
  EXPECT_LT(r.z.head(n - 1).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_NEAR(std::abs(r.z[n - 1]), 1.0, 1e-6) << "the balance point at y = 0 is not a rest state";
}

// f = z⁴: Newton's steps only take a third off z each time (the curvature vanishes at the
// minimum), so the last stretch to the slope tolerance creeps, lowering f less and less.
class Quartic : public ManifoldProblem {
 public:
  int variables() const override { return 1; }
  int objectives() const override { return 1; }
  int equalities() const override { return 0; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    values[0] = std::pow(z[0], 4);
    jacobian[0] = 4 * std::pow(z[0], 3);
  }
  bool lagrangian_hessian(const double* z,
                          const std::vector<int>&,
                          const Eigen::VectorXd&,
                          Eigen::MatrixXd& hessian) override {
    hessian = Eigen::MatrixXd::Constant(1, 1, 12 * z[0] * z[0]);
    return true;
  }
};

TEST(ManifoldSolver, RelaxEndsWhereItsProgressWindowGainsTooLittle) {
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(1, -inf);
  const Eigen::VectorXd hi = Eigen::VectorXd::Constant(1, inf);
  const Eigen::VectorXd start = Eigen::VectorXd::Constant(1, 1.0);
  Quartic problem;
  ManifoldSolver full(problem, lo, hi);
  const ManifoldSolver::Result to_rest = full.relax(start, 500);
  ASSERT_TRUE(to_rest.converged);
  EXPECT_LT(std::abs(4 * std::pow(to_rest.z[0], 3)), 1e-9);

  ManifoldSolverOptions o;
  o.progress_window = 3;
  o.least_progress = 1e-4;
  ManifoldSolver windowed(problem, lo, hi, o);
  const ManifoldSolver::Result started = windowed.relax(start, 500);
  // It ended early, once three steps gained under 1e-4 together: f had fallen below that
  // (so z below 0.1), and it was still sloping well above the tolerance.
  EXPECT_LT(started.iterations, to_rest.iterations);
  EXPECT_LT(std::pow(started.z[0], 4), 1e-4);
  EXPECT_GT(std::abs(4 * std::pow(started.z[0], 3)), 1e-6);
  // A window that gains enough never ends it early.
  o.least_progress = 0;
  ManifoldSolver patient(problem, lo, hi, o);
  EXPECT_EQ(patient.relax(start, 500).iterations, to_rest.iterations);
}

// Residuals r = (10·(y − x²), 1 − x, 3 + x² + y²): a curved valley (Rosenbrock's) in which
// the third residual stays near 3, its curvature missing from the Gauss-Newton model: from
// (−1.5, 2) Levenberg-Marquardt crawls (ten iterations lower ½‖r‖², about 4.9, by under 1 %)
// short of the minimum (its slope still about 10⁻⁶), and the fit is finished by Newton's method on
// ½‖r‖² — unless ½‖r‖² is below the threshold set for that.
class LargeResiduals : public ManifoldProblem {
 public:
  int variables() const override { return 2; }
  int objectives() const override { return 3; }
  int equalities() const override { return 0; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    const double x = z[0], y = z[1];
    values[0] = 10 * (y - x * x);
    values[1] = 1 - x;
    values[2] = 3 + x * x + y * y;
    jacobian[0] = -20 * x;
    jacobian[1] = 10;
    jacobian[2] = -1;
    jacobian[3] = 0;
    jacobian[4] = 2 * x;
    jacobian[5] = 2 * y;
  }
  // The slope of ½‖r‖² at z.
  Eigen::Vector2d slope(const Eigen::VectorXd& z) {
    double v[3], j[6];
    evaluate(z.data(), v, j);
    const Eigen::Map<const Eigen::Matrix<double, 3, 2, Eigen::RowMajor>> jac(j);
    return jac.transpose() * Eigen::Map<const Eigen::Vector3d>(v);
  }
};

TEST(ManifoldSolver, AFitCrawlingBelowItsFinishThresholdIsNotFinished) {
  const double inf = std::numeric_limits<double>::infinity();
  const Eigen::VectorXd lo = Eigen::VectorXd::Constant(2, -inf);
  const Eigen::VectorXd hi = Eigen::VectorXd::Constant(2, inf);
  const Eigen::VectorXd start = Eigen::Vector2d(-1.5, 2.0);
  LargeResiduals problem;
  auto fit_with = [&](double finish_above) {
    ManifoldSolverOptions o;
    o.finish_above = finish_above;
    ManifoldSolver solver(problem, lo, hi, o);
    return solver.fit(start, 500);
  };
  const ManifoldSolver::Result finished = fit_with(0);
  EXPECT_LT(problem.slope(finished.z).norm(), 1e-8);
  // Above ½‖r‖² where it crawls, the fit ends there: short of the minimum, and sooner.
  const ManifoldSolver::Result crawled = fit_with(5.5);
  EXPECT_GT(problem.slope(crawled.z).norm(), 1e-7);
  EXPECT_LT(crawled.iterations, finished.iterations);
  // Below it, the finish runs as without a threshold.
  const ManifoldSolver::Result below = fit_with(4.5);
  EXPECT_EQ(below.iterations, finished.iterations);
  EXPECT_EQ(below.z, finished.z);
}

// The end of a planar chain of n unit links, each turned by z_k from the one before (radians):
// residuals end − goal. Near full stretch the goal is reachable but the chain's Jacobian nearly
// loses a rank, and Levenberg-Marquardt closes in on it slowly.
class PlanarReach : public ManifoldProblem {
 public:
  PlanarReach(int n, Eigen::Vector2d goal) : n_(n), goal_(std::move(goal)) {}
  int variables() const override { return n_; }
  int objectives() const override { return 2; }
  int equalities() const override { return 0; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    std::vector<double> heading(static_cast<std::size_t>(n_));
    double a = 0;
    for (int k = 0; k < n_; ++k) heading[static_cast<std::size_t>(k)] = a += z[k];
    Eigen::Vector2d end = Eigen::Vector2d::Zero();
    for (double h : heading) end += Eigen::Vector2d(std::cos(h), std::sin(h));
    values[0] = end.x() - goal_.x();
    values[1] = end.y() - goal_.y();
    // Turning joint k swings every link from k on about the joint's point.
    for (int k = 0; k < n_; ++k) {
      Eigen::Vector2d tail = Eigen::Vector2d::Zero();
      for (int j = k; j < n_; ++j) {
        const double h = heading[static_cast<std::size_t>(j)];
        tail += Eigen::Vector2d(std::cos(h), std::sin(h));
      }
      jacobian[k] = -tail.y();
      jacobian[n_ + k] = tail.x();
    }
  }

 private:
  int n_;
  Eigen::Vector2d goal_;
};

// Reaching straight out, the goal is the chain fully stretched, where its Jacobian loses a rank:
// Levenberg-Marquardt converges there only linearly (about 400 iterations). A fit within its
// caller's threshold that no longer halves ½‖r‖² in ten iterations stops where it is.
TEST(ManifoldSolver, AFitConvergingSlowlyWithinItsThresholdStops) {
  const double inf = std::numeric_limits<double>::infinity();
  constexpr int kLinks = 30;
  PlanarReach problem(kLinks, Eigen::Vector2d(kLinks, 0.0));
  auto fit_with = [&](double finish_above) {
    ManifoldSolverOptions o;
    o.finish_above = finish_above;
    ManifoldSolver solver(problem,
                          Eigen::VectorXd::Constant(kLinks, -inf),
                          Eigen::VectorXd::Constant(kLinks, inf),
                          o);
    return solver.fit(Eigen::VectorXd::Constant(kLinks, 0.2), 500);
  };
  auto half_squared = [&](const ManifoldSolver::Result& r) {
    double v[2];
    std::vector<double> jacobian(2 * kLinks);
    problem.evaluate(r.z.data(), v, jacobian.data());
    return 0.5 * (v[0] * v[0] + v[1] * v[1]);
  };
  const ManifoldSolver::Result full = fit_with(0);
  EXPECT_LT(half_squared(full), 1e-8);
  const ManifoldSolver::Result near = fit_with(1e-2);
  EXPECT_TRUE(near.converged);
  EXPECT_LT(near.iterations, full.iterations / 2);
  EXPECT_LE(half_squared(near), 1e-2);
  EXPECT_GT(half_squared(near), 1e-6);
}

// h = (1 + z², (z − 3)/100) = 0 has no solution: ‖h‖² has its least positive value near
// z = 0, which Levenberg-Marquardt approaches step by step, each lowering ‖h‖² a little.
class UnclosableGap : public ManifoldProblem {
 public:
  int evaluations = 0;
  int variables() const override { return 1; }
  int objectives() const override { return 1; }
  int equalities() const override { return 2; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    ++evaluations;
    values[0] = 0;
    values[1] = 1 + z[0] * z[0];
    values[2] = (z[0] - 3) / 100;
    jacobian[0] = 0;
    jacobian[1] = 2 * z[0];
    jacobian[2] = 0.01;
  }
};

TEST(ManifoldSolver, CloseGivesUpOnAGapThatStopsHalving) {
  const double inf = std::numeric_limits<double>::infinity();
  UnclosableGap problem;
  ManifoldSolver solver(
      problem, Eigen::VectorXd::Constant(1, -inf), Eigen::VectorXd::Constant(1, inf));
  Eigen::VectorXd z = Eigen::VectorXd::Constant(1, 10.0);
  EXPECT_FALSE(solver.close(z, 100));
  EXPECT_DOUBLE_EQ(z[0], 10.0) << "an unclosed start is left as it was";
  // The gap halves while z falls from 10 to about 1, then barely moves: ten iterations after
  // that it is abandoned, not followed until its steps stop lowering it.
  EXPECT_LE(problem.evaluations, 35);  // 47 when followed until its steps stop lowering it
}

// f = ½‖z − c‖², each evaluation taking `pause` (a model of an expensive step).
class SlowBowl : public ManifoldProblem {
 public:
  explicit SlowBowl(std::chrono::milliseconds pause) : pause_(pause) {}
  int variables() const override { return 2; }
  int objectives() const override { return 1; }
  int equalities() const override { return 0; }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    std::this_thread::sleep_for(pause_);
    const double dx = z[0] - 1000, dy = z[1] + 1000;
    values[0] = 0.5 * (dx * dx + dy * dy);
    jacobian[0] = dx;
    jacobian[1] = dy;
  }
  bool lagrangian_hessian(const double*,
                          const std::vector<int>&,
                          const Eigen::VectorXd&,
                          Eigen::MatrixXd& hessian) override {
    hessian = Eigen::MatrixXd::Identity(2, 2);
    return true;
  }

 private:
  std::chrono::milliseconds pause_;
};

TEST(ManifoldSolver, ACalledDeadlineStopsItBeforeAnyIteration) {
  SlowBowl problem(std::chrono::milliseconds(0));
  auto stop = std::make_shared<StopClock>(Clock::now() + std::chrono::hours(1));
  ASSERT_TRUE(stop->would_pass(std::chrono::hours(2)));  // another step called it
  ManifoldSolverOptions o;
  o.stop = stop;
  const double inf = std::numeric_limits<double>::infinity();
  ManifoldSolver solver(problem, Eigen::Vector2d(-inf, -inf), Eigen::Vector2d(inf, inf), o);
  const ManifoldSolver::Result r = solver.relax(Eigen::Vector2d(0, 0), 100);
  EXPECT_TRUE(r.timed_out);
  EXPECT_EQ(r.iterations, 0);
}

TEST(ManifoldSolver, DoesNotStartAnIterationItCannotFinishBeforeTheDeadline) {
  // An iteration costs one evaluation (the trial point), 10 ms; the start costs one too. With
  // the deadline at 25 ms, the second iteration would end at about 30 ms: it is not started,
  // and the deadline is called (the caller's later steps see it passed).
  SlowBowl problem(std::chrono::milliseconds(10));
  auto stop = std::make_shared<StopClock>(Clock::now() + std::chrono::milliseconds(25));
  ManifoldSolverOptions o;
  o.stop = stop;
  o.max_step = 1;  // the bowl's bottom is ~1400 steps away: time, not convergence, ends it
  const double inf = std::numeric_limits<double>::infinity();
  ManifoldSolver solver(problem, Eigen::Vector2d(-inf, -inf), Eigen::Vector2d(inf, inf), o);
  const ManifoldSolver::Result r = solver.relax(Eigen::Vector2d(0, 0), 100);
  EXPECT_TRUE(r.timed_out);
  EXPECT_TRUE(stop->passed());
  // Sleeps last at least as long as asked: at most one iteration fits (none if the machine
  // was slow to start).
  EXPECT_LE(r.iterations, 1);
}

// The null space of the kept rows: orthonormal, annihilated by the rows, of the dimension the
// rank leaves (redundant rows, as fixed joints make, count once), empty when nothing may move.
TEST(ManifoldSolver, NullSpaceOfRedundantAndFullRows) {
  EXPECT_TRUE(ManifoldSolver::null_space(Eigen::MatrixXd(0, 3)).isIdentity());
  const Eigen::MatrixXd full = Eigen::MatrixXd::Identity(3, 3) * 2;
  EXPECT_EQ(ManifoldSolver::null_space(full).rows(), 3);
  EXPECT_EQ(ManifoldSolver::null_space(full).cols(), 0);
  Eigen::MatrixXd rows(3, 5);
  rows << 1, 2, 0, 0, 1,  //
      0, 1, 1, 0, 0,      //
      1, 3, 1, 0, 1;      // the sum of the first two
  const Eigen::MatrixXd z = ManifoldSolver::null_space(rows);
  ASSERT_EQ(z.cols(), 3);
  EXPECT_LT((rows * z).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((z.transpose() * z - Eigen::MatrixXd::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-12);
}

// The projection's step: it solves the rows, consistently redundant ones included, and is the
// shortest such step (orthogonal to the null space); nothing to solve gives no step.
TEST(ManifoldSolver, MinimumNormSolutionOfRedundantAndFullRows) {
  EXPECT_EQ(ManifoldSolver::min_norm_solution(Eigen::MatrixXd(0, 4), Eigen::VectorXd(0)),
            Eigen::VectorXd::Zero(4));
  EXPECT_EQ(ManifoldSolver::min_norm_solution(Eigen::MatrixXd::Zero(2, 3), Eigen::Vector2d(0, 0)),
            Eigen::VectorXd::Zero(3));
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  for (int redundant = 0; redundant <= 1; ++redundant) {
    Eigen::MatrixXd a(4, 7);
    for (int i = 0; i < a.rows(); ++i)
      for (int j = 0; j < a.cols(); ++j) a(i, j) = normal(rng);
    Eigen::VectorXd b(4);
    for (int i = 0; i < 4; ++i) b[i] = normal(rng);
    if (redundant) {
      a.row(3) = 2 * a.row(0) - a.row(1);  // a fixed joint's rows: one the others imply
      b[3] = 2 * b[0] - b[1];
    }
    const Eigen::VectorXd x = ManifoldSolver::min_norm_solution(a, b);
    EXPECT_LT((a * x - b).cwiseAbs().maxCoeff(), 1e-10) << "redundant " << redundant;
    const Eigen::MatrixXd z = ManifoldSolver::null_space(a);
    EXPECT_EQ(z.cols(), redundant ? 4 : 3);
    EXPECT_LT((z.transpose() * x).cwiseAbs().maxCoeff(), 1e-10) << "redundant " << redundant;
    // The same as the complete orthogonal decomposition's minimum-norm answer.
    EXPECT_LT((x - a.completeOrthogonalDecomposition().solve(b)).cwiseAbs().maxCoeff(), 1e-9);
  }
}

// Multipliers of rows that are redundant up to round-off (a fixed joint's, or a held target's
// 12 rows of rank 6): those rows count once, and the answer is the minimum-norm one, not one
// that divides by the round-off.
TEST(ManifoldSolver, MultipliersOfRowsRedundantUpToRoundOff) {
  Eigen::MatrixXd rows(2, 3);
  rows << 1, 0, 0,  //
      1, 1e-12, 0;  // the first row, up to round-off
  const Eigen::VectorXd lambda =
      ManifoldSolver::least_squares_multipliers(rows, Eigen::Vector3d(1, 2, 3));
  ASSERT_EQ(lambda.size(), 2);
  EXPECT_NEAR(lambda[0], 0.5, 1e-9);
  EXPECT_NEAR(lambda[1], 0.5, 1e-9);
  // Independent rows get the exact least-squares multipliers.
  Eigen::MatrixXd independent(2, 3);
  independent << 1, 0, 0,  //
      0, 2, 0;
  const Eigen::VectorXd exact =
      ManifoldSolver::least_squares_multipliers(independent, Eigen::Vector3d(1, 2, 3));
  EXPECT_NEAR(exact[0], 1.0, 1e-12);
  EXPECT_NEAR(exact[1], 1.0, 1e-12);
}

// A potential under linear equalities C·z = d (C may repeat a row: a fixed joint's rows).
class UnderRows : public ManifoldProblem {
 public:
  explicit UnderRows(Eigen::MatrixXd c) : c_(std::move(c)) {}
  int variables() const override { return static_cast<int>(c_.cols()); }
  int objectives() const override { return 1; }
  int equalities() const override { return static_cast<int>(c_.rows()); }
  int inequalities() const override { return 0; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    const Eigen::Map<const Eigen::VectorXd> x(z, variables());
    const int n = variables();
    values[0] = 0.5 * x.squaredNorm();
    for (int k = 0; k < n; ++k) jacobian[k] = x[k];
    for (int r = 0; r < c_.rows(); ++r) {
      values[1 + r] = c_.row(r).dot(x);
      for (int k = 0; k < n; ++k) jacobian[(1 + r) * n + k] = c_(r, k);
    }
  }

 private:
  Eigen::MatrixXd c_;
};

// The reduced Hessian and the residuals' Jacobian along the allowed motions, computed from
// the rows' Householder reflectors, are Zᵀ·H·Z and M·Z with the explicit basis Z; with no
// rows (Z the identity) they are the matrices themselves.
TEST(ManifoldSolver, ReductionsByReflectorsMatchTheExplicitBasis) {
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  constexpr int n = 30;
  auto random = [&](int rows, int cols) {
    Eigen::MatrixXd m(rows, cols);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < cols; ++j) m(i, j) = normal(rng);
    return m;
  };
  Eigen::MatrixXd h = random(n, n);
  h = 0.5 * (h + h.transpose());
  const Eigen::MatrixXd residuals = random(12, n);
  for (int rows : {0, 1, 6, 12}) {
    SCOPED_TRACE(rows);
    Eigen::MatrixXd c = random(rows, n);
    if (rows >= 6) c.row(rows - 1) = c.row(0) - 3 * c.row(1);  // redundant
    UnderRows problem(c);
    ManifoldSolver solver(
        problem, Eigen::VectorXd::Constant(n, -1e9), Eigen::VectorXd::Constant(n, 1e9));
    const ManifoldSolver::Active act = solver.active_set(solver.evaluate(Eigen::VectorXd::Zero(n)));
    ASSERT_EQ(act.free.size(), static_cast<std::size_t>(n));
    const int expected_motions = n - (rows >= 6 ? rows - 1 : rows);
    ASSERT_EQ(act.motions(), expected_motions);
    const Eigen::MatrixXd Z = act.basis();
    ASSERT_EQ(Z.cols(), expected_motions);
    // Products by reflectors are products with the basis.
    const Eigen::VectorXd q = random(expected_motions, 1);
    const Eigen::VectorXd v = random(n, 1);
    EXPECT_LT((act.along(q) - Z * q).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((act.onto(v) - Z.transpose() * v).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((Z.transpose() * Z - Eigen::MatrixXd::Identity(expected_motions, expected_motions))
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12);
    if (rows > 0) {
      EXPECT_LT((c * Z).cwiseAbs().maxCoeff(), 1e-9);  // Z spans c's null space
    }
    EXPECT_EQ(static_cast<bool>(act.rows_qr), rows > 0);
    const Eigen::MatrixXd reduced = ManifoldSolver::reduced(act, h);
    const Eigen::MatrixXd explicit_reduced = Z.transpose() * h * Z;
    ASSERT_EQ(reduced.rows(), expected_motions);
    EXPECT_LT((reduced - explicit_reduced).cwiseAbs().maxCoeff(), 1e-12);
    const Eigen::MatrixXd along = ManifoldSolver::along_motions(act, residuals);
    ASSERT_EQ(along.cols(), expected_motions);
    EXPECT_LT((along - residuals * Z).cwiseAbs().maxCoeff(), 1e-12);
    if (rows == 0) {
      EXPECT_EQ(reduced, h);
      EXPECT_EQ(along, residuals);
    }
  }
}

// f = ½‖z − a‖² on the unit sphere (an equality that curves), pressed against a wall z₀ ≥ 0.6 whose
// row is flat where it binds (a contact between faceted bodies). With `skip_flat_rows`,
// evaluate_slopes() writes NaN where the flat row is: the differenced Hessian must not read it.
class SphereAgainstAWall : public ManifoldProblem {
 public:
  explicit SphereAgainstAWall(bool skip_flat_rows) : skip_flat_rows_(skip_flat_rows) {}
  int variables() const override { return 3; }
  int objectives() const override { return 1; }
  int equalities() const override { return 1; }
  int inequalities() const override { return 1; }
  bool flat_inequality(int) const override { return true; }
  void evaluate(const double* z, double* values, double* jacobian) override {
    ++full;
    fill(z, values, jacobian, /*wall=*/true);
  }
  void evaluate_slopes(const double* z, double* values, double* jacobian) override {
    ++slopes;
    fill(z, values, jacobian, /*wall=*/!skip_flat_rows_);
  }
  int full = 0;
  int slopes = 0;

 private:
  void fill(const double* z, double* values, double* jacobian, bool wall) const {
    const Eigen::Vector3d a(-2.0, 0.5, 0.3);
    const Eigen::Map<const Eigen::Vector3d> x(z);
    values[0] = 0.5 * (x - a).squaredNorm();
    values[1] = x.squaredNorm() - 1;
    for (int k = 0; k < 3; ++k) {
      jacobian[k] = x[k] - a[k];
      jacobian[3 + k] = 2 * x[k];
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    values[2] = wall ? 0.6 - x[0] : nan;
    jacobian[6] = wall ? -1 : nan;
    jacobian[7] = wall ? 0 : nan;
    jacobian[8] = wall ? 0 : nan;
  }
  bool skip_flat_rows_;
};

TEST(ManifoldSolver, DifferencedHessiansReadNoFlatRowsAndEvaluateOnlySlopes) {
  // The constrained minimum: on the wall, on the sphere, and turned towards a's (y, z).
  const double turn = std::atan2(0.3, 0.5);
  const Eigen::Vector3d at(0.6, 0.8 * std::cos(turn), 0.8 * std::sin(turn));
  Eigen::MatrixXd hessians[2];
  for (const bool skip : {false, true}) {
    SphereAgainstAWall problem(skip);
    ManifoldSolver solver(
        problem, Eigen::VectorXd::Constant(3, -10), Eigen::VectorXd::Constant(3, 10));
    const ManifoldSolver::Point p = solver.evaluate(at);
    ASSERT_EQ(p.binding.size(), 1u);  // the wall's row binds here
    const ManifoldSolver::Active act = solver.active_set(p);
    ASSERT_EQ(act.rows.size(), 2u);  // the objective presses against the wall
    const int full_before = problem.full;
    hessians[skip ? 1 : 0] = solver.lagrangian_hessian(p, act);
    EXPECT_EQ(problem.full, full_before);  // one evaluate_slopes() per column instead
    EXPECT_EQ(problem.slopes, 3);
  }
  ASSERT_TRUE(hessians[1].allFinite());
  EXPECT_EQ(hessians[0], hessians[1]);
  // Against the closed form: ∇²f − λ·∇²h = (1 − 2λ)·I, λ the sphere's multiplier.
  const double lambda = 0.5 * (at[1] - 0.5) / at[1];  // from the y row (the wall has no y)
  EXPECT_LT((hessians[0] - (1 - 2 * lambda) * Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(),
            1e-5);
}

TEST(StopClock, ACallEndsItForEveryLaterCheck) {
  const StopClock none;
  EXPECT_FALSE(none.passed());
  EXPECT_FALSE(none.would_pass(std::chrono::hours(24)));

  const StopClock clock(Clock::now() + std::chrono::hours(1));
  EXPECT_FALSE(clock.passed());
  EXPECT_FALSE(clock.would_pass(std::chrono::minutes(1)));
  EXPECT_FALSE(clock.passed()) << "asking does not call it";
  EXPECT_TRUE(clock.would_pass(std::chrono::hours(2)));
  EXPECT_TRUE(clock.passed());
  EXPECT_TRUE(clock.would_pass(Clock::duration::zero()));

  const StopClock past(Clock::now() - std::chrono::milliseconds(1));
  EXPECT_TRUE(past.passed());
}

TEST(StopClock, SpeculativeWorkStopsWithItsParentOrWhenCalledOff) {
  const auto parent = std::make_shared<const StopClock>(Clock::now() + std::chrono::hours(1));
  const StopClock child(parent);
  EXPECT_FALSE(child.passed());
  EXPECT_FALSE(child.would_pass(std::chrono::minutes(1)));
  child.call_off();
  EXPECT_TRUE(child.passed());
  EXPECT_TRUE(child.would_pass(Clock::duration::zero()));
  EXPECT_FALSE(parent->passed()) << "calling off the child leaves the parent running";

  const StopClock sibling(parent);
  EXPECT_TRUE(sibling.would_pass(std::chrono::hours(2))) << "the parent's deadline holds";
  EXPECT_TRUE(parent->passed());
  EXPECT_TRUE(sibling.passed());

  const StopClock orphan(std::shared_ptr<const StopClock>{});
  EXPECT_FALSE(orphan.passed());
  orphan.call_off();
  EXPECT_TRUE(orphan.passed());
}

}  // namespace
}  // namespace fabkit::solvers

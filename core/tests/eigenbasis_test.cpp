// The eigenbasis a trust-region step is taken in, formed (Eigen) or factored (Householder
// reflectors and LAPACK's divide and conquer): both must be the eigendecomposition of the
// matrix, whatever its spectrum — distinct, clustered at zero (the neutral directions of a
// chain's free turns), or negative.
#include "fabkit/core/solvers/eigenbasis.h"

#include <gtest/gtest.h>

#include <random>

namespace fabkit::solvers {
namespace {

Eigen::MatrixXd random_orthogonal(int n, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  Eigen::MatrixXd m(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) m(i, j) = normal(rng);
  return Eigen::HouseholderQR<Eigen::MatrixXd>(m).householderQ();
}

// V·diag(values)·Vᵀ for a random orthogonal V.
Eigen::MatrixXd with_spectrum(const Eigen::VectorXd& values, std::mt19937& rng) {
  const Eigen::MatrixXd v = random_orthogonal(static_cast<int>(values.size()), rng);
  const Eigen::MatrixXd h = v * values.asDiagonal() * v.transpose();
  return 0.5 * (h + h.transpose());
}

// A spectrum like a settling chain's: a few negative curvatures, a cluster of neutral ones
// at round-off, the rest positive over six decades.
Eigen::VectorXd chain_like_spectrum(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  Eigen::VectorXd values(n);
  for (int i = 0; i < n; ++i) {
    if (i < n / 10) {
      values[i] = -std::pow(10.0, -3 + 3 * unit(rng));
    } else if (i < n / 2) {
      values[i] = 1e-14 * (unit(rng) - 0.5);
    } else {
      values[i] = std::pow(10.0, -3 + 6 * unit(rng));
    }
  }
  return values;
}

void expect_eigendecomposition(const Eigen::MatrixXd& h, const Eigenbasis& basis) {
  const int n = static_cast<int>(h.rows());
  ASSERT_EQ(basis.size(), n);
  const double scale = h.cwiseAbs().maxCoeff();
  for (int i = 1; i < n; ++i) EXPECT_LE(basis.values()[i - 1], basis.values()[i]) << i;
  std::mt19937 rng(5);
  std::normal_distribution<double> normal;
  for (int i = 0; i < n; ++i) {
    const Eigen::VectorXd v = basis.vector(i);
    EXPECT_NEAR(v.norm(), 1.0, 1e-12) << i;
    EXPECT_LT((h * v - basis.values()[i] * v).norm(), 1e-12 * n * scale) << i;
  }
  // Orthonormal: coordinates and combinations are inverse to each other.
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = normal(rng);
  EXPECT_LT((basis.combination(basis.coordinates(x)) - x).norm(), 1e-12 * n * x.norm());
  // The largest entry of the lowest curvature's vector is positive.
  const Eigen::VectorXd lowest = basis.vector(0);
  Eigen::Index k = 0;
  lowest.cwiseAbs().maxCoeff(&k);
  EXPECT_GT(lowest[k], 0);
}

TEST(Eigenbasis, FormedAndFactoredAreTheMatrixsEigendecomposition) {
  std::mt19937 rng(11);
  for (int n : {1, 2, 7, 40, 64, 130, 254}) {
    const Eigen::MatrixXd h = with_spectrum(chain_like_spectrum(n, rng), rng);
    for (bool factored : {false, true}) {
      SCOPED_TRACE(testing::Message() << n << " rows, factored " << factored);
      const Eigenbasis basis(h, factored);
      EXPECT_EQ(basis.factored(), factored && n > 1);
      expect_eigendecomposition(h, basis);
    }
    EXPECT_EQ(Eigenbasis(h).factored(), n >= Eigenbasis::kFactoredFrom);
  }
}

// What the solver builds from the basis, a regularised Newton step Σ cᵢ/(λᵢ + μ)·vᵢ with
// c = Vᵀg, is (H + μI)⁻¹·g in both representations (signs of the vectors cancel).
TEST(Eigenbasis, StepsAreTheSameInBothRepresentations) {
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  for (int n : {40, 100, 200}) {
    const Eigen::MatrixXd h = with_spectrum(chain_like_spectrum(n, rng), rng);
    Eigen::VectorXd g(n);
    for (int i = 0; i < n; ++i) g[i] = normal(rng);
    const double mu = 2.0 - h.selfadjointView<Eigen::Lower>().eigenvalues().minCoeff();
    const Eigen::VectorXd direct = (h + mu * Eigen::MatrixXd::Identity(n, n)).ldlt().solve(g);
    for (bool factored : {false, true}) {
      const Eigenbasis basis(h, factored);
      const Eigen::VectorXd c = basis.coordinates(g);
      Eigen::VectorXd y(n);
      for (int i = 0; i < n; ++i) y[i] = c[i] / (basis.values()[i] + mu);
      EXPECT_LT((basis.combination(y) - direct).norm(), 1e-10 * direct.norm())
          << n << " rows, factored " << factored;
    }
  }
}

TEST(Eigenbasis, AnEmptyMatrixHasAnEmptyBasis) {
  const Eigenbasis basis(Eigen::MatrixXd(0, 0), true);
  EXPECT_EQ(basis.size(), 0);
  EXPECT_EQ(basis.coordinates(Eigen::VectorXd(0)).size(), 0);
}

}  // namespace
}  // namespace fabkit::solvers

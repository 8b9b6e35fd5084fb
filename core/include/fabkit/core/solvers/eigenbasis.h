#pragma once
/// The eigendecomposition H = V·diag(λ)·Vᵀ of a symmetric matrix, as a trust-region step uses
/// it: the eigenvalues, ascending, and products with V and Vᵀ.
///
/// Below kFactoredFrom rows Eigen's solver forms V. From there V is kept factored, V = Q·S:
/// Q the Householder reflectors that make H tridiagonal (Eigen), S the tridiagonal matrix's
/// eigenvectors by LAPACK's divide and conquer (dstedc). Forming V — Eigen turns Q into a
/// matrix and applies every rotation of its QR iteration to it — was three quarters of the
/// decomposition's cost (a 254-motion model of a 64-hook chain: 12 ms, against 4.5 ms
/// factored); products with Q and S cost O(n²), and a trust-region step needs a few.

#include <Eigen/Dense>
#include <optional>

namespace fabkit::solvers {

class Eigenbasis {
 public:
  /// From this many rows V is kept factored (measured: at 40 rows the two cost the same,
  /// at 100 the factored one half).
  static constexpr int kFactoredFrom = 64;

  /// `symmetric` is read as its lower triangle. Eigenvector 0 (the lowest curvature's, the
  /// one a step escapes along from a balance point) has its largest entry positive, so that
  /// the escape goes the same way whatever round-off chose.
  explicit Eigenbasis(const Eigen::MatrixXd& symmetric);
  /// As above with the representation chosen by the caller (tests compare the two).
  Eigenbasis(const Eigen::MatrixXd& symmetric, bool factored);

  int size() const { return static_cast<int>(values_.size()); }
  bool factored() const { return tridiagonal_.has_value(); }
  /// λ, ascending.
  const Eigen::VectorXd& values() const { return values_; }
  /// Vᵀ·x: x's coordinates along the eigenvectors.
  Eigen::VectorXd coordinates(const Eigen::VectorXd& x) const;
  /// V·y, the terms with y_i = 0 left out.
  Eigen::VectorXd combination(const Eigen::VectorXd& y) const;
  /// Eigenvector i.
  Eigen::VectorXd vector(int i) const;

 private:
  void decompose(const Eigen::MatrixXd& symmetric, bool factored);

  Eigen::VectorXd values_;
  /// V itself, or S when factored.
  Eigen::MatrixXd vectors_;
  std::optional<Eigen::Tridiagonalization<Eigen::MatrixXd>> tridiagonal_;
};

}  // namespace fabkit::solvers

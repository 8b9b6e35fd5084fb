#include "fabkit/core/solvers/eigenbasis.h"

#include <cstddef>
#include <vector>

// LAPACK (Fortran): divide and conquer on a symmetric tridiagonal matrix. The trailing length
// is the character argument's, which gfortran passes hidden.
extern "C" void dstedc_(const char* compz,
                        const int* n,
                        double* d,
                        double* e,
                        double* z,
                        const int* ldz,
                        double* work,
                        const int* lwork,
                        int* iwork,
                        const int* liwork,
                        int* info,
                        std::size_t compz_length);

namespace fabkit::solvers {

namespace {

// The eigenvalues (into d, ascending) and eigenvectors (into z) of the tridiagonal matrix with
// diagonal d and off-diagonal e; false where LAPACK reports a failure.
bool tridiagonal_eigen(Eigen::VectorXd& d, Eigen::VectorXd e, Eigen::MatrixXd& z) {
  const int n = static_cast<int>(d.size());
  z.resize(n, n);
  if (n == 0) return true;
  if (e.size() < n) e.conservativeResize(n);  // dstedc reads n-1; room for any convention
  const int ldz = n;
  // The workspace LAPACK asks for (lwork = liwork = -1), then the decomposition.
  auto run = [&](double* work, int lwork, int* iwork, int liwork) {
    int info = 0;
    dstedc_("I", &n, d.data(), e.data(), z.data(), &ldz, work, &lwork, iwork, &liwork, &info, 1);
    return info == 0;
  };
  double work_size = 0;
  int iwork_size = 0;
  if (!run(&work_size, -1, &iwork_size, -1)) return false;
  std::vector<double> work(static_cast<std::size_t>(std::max(1, static_cast<int>(work_size))));
  std::vector<int> iwork(static_cast<std::size_t>(std::max(1, iwork_size)));
  return run(
      work.data(), static_cast<int>(work.size()), iwork.data(), static_cast<int>(iwork.size()));
}

// The index of v's entry of largest magnitude (the first of equals).
Eigen::Index largest_entry(const Eigen::VectorXd& v) {
  Eigen::Index k = 0;
  v.cwiseAbs().maxCoeff(&k);
  return k;
}

}  // namespace

Eigenbasis::Eigenbasis(const Eigen::MatrixXd& symmetric) {
  decompose(symmetric, symmetric.rows() >= kFactoredFrom);
}

Eigenbasis::Eigenbasis(const Eigen::MatrixXd& symmetric, bool factored) {
  decompose(symmetric, factored);
}

void Eigenbasis::decompose(const Eigen::MatrixXd& symmetric, bool factored) {
  if (symmetric.rows() == 0) return;  // Eigen's solver reads the largest entry of the matrix
  // Non-finite entries go to Eigen's solver, which reports them as it finds them (LAPACK's
  // iterations are bounded too, but nothing is gained by handing it a NaN).
  if (factored && symmetric.rows() > 1 && symmetric.allFinite()) {
    tridiagonal_.emplace(symmetric);
    values_ = tridiagonal_->diagonal();
    if (tridiagonal_eigen(values_, tridiagonal_->subDiagonal(), vectors_)) {
      const Eigen::VectorXd lowest = vector(0);
      if (lowest[largest_entry(lowest)] < 0) vectors_.col(0) = -vectors_.col(0);
      return;
    }
    tridiagonal_.reset();  // LAPACK did not converge: Eigen's QR iteration instead
  }
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(symmetric);
  values_ = eig.eigenvalues();
  vectors_ = eig.eigenvectors();
  if (vectors_.cols() > 0 && vectors_(largest_entry(vectors_.col(0)), 0) < 0) {
    vectors_.col(0) = -vectors_.col(0);
  }
}

Eigen::VectorXd Eigenbasis::coordinates(const Eigen::VectorXd& x) const {
  if (!tridiagonal_) return vectors_.transpose() * x;
  const Eigen::VectorXd turned = tridiagonal_->matrixQ().adjoint() * x;
  return vectors_.transpose() * turned;
}

Eigen::VectorXd Eigenbasis::combination(const Eigen::VectorXd& y) const {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(vectors_.rows());
  for (int i = 0; i < y.size(); ++i) {
    if (y[i] != 0) out += y[i] * vectors_.col(i);
  }
  if (!tridiagonal_) return out;
  return tridiagonal_->matrixQ() * out;
}

Eigen::VectorXd Eigenbasis::vector(int i) const {
  if (!tridiagonal_) return vectors_.col(i);
  return tridiagonal_->matrixQ() * vectors_.col(i);
}

}  // namespace fabkit::solvers

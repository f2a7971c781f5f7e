#include "core/discrepancy/dense_algebra.h"

#include <Eigen/Dense>

namespace roverlab::analysis {

std::optional<EigenvalueRange> symmetric_eigenvalue_range(const Eigen::MatrixXd& a) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(a, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) return std::nullopt;
  return EigenvalueRange{eig.eigenvalues().minCoeff(), eig.eigenvalues().maxCoeff()};
}

Eigen::MatrixXd lu_inverse(const Eigen::MatrixXd& a) { return a.inverse(); }

std::optional<Eigen::MatrixXd> positive_definite_inverse(const Eigen::MatrixXd& a) {
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return std::nullopt;
  return Eigen::MatrixXd(ldlt.solve(Eigen::MatrixXd::Identity(a.rows(), a.cols())));
}

}  // namespace roverlab::analysis

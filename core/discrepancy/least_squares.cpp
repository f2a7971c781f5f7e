#include "core/discrepancy/least_squares.h"

#include <Eigen/Dense>

namespace roverlab::analysis {

PseudoInverse pseudo_inverse(const Eigen::MatrixXd& a, double threshold) {
  Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(a);
  cod.setThreshold(threshold);
  return {cod.pseudoInverse(), cod.rank()};
}

Eigen::VectorXd least_squares(const Eigen::Ref<const RowMajorMatrix>& a, const Eigen::Ref<const Eigen::VectorXd>& b) {
  return a.completeOrthogonalDecomposition().solve(b);
}

}  // namespace roverlab::analysis

#pragma once

#include <Eigen/Core>

#include "core/discrepancy/dense_algebra.h"

namespace roverlab::analysis {

// The complete orthogonal decompositions of dense_algebra.h's note, in a unit
// of their own (two decompositions, 20 s of g++).

// The pseudo-inverse of a by complete orthogonal decomposition, pivots below
// threshold (relative) counted as zero, and the rank found.
struct PseudoInverse {
  Eigen::MatrixXd matrix;
  Eigen::Index rank = 0;
};
PseudoInverse pseudo_inverse(const Eigen::MatrixXd& a, double threshold);

// The minimum-norm least-squares x of a x = b (complete orthogonal decomposition).
Eigen::VectorXd least_squares(const Eigen::Ref<const RowMajorMatrix>& a, const Eigen::Ref<const Eigen::VectorXd>& b);

}  // namespace roverlab::analysis

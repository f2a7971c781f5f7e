#pragma once

#include <optional>

#include <Eigen/Core>

namespace roverlab::analysis {

// Eigen's dynamic-size decompositions the studies use to weigh a fit, compiled
// once in dense_algebra.cpp: each costs 3-17 s of g++ in every unit that names
// it (the rover fit took 50 s of which 45 were these; docs/performance.md,
// "g++'s garbage collector, the studies' decompositions compiled once");
// least_squares.h holds the orthogonal ones.

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The extreme eigenvalues of a symmetric matrix; nullopt when the solver fails.
struct EigenvalueRange {
  double min = 0;
  double max = 0;
};
std::optional<EigenvalueRange> symmetric_eigenvalue_range(const Eigen::MatrixXd& a);

// a^-1 by partial-pivoting LU (Eigen's inverse() of a dynamic matrix).
Eigen::MatrixXd lu_inverse(const Eigen::MatrixXd& a);

// a^-1 of a symmetric matrix by LDL^T; nullopt when a is not positive definite.
std::optional<Eigen::MatrixXd> positive_definite_inverse(const Eigen::MatrixXd& a);

}  // namespace roverlab::analysis

#pragma once
// Generic Kalman steps over Eigen types, shared by the estimators: covariance
// propagation and a measurement update in Joseph form that keeps P symmetric
// positive definite. Estimators supply their own models (F, Q, H, R).

#include <Eigen/Dense>
#include <cmath>

namespace roverlab::estimation {

// P <- Phi P Phi^T + Q (seed 002 Eq. 13 with L = I), symmetrised.
void propagate_covariance(Eigen::MatrixXd& P, const Eigen::MatrixXd& Phi, const Eigen::MatrixXd& Q);

struct UpdateResult {
  Eigen::VectorXd correction;  // K y
  double nis = 0.0;            // normalised innovation squared y^T S^-1 y
  double log_det_s = 0.0;      // ln det S (the innovation's likelihood)
  bool ok = false;             // false when S is not positive definite or the gate rejected it
  bool rejected = false;       // nis above the gate: state and P left unchanged
};

// Kalman gain K = P H^T (H P H^T + R)^-1 (Eq. 15), correction K y (Eq. 16),
// and P <- (I - K H) P (I - K H)^T + K R K^T (Joseph form of Eq. 28).
// A measurement whose nis exceeds `gate` (a chi-square quantile) is rejected.
UpdateResult kalman_update(Eigen::MatrixXd& P, const Eigen::MatrixXd& H, const Eigen::MatrixXd& R,
                           const Eigen::VectorXd& innovation, double gate = HUGE_VAL);

}  // namespace roverlab::estimation

#include "core/filters/kalman.h"

namespace roverlab::estimation {

void propagate_covariance(Eigen::MatrixXd& P, const Eigen::MatrixXd& Phi, const Eigen::MatrixXd& Q) {
  P = Phi * P * Phi.transpose() + Q;
  P = 0.5 * (P + P.transpose());
}

UpdateResult kalman_update(Eigen::MatrixXd& P, const Eigen::MatrixXd& H, const Eigen::MatrixXd& R,
                           const Eigen::VectorXd& innovation, double gate) {
  UpdateResult r;
  const Eigen::MatrixXd S = H * P * H.transpose() + R;
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success) return r;
  r.nis = innovation.dot(llt.solve(innovation));
  r.log_det_s = 2.0 * Eigen::MatrixXd(llt.matrixL()).diagonal().array().log().sum();
  if (!(r.nis <= gate)) {
    r.rejected = true;
    return r;
  }
  const Eigen::MatrixXd K = llt.solve(H * P).transpose();  // P H^T S^-1 (S symmetric)
  r.correction = K * innovation;
  const Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(P.rows(), P.cols()) - K * H;
  P = I_KH * P * I_KH.transpose() + K * R * K.transpose();
  P = 0.5 * (P + P.transpose());
  r.ok = true;
  return r;
}

}  // namespace roverlab::estimation

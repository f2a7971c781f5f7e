#include "core/estimation/nonlinear_filter.h"

namespace roverlab::estimation {

void ExtendedKalmanFilter::predict(const Linearized& f, const Eigen::MatrixXd& Q) {
  x = f.value;
  P = f.dx * P * f.dx.transpose() + f.dn * Q * f.dn.transpose();
  P = 0.5 * (P + P.transpose());
}

UpdateResult ExtendedKalmanFilter::update(const Linearized& h, const Eigen::MatrixXd& R, const Eigen::VectorXd& y) {
  const Eigen::MatrixXd MRM = h.dn * R * h.dn.transpose();
  UpdateResult u = kalman_update(P, h.dx, MRM, y - h.value);
  if (u.ok) x += u.correction;
  return u;
}

void ExtendedKalmanFilter::predict_diagonal(const Linearized& f, const Eigen::VectorXd& q) {
  x = f.value;
  const Eigen::MatrixXd Ls = f.dn * q.cwiseSqrt().asDiagonal();
  P = f.dx * P * f.dx.transpose();
  P.noalias() += Ls * Ls.transpose();
  P = 0.5 * (P + P.transpose());
}

UpdateResult ExtendedKalmanFilter::update_diagonal(const Linearized& h, const Eigen::VectorXd& r, const Eigen::VectorXd& y) {
  const Eigen::MatrixXd Ms = h.dn * r.cwiseSqrt().asDiagonal();
  const Eigen::MatrixXd MRM = Ms * Ms.transpose();
  UpdateResult u = kalman_update(P, h.dx, MRM, y - h.value);
  if (u.ok) x += u.correction;
  return u;
}

void ExtendedKalmanFilter::reset_cross_covariance() { P = Eigen::MatrixXd(P.diagonal().asDiagonal()); }

bool UnscentedKalmanFilter::step(const Function& f, const Eigen::MatrixXd& Q, const Function& h,
                                 const Eigen::MatrixXd& R, const Eigen::VectorXd& y) {
  const Eigen::Index nx = x.size(), np = Q.rows(), nm = R.rows();
  const Eigen::Index L = nx + np + nm;
  Eigen::MatrixXd Pa = Eigen::MatrixXd::Zero(L, L);
  Pa.topLeftCorner(nx, nx) = P;
  Pa.block(nx, nx, np, np) = Q;
  Pa.bottomRightCorner(nm, nm) = R;
  const double lambda = alpha * alpha * (static_cast<double>(L) + kappa) - static_cast<double>(L);
  const Eigen::LLT<Eigen::MatrixXd> llt((static_cast<double>(L) + lambda) * Pa);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd S = llt.matrixL();
  const Eigen::Index n = 2 * L + 1;
  const double wm0 = lambda / (static_cast<double>(L) + lambda), wi = 0.5 / (static_cast<double>(L) + lambda);
  const double wc0 = wm0 + (1.0 - alpha * alpha + beta);
  Eigen::VectorXd xa = Eigen::VectorXd::Zero(L);
  xa.head(nx) = x;
  // Sigma points through f (Eq. 2.18), then h on the propagated points (Eq. 2.19).
  Eigen::MatrixXd X(nx, n);
  Eigen::MatrixXd Y(y.size(), n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::VectorXd s = xa;
    if (i > 0 && i <= L) s += S.col(i - 1);
    if (i > L) s -= S.col(i - 1 - L);
    X.col(i) = f(s.head(nx), s.segment(nx, np));
    Y.col(i) = h(X.col(i), s.tail(nm));
  }
  auto weight_m = [&](Eigen::Index i) { return i == 0 ? wm0 : wi; };
  auto weight_c = [&](Eigen::Index i) { return i == 0 ? wc0 : wi; };
  Eigen::VectorXd xm = Eigen::VectorXd::Zero(nx), ym = Eigen::VectorXd::Zero(y.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    xm += weight_m(i) * X.col(i);
    ym += weight_m(i) * Y.col(i);
  }
  Eigen::MatrixXd Pxx = Eigen::MatrixXd::Zero(nx, nx), Pyy = Eigen::MatrixXd::Zero(y.size(), y.size()),
                  Pxy = Eigen::MatrixXd::Zero(nx, y.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::VectorXd dx = X.col(i) - xm, dy = Y.col(i) - ym;
    Pxx += weight_c(i) * dx * dx.transpose();
    Pyy += weight_c(i) * dy * dy.transpose();
    Pxy += weight_c(i) * dx * dy.transpose();
  }
  x = xm;
  P = 0.5 * (Pxx + Pxx.transpose());
  // Eq. 2.20.
  const Eigen::LLT<Eigen::MatrixXd> syy(Pyy);
  if (syy.info() != Eigen::Success) return false;
  const Eigen::MatrixXd K = syy.solve(Pxy.transpose()).transpose();
  x += K * (y - ym);
  P -= K * Pyy * K.transpose();
  P = 0.5 * (P + P.transpose());
  return true;
}

void UnscentedKalmanFilter::reset_cross_covariance() { P = Eigen::MatrixXd(P.diagonal().asDiagonal()); }

}  // namespace roverlab::estimation

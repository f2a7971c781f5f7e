#include "core/estimation/nonlinear_filter.h"

#include <cmath>

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
  const Eigen::Index nx = x.size(), np = Q.rows(), nm = R.rows(), ny = y.size();
  const Eigen::Index L = nx + np + nm;
  const double lambda = alpha * alpha * (static_cast<double>(L) + kappa) - static_cast<double>(L);
  const double c = std::sqrt(static_cast<double>(L) + lambda);
  // Cholesky factor of (L + lambda) blockdiag(P, Q, R), block by block.
  const Eigen::LLT<Eigen::MatrixXd> llt(P);
  if (llt.info() != Eigen::Success) return false;
  const Eigen::MatrixXd Sx = c * Eigen::MatrixXd(llt.matrixL());
  auto factor = [&](const Eigen::MatrixXd& M, Eigen::MatrixXd& last, Eigen::MatrixXd& S) {
    if (last.rows() == M.rows() && last.cols() == M.cols() && last == M) return true;
    const Eigen::LLT<Eigen::MatrixXd> l(M);
    if (l.info() != Eigen::Success) return false;
    last = M;
    S = Eigen::MatrixXd(l.matrixL());
    return true;
  };
  if (!factor(Q, Q_, SQ_) || !factor(R, R_, SR_)) return false;
  const Eigen::Index n = 2 * L + 1;
  const double wm0 = lambda / (static_cast<double>(L) + lambda), wi = 0.5 / (static_cast<double>(L) + lambda);
  const double wc0 = wm0 + (1.0 - alpha * alpha + beta);
  X_.resize(nx, n);
  Y_.resize(ny, n);
  // Sigma point i: 0 the centre, 1..L plus and L+1..2L minus a column of the
  // factor. Eq. 2.18: X_i = f(x_i, n_p,i); Eq. 2.19: Y_i = h(X_i, n_m,i).
  Eigen::VectorXd xs(nx), nps(np), nms(nm), fx(nx), hy(ny);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Index d = i == 0 ? -1 : (i - 1) % L;
    const double sign = i > L ? -1.0 : 1.0;
    xs = x;
    nps.setZero();
    nms.setZero();
    if (d >= 0 && d < nx) xs += sign * Sx.col(d);
    if (d >= nx && d < nx + np) nps += (sign * c) * SQ_.col(d - nx);
    if (d >= nx + np) nms += (sign * c) * SR_.col(d - nx - np);
    if (d >= nx + np) {
      X_.col(i) = X_.col(0);  // measurement noise does not enter f
    } else {
      f(xs, nps, fx);
      X_.col(i) = fx;
    }
    fx = X_.col(i);
    h(fx, nms, hy);
    Y_.col(i) = hy;
  }
  Eigen::VectorXd wm = Eigen::VectorXd::Constant(n, wi);
  wm(0) = wm0;
  const Eigen::VectorXd xm = X_ * wm, ym = Y_ * wm;
  X_.colwise() -= xm;
  Y_.colwise() -= ym;
  // The 2 nm measurement-noise points share the centre's deviation in x:
  // in Pxx they fold into the centre's column (weight wc0 + 2 nm wi), in
  // Pxy into dx_0 (wc0 dy_0 + wi sum of their dy)^T.
  const Eigen::Index nd = 1 + 2 * (nx + np);
  Eigen::MatrixXd Xd(nx, nd), Yd(ny, nd);
  Eigen::VectorXd wd(nd);
  Xd.col(0) = X_.col(0);
  wd(0) = wc0 + 2.0 * static_cast<double>(nm) * wi;
  Yd.col(0) = wc0 * Y_.col(0) + wi * (Y_.middleCols(1 + nx + np, nm).rowwise().sum() +
                                      Y_.middleCols(L + 1 + nx + np, nm).rowwise().sum());
  for (Eigen::Index k = 0; k < nx + np; ++k) {
    Xd.col(1 + 2 * k) = X_.col(1 + k);
    Xd.col(2 + 2 * k) = X_.col(1 + L + k);
    Yd.col(1 + 2 * k) = wi * Y_.col(1 + k);
    Yd.col(2 + 2 * k) = wi * Y_.col(1 + L + k);
    wd(1 + 2 * k) = wd(2 + 2 * k) = wi;
  }
  // Weighted sums of outer products; with non-negative weights as
  // symmetric rank updates on the square roots (half the work).
  auto weighted_outer = [](const Eigen::MatrixXd& D, const Eigen::VectorXd& w) {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(D.rows(), D.rows());
    if ((w.array() >= 0.0).all()) {
      M.selfadjointView<Eigen::Lower>().rankUpdate(D * w.cwiseSqrt().asDiagonal());
      M.triangularView<Eigen::StrictlyUpper>() = M.transpose();
    } else {
      M.noalias() = (D * w.asDiagonal()) * D.transpose();
    }
    return M;
  };
  Eigen::VectorXd wc = Eigen::VectorXd::Constant(n, wi);
  wc(0) = wc0;
  const Eigen::MatrixXd Pxx = weighted_outer(Xd, wd);
  const Eigen::MatrixXd Pyy = weighted_outer(Y_, wc);
  Eigen::MatrixXd Pxy(nx, ny);
  Pxy.noalias() = Xd * Yd.transpose();
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

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
  // Additive noises (declared by the model, used only when uncorrelated
  // with the rest): the first nx process noises and the last ny
  // measurement noises.
  const Eigen::Index pa = additive_process_noise && np >= nx && Q.bottomLeftCorner(np - nx, nx).isZero(0.0) ? nx : 0;
  const Eigen::Index ma = additive_measurement_noise && nm >= ny && R.bottomLeftCorner(ny, nm - ny).isZero(0.0) ? ny : 0;
  const double wm0 = lambda / (static_cast<double>(L) + lambda), wi = 0.5 / (static_cast<double>(L) + lambda);
  const double wc0 = wm0 + (1.0 - alpha * alpha + beta);

  // Eq. 2.18: the points through f. Column 0 the centre, then a plus and a
  // minus point per state direction and per non-additive process noise.
  const Eigen::Index nf = 1 + 2 * (nx + np - pa);
  X_.resize(nx, nf);
  Eigen::VectorXd xs(nx), nps = Eigen::VectorXd::Zero(np), nms = Eigen::VectorXd::Zero(nm), fx(nx), hy(ny);
  f(x, nps, fx);
  X_.col(0) = fx;
  for (Eigen::Index d = 0; d < nx; ++d) {
    for (int k = 0; k < 2; ++k) {
      xs = x;
      if (k == 0) xs += Sx.col(d);
      if (k == 1) xs -= Sx.col(d);
      f(xs, nps, fx);
      X_.col(1 + 2 * d + k) = fx;
    }
  }
  for (Eigen::Index j = pa; j < np; ++j) {
    for (int k = 0; k < 2; ++k) {
      nps = (k == 0 ? c : -c) * SQ_.col(j);
      f(x, nps, fx);
      X_.col(1 + 2 * nx + 2 * (j - pa) + k) = fx;
    }
  }
  nps.setZero();
  // Eq. 2.19: the points through h. Those of f; the centre moved along each
  // additive process noise (its sigma points are X_0 +- c SQ_j, f is not
  // needed); the centre with each non-additive measurement noise. Additive
  // measurement noises move h's value by +- c SR_m and are not evaluated.
  const Eigen::Index nmh = nm - ma;
  Eigen::MatrixXd Yf(ny, nf), Yp(ny, 2 * pa), Ym(ny, 2 * nmh), Dp(nx, pa);
  for (Eigen::Index i = 0; i < nf; ++i) {
    fx = X_.col(i);
    h(fx, nms, hy);
    Yf.col(i) = hy;
  }
  for (Eigen::Index j = 0; j < pa; ++j) {
    Dp.col(j) = c * SQ_.col(j).head(nx);
    for (int k = 0; k < 2; ++k) {
      fx = X_.col(0);
      if (k == 0) fx += Dp.col(j);
      if (k == 1) fx -= Dp.col(j);
      h(fx, nms, hy);
      Yp.col(2 * j + k) = hy;
    }
  }
  fx = X_.col(0);
  for (Eigen::Index j = 0; j < nmh; ++j) {
    for (int k = 0; k < 2; ++k) {
      nms = (k == 0 ? c : -c) * SR_.col(j);
      h(fx, nms, hy);
      Ym.col(2 * j + k) = hy;
    }
  }
  // Means: pairs along additive noises average to the centre.
  const double w0x = wm0 + 2.0 * wi * static_cast<double>(pa + nm);
  const double w0y = wm0 + 2.0 * wi * static_cast<double>(ma);
  const Eigen::VectorXd xm = w0x * X_.col(0) + wi * X_.rightCols(nf - 1).rowwise().sum();
  const Eigen::VectorXd ym = w0y * Yf.col(0) + wi * (Yf.rightCols(nf - 1).rowwise().sum() + Yp.rowwise().sum() +
                                                     Ym.rowwise().sum());
  X_.colwise() -= xm;
  Yf.colwise() -= ym;
  Yp.colwise() -= ym;
  Ym.colwise() -= ym;
  // Covariances. A pair along an additive noise contributes 2 wi dx0 dx0^T
  // + 2 wi delta delta^T, and 2 wi c^2 = 1, so those pairs add Q's or R's
  // additive block and fold the rest into the centre's weight.
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
  Eigen::VectorXd wx = Eigen::VectorXd::Constant(nf, wi);
  wx(0) = wc0 + 2.0 * wi * static_cast<double>(pa + nm);
  Eigen::MatrixXd Pxx = weighted_outer(X_, wx);
  if (pa > 0) Pxx += Q.topLeftCorner(nx, nx);
  Eigen::MatrixXd Yall(ny, nf + 2 * pa + 2 * nmh);
  Yall << Yf, Yp, Ym;
  Eigen::VectorXd wy = Eigen::VectorXd::Constant(Yall.cols(), wi);
  wy(0) = wc0 + 2.0 * wi * static_cast<double>(ma);
  Eigen::MatrixXd Pyy = weighted_outer(Yall, wy);
  if (ma > 0) Pyy += R.bottomRightCorner(ny, ny);
  // Pxy = dx0 (w dy0 + wi sum dy of the points sharing X_0)^T
  //     + wi sum dx dy^T over f's points + wi sum_j delta_j (dy_j+ - dy_j-)^T.
  // (delta_j = c SQ_j is a column of the triangular factor.)
  Eigen::MatrixXd Ya(ny, nf);
  Ya.col(0) = (wc0 + 2.0 * wi * static_cast<double>(ma)) * Yf.col(0) + wi * (Yp.rowwise().sum() + Ym.rowwise().sum());
  Ya.rightCols(nf - 1) = wi * Yf.rightCols(nf - 1);
  Eigen::MatrixXd Pxy(nx, ny);
  Pxy.noalias() = X_ * Ya.transpose();
  if (pa > 0) {
    Eigen::MatrixXd Yd(pa, ny);  // wi (dy_j+ - dy_j-)^T
    for (Eigen::Index j = 0; j < pa; ++j) Yd.row(j) = (c * wi) * (Yp.col(2 * j) - Yp.col(2 * j + 1)).transpose();
    Pxy.noalias() += SQ_.topLeftCorner(nx, pa).triangularView<Eigen::Lower>() * Yd;
  }
  x = xm;
  P = 0.5 * (Pxx + Pxx.transpose());
  // Eq. 2.20 with Pyy = L L^T: K = Pxy Pyy^-1 = W^T L^-1 for W = L^-1 Pxy^T,
  // so K (y - ym) = W^T L^-1 (y - ym) and K Pyy K^T = W^T W.
  const Eigen::LLT<Eigen::MatrixXd> syy(Pyy);
  if (syy.info() != Eigen::Success) return false;
  const Eigen::MatrixXd W = syy.matrixL().solve(Pxy.transpose());
  x.noalias() += W.transpose() * syy.matrixL().solve(y - ym);
  P.selfadjointView<Eigen::Lower>().rankUpdate(W.transpose(), -1.0);
  P.triangularView<Eigen::StrictlyUpper>() = P.transpose();
  return true;
}

void UnscentedKalmanFilter::reset_cross_covariance() { P = Eigen::MatrixXd(P.diagonal().asDiagonal()); }

}  // namespace roverlab::estimation

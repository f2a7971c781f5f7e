#include "core/filters/nonlinear_filter.h"

#include <algorithm>
#include <cmath>
#include <vector>

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

UpdateResult ExtendedKalmanFilter::update_diagonal(const Linearized& h, const Eigen::VectorXd& r,
                                                   const Eigen::VectorXd& y, double gate) {
  const Eigen::MatrixXd Ms = h.dn * r.cwiseSqrt().asDiagonal();
  const Eigen::MatrixXd MRM = Ms * Ms.transpose();
  UpdateResult u = kalman_update(P, h.dx, MRM, y - h.value, gate);
  if (u.ok) x += u.correction;
  return u;
}

void ExtendedKalmanFilter::reset_cross_covariance() { P = Eigen::MatrixXd(P.diagonal().asDiagonal()); }

namespace {

// Non-zero rows of a column, or -1 when there are more than kSparse.
constexpr int kSparse = 6;
int nonzeros(const Eigen::Ref<const Eigen::VectorXd>& v, Eigen::Index* idx) {
  const Eigen::Index n = (v.array() != 0.0).count();  // vectorised: most columns are dense or very sparse
  if (n > kSparse) return -1;
  int k = 0;
  for (Eigen::Index r = 0; r < v.size() && k < n; ++r) {
    if (v(r) != 0.0) idx[k++] = r;
  }
  return k;
}

// M += w sum_i e_i e_i^T (w >= 0) on M's lower triangle: sparse columns
// entry by entry, the rest as one symmetric rank update (all of E's columns
// when none is sparse, else copied into D). The caller fills the upper
// triangle when done. `dense` and D are scratch, kept between calls.
void add_outer(Eigen::MatrixXd& M, const Eigen::MatrixXd& E, double w, std::vector<Eigen::Index>& dense,
               Eigen::MatrixXd& D) {
  dense.clear();
  Eigen::Index idx[kSparse], zero = 0;
  for (Eigen::Index i = 0; i < E.cols(); ++i) {
    const int k = nonzeros(E.col(i), idx);
    if (k < 0) {
      dense.push_back(i);
      continue;
    }
    zero += k == 0 ? 1 : 0;
    const double* e = E.col(i).data();
    for (int a = 0; a < k; ++a) {
      const double wa = w * e[idx[a]];
      double* m = M.col(0).data() + idx[a];
      for (int b = 0; b <= a; ++b) m[idx[b] * M.outerStride()] += wa * e[idx[b]];
    }
  }
  if (dense.empty()) return;
  if (static_cast<Eigen::Index>(dense.size()) + zero == E.cols()) {  // zero columns add nothing
    M.selfadjointView<Eigen::Lower>().rankUpdate(E, w);
    return;
  }
  D.resize(E.rows(), static_cast<Eigen::Index>(dense.size()));
  for (std::size_t i = 0; i < dense.size(); ++i) D.col(static_cast<Eigen::Index>(i)) = E.col(dense[i]);
  M.selfadjointView<Eigen::Lower>().rankUpdate(D, w);
}

// M += w sum_i a_i b_i^T: columns of A that are sparse row by row, the
// rest as one product (all of A and B when none is sparse). `dense`, DA and
// DB are scratch.
void add_cross(Eigen::MatrixXd& M, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B, double w,
               std::vector<Eigen::Index>& dense, Eigen::MatrixXd& DA, Eigen::MatrixXd& DB) {
  dense.clear();
  Eigen::Index idx[kSparse], zero = 0;
  for (Eigen::Index i = 0; i < A.cols(); ++i) {
    const int k = nonzeros(A.col(i), idx);
    if (k < 0) {
      dense.push_back(i);
      continue;
    }
    zero += k == 0 ? 1 : 0;
    for (int a = 0; a < k; ++a) M.row(idx[a]) += (w * A(idx[a], i)) * B.col(i).transpose();
  }
  if (dense.empty()) return;
  if (static_cast<Eigen::Index>(dense.size()) + zero == A.cols()) {
    M.noalias() += w * (A * B.transpose());
    return;
  }
  DA.resize(A.rows(), static_cast<Eigen::Index>(dense.size()));
  DB.resize(B.rows(), static_cast<Eigen::Index>(dense.size()));
  for (std::size_t i = 0; i < dense.size(); ++i) {
    DA.col(static_cast<Eigen::Index>(i)) = A.col(dense[i]);
    DB.col(static_cast<Eigen::Index>(i)) = B.col(dense[i]);
  }
  M.noalias() += w * (DA * DB.transpose());
}

}  // namespace

bool UnscentedKalmanFilter::step(const Function& f, const Eigen::MatrixXd& Q, const Function& h,
                                 const Eigen::MatrixXd& R, const Eigen::VectorXd& y) {
  nis = 0;
  rejected = false;
  if (!factor_covariances(Q, R, y.size())) return false;
  propagate_sigma_points(f, Q.rows());
  measure_sigma_points(h, R.rows(), y.size());
  covariances(Q, R);
  return correct(y);
}

// Cholesky factor of (L + lambda) blockdiag(P, Q, R), block by block, and
// the scaled unscented transform's weights.
bool UnscentedKalmanFilter::factor_covariances(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R, Eigen::Index ny) {
  const Eigen::Index nx = x.size(), np = Q.rows(), nm = R.rows();
  L_ = nx + np + nm;
  const double lambda = alpha * alpha * (static_cast<double>(L_) + kappa) - static_cast<double>(L_);
  c_ = std::sqrt(static_cast<double>(L_) + lambda);
  if (diagonal_only) {  // P is diagonal (kept so by the previous step)
    if (!(P.diagonal().array() > 0.0).all()) return false;
    Sx_ = (c_ * P.diagonal().cwiseSqrt()).asDiagonal();
  } else {
    llt_x_.compute(P);
    if (llt_x_.info() != Eigen::Success) return false;
    Sx_ = llt_x_.matrixL();
    Sx_ *= c_;
  }
  auto factor = [](const Eigen::MatrixXd& M, Eigen::MatrixXd& last, Eigen::MatrixXd& S) {
    if (last.rows() == M.rows() && last.cols() == M.cols() && last == M) return true;
    if (M.isDiagonal(0.0)) {  // the Cholesky factor of a diagonal matrix, without the general factorisation
      if (!(M.diagonal().array() > 0.0).all()) return false;
      last = M;
      S = M.diagonal().cwiseSqrt().asDiagonal();
      return true;
    }
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
  pa_ = additive_process_noise && np >= nx && Q.bottomLeftCorner(np - nx, nx).isZero(0.0) ? nx : 0;
  ma_ = additive_measurement_noise && nm >= ny && R.bottomLeftCorner(ny, nm - ny).isZero(0.0) ? ny : 0;
  const double wm0 = lambda / (static_cast<double>(L_) + lambda);
  wi_ = 0.5 / (static_cast<double>(L_) + lambda);
  wc0_ = wm0 + (1.0 - alpha * alpha + beta);
  return true;
}

// Eq. 2.18: the points through f. Column 0 the centre, then a plus and a
// minus point per state direction and per non-additive process noise.
void UnscentedKalmanFilter::propagate_sigma_points(const Function& f, Eigen::Index np) {
  const Eigen::Index nx = x.size();
  const Eigen::Index nf = 1 + 2 * (nx + np - pa_);
  X_.resize(nx, nf);
  Eigen::VectorXd& xs = xs_;
  Eigen::VectorXd& nps = nps_;
  Eigen::VectorXd& fx = fx_;
  xs.resize(nx);
  fx.resize(nx);
  nps.setZero(np);
  f(x, nps, fx);
  X_.col(0) = fx;
  for (Eigen::Index d = 0; d < nx; ++d) {
    for (int k = 0; k < 2; ++k) {
      xs = x;
      if (k == 0) xs += Sx_.col(d);
      if (k == 1) xs -= Sx_.col(d);
      f(xs, nps, fx);
      X_.col(1 + 2 * d + k) = fx;
    }
  }
  for (Eigen::Index j = pa_; j < np; ++j) {
    for (int k = 0; k < 2; ++k) {
      nps = (k == 0 ? c_ : -c_) * SQ_.col(j);
      f(x, nps, fx);
      X_.col(1 + 2 * nx + 2 * (j - pa_) + k) = fx;
    }
  }
}

// h at one sigma point, stored as the deviation from the centre's Y0_;
// through h_incremental when the model has one, told which entries differ
// from the centre's (changed_x_, changed_n_).
void UnscentedKalmanFilter::measure_point(const Function& h, const Eigen::VectorXd& xp, const Eigen::VectorXd& noise,
                                          Eigen::Ref<Eigen::VectorXd> out) {
  if (h_incremental) {
    h_incremental(xp, noise, changed_x_, changed_n_, Y0_, hy_);
  } else {
    h(xp, noise, hy_);
  }
  out = hy_ - Y0_;
}

// Eq. 2.19: the points through h. Those of f; the centre moved along each
// additive process noise (its sigma points are X_0 +- c SQ_j, f is not
// needed); the centre with each non-additive measurement noise. Additive
// measurement noises move h's value by +- c SR_m and are not evaluated.
void UnscentedKalmanFilter::measure_sigma_points(const Function& h, Eigen::Index nm, Eigen::Index ny) {
  const Eigen::Index nx = x.size(), nf = X_.cols(), pa = pa_;
  const Eigen::Index nmh = nm - ma_;
  Y_.resize(ny, nf);
  Yp_.resize(ny, 2 * pa);
  Ym_.resize(ny, 2 * nmh);
  Dp_.resize(nx, pa);
  Eigen::VectorXd nms = Eigen::VectorXd::Zero(nm), fx = X_.col(0);
  hy_.resize(ny);
  h(fx, nms, hy_);
  Y_.col(0) = hy_;
  X0_ = X_.col(0);
  Y0_ = hy_;
  changed_x_.reserve(static_cast<std::size_t>(nx));
  changed_n_.reserve(static_cast<std::size_t>(nm));
  auto pattern = [](const Eigen::Ref<const Eigen::VectorXd>& v, std::vector<Eigen::Index>& out) {
    out.clear();
    for (Eigen::Index r = 0; r < v.size(); ++r) {
      if (v(r) != 0.0) out.push_back(r);
    }
  };
  changed_n_.clear();
  for (Eigen::Index i = 1; i < nf; ++i) {
    fx = X_.col(i);
    if (h_incremental) {
      changed_x_.clear();
      for (Eigen::Index r = 0; r < nx; ++r) {
        if (fx(r) != X0_(r)) changed_x_.push_back(r);
      }
    }
    measure_point(h, fx, nms, Y_.col(i));
  }
  for (Eigen::Index j = 0; j < pa; ++j) {
    Dp_.col(j) = c_ * SQ_.col(j).head(nx);
    if (h_incremental) pattern(Dp_.col(j), changed_x_);
    for (int k = 0; k < 2; ++k) {
      fx = X0_;
      if (k == 0) fx += Dp_.col(j);
      if (k == 1) fx -= Dp_.col(j);
      measure_point(h, fx, nms, Yp_.col(2 * j + k));
    }
  }
  fx = X0_;
  changed_x_.clear();
  for (Eigen::Index j = 0; j < nmh; ++j) {
    if (h_incremental) pattern(SR_.col(j), changed_n_);
    for (int k = 0; k < 2; ++k) {
      nms = (k == 0 ? c_ : -c_) * SR_.col(j);
      measure_point(h, fx, nms, Ym_.col(2 * j + k));
    }
  }
}

// Deviations from the centre: e_i = X_i - X_0 and Y_i - Y_0, mostly
// sparse (a sigma point moves a few states or wheels). With wm = wc = wi
// off the centre, the means are X_0 + s_x and Y_0 + s_y with
// s = wi sum e (pairs along additive noises cancel), and every covariance
// is wi sum e e^T + (W - 2) s s^T (W = sum of wc = 2 - alpha^2 + beta),
// plus Q's or R's additive block: such a pair adds 2 wi delta delta^T and
// 2 wi c^2 = 1. Leaves the predicted mean in x and ym_, Pxx_, Pyy_, Pxy_.
void UnscentedKalmanFilter::covariances(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R) {
  const Eigen::Index nx = x.size(), ny = Y_.rows(), pa = pa_;
  const double wi = wi_;
  X_.colwise() -= X0_;
  Y_.col(0).setZero();
  Eigen::VectorXd& sx = sx_;
  Eigen::VectorXd& sy = sy_;
  sx.noalias() = X_.rowwise().sum();
  sx *= wi;
  sy.noalias() = Y_.rowwise().sum();
  if (Yp_.cols() > 0) sy.noalias() += Yp_.rowwise().sum();
  if (Ym_.cols() > 0) sy.noalias() += Ym_.rowwise().sum();
  sy *= wi;
  ym_ = Y0_ + sy;
  const double W2 = wc0_ + 2.0 * static_cast<double>(L_) * wi - 2.0;
  Pxx_ = W2 * sx * sx.transpose();
  add_outer(Pxx_, X_, wi, dense_, D_);
  Pxx_.triangularView<Eigen::StrictlyUpper>() = Pxx_.transpose();
  if (pa > 0) Pxx_ += Q.topLeftCorner(nx, nx);
  Pyy_ = W2 * sy * sy.transpose();
  add_outer(Pyy_, Y_, wi, dense_, D_);
  add_outer(Pyy_, Yp_, wi, dense_, D_);
  add_outer(Pyy_, Ym_, wi, dense_, D_);
  Pyy_.triangularView<Eigen::StrictlyUpper>() = Pyy_.transpose();
  if (ma_ > 0) Pyy_ += R.bottomRightCorner(ny, ny);
  // Pxy: f's points, and delta_j (e_j+ - e_j-)^T along the additive process
  // noises (delta_j = c SQ_j, a column of the triangular factor).
  Pxy_ = W2 * sx * sy.transpose();
  add_cross(Pxy_, X_, Y_, wi, dense_, D_, DB_);
  if (pa > 0) {
    Eigen::MatrixXd Yd(pa, ny);
    for (Eigen::Index j = 0; j < pa; ++j) Yd.row(j) = (c_ * wi) * (Yp_.col(2 * j) - Yp_.col(2 * j + 1)).transpose();
    Pxy_.noalias() += SQ_.topLeftCorner(nx, pa).triangularView<Eigen::Lower>() * Yd;
  }
  x = X0_ + sx;
  if (pa > 0) {
    P = 0.5 * (Pxx_ + Pxx_.transpose());
  } else {
    P = Pxx_;  // symmetric already: its upper triangle is a copy of the lower
  }
}

// Eq. 2.20 with Pyy = L L^T: K = Pxy Pyy^-1 = W^T L^-1 for W = L^-1 Pxy^T,
// so K (y - ym) = W^T L^-1 (y - ym) and K Pyy K^T = W^T W.
bool UnscentedKalmanFilter::correct(const Eigen::VectorXd& y) {
  Eigen::LLT<Eigen::MatrixXd>& syy = llt_y_;
  syy.compute(Pyy_);
  if (syy.info() != Eigen::Success) return false;
  Eigen::VectorXd& z = z_;
  z = y - ym_;
  syy.matrixL().solveInPlace(z);  // NIS of Eq. 2.20's innovation (seed 000): |z|^2, gated
  nis = z.squaredNorm();
  log_det_pyy = 2.0 * syy.matrixLLT().diagonal().array().log().sum();
  rejected = !(nis <= gate);
  if (rejected) return true;  // x and P as predicted
  Eigen::MatrixXd& W = W_;
  W = Pxy_.transpose();
  syy.matrixL().solveInPlace(W);
  x.noalias() += W.transpose() * z;
  if (diagonal_only) {
    P = Eigen::VectorXd(P.diagonal() - W.colwise().squaredNorm().transpose()).asDiagonal();
    return true;
  }
  P.selfadjointView<Eigen::Lower>().rankUpdate(W.transpose(), -1.0);
  P.triangularView<Eigen::StrictlyUpper>() = P.transpose();
  return true;
}

void UnscentedKalmanFilter::reset_cross_covariance() { P = Eigen::MatrixXd(P.diagonal().asDiagonal()); }

}  // namespace roverlab::estimation

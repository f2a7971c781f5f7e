#pragma once
// A fixed-size unscented Kalman filter (seed 000 Eq. 2.18-2.20) for models
// whose state and measurement sizes are compile-time constants and whose
// noises are additive: the process noise already added to P by the caller
// (x' = f(x + w)), the measurement noise uncorrelated, y = h(x') + v, v ~
// N(0, diag(r)). The same scaled unscented transform as the generic
// UnscentedKalmanFilter (nonlinear_filter.h) on the augmented state [x; v]
// (L = NX + NY), with the same weights, gate and results up to rounding;
// its matrices live on the stack and its products are unrolled by Eigen.
// Used by the net-traction estimators (22 + 11 and 9 + 9).

#include <array>
#include <cmath>
#include <cstddef>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace roverlab::estimation {

template <int NX, int NY>
class FixedUnscentedFilter {
 public:
  using State = Eigen::Matrix<double, NX, 1>;
  using Covariance = Eigen::Matrix<double, NX, NX>;
  using Measurement = Eigen::Matrix<double, NY, 1>;
  static constexpr int kPoints = 2 * NX;  // sigma points besides the centre

  State x = State::Zero();
  Covariance P = Covariance::Identity();
  double alpha = 1.0, beta = 2.0, kappa = 0.0;
  double gate = HUGE_VAL;  // NIS gate of the update (a chi-square quantile)
  double nis = 0, log_det_pyy = 0;
  bool rejected = false;
  // The model's promise that measurement j is state copied_state[j]
  // unchanged (h's row j copies it; -1: it does not). Pxy's column j is
  // then Pxx's column copied_state[j] and is not summed again.
  std::array<int, NY> copied_state = not_copied();

  // One predict-update cycle: f(const State&, State&) and
  // h(const State&, Measurement&). Returns false when P or Pyy is not
  // positive definite (the state is then left as it was, or as predicted).
  template <class F, class H>
  bool step(const F& f, const H& h, const Measurement& r, const Measurement& y) {
    if (!sigma_factor()) return false;
    f(x, X0_);
    State xs, fx;
    for (int d = 0; d < NX; ++d) {
      for (int k = 0; k < 2; ++k) {
        if (k == 0) xs = x + S_.col(d);
        if (k == 1) xs = x - S_.col(d);
        f(xs, fx);
        XP_.col(2 * d + k) = fx;
      }
    }
    EX_ = XP_.colwise() - X0_;
    measure(h);
    const State sx = wi_ * EX_.rowwise().sum();
    lower_outer_sum(EX_, Pxx_);
    Pxx_ *= wi_;
    Pxx_.noalias() += W2_ * sx * sx.transpose();
    x = X0_ + sx;
    P = Pxx_.template selfadjointView<Eigen::Lower>();
    int summed[NY], n = 0;
    for (int j = 0; j < NY; ++j) {
      if (copied_state[static_cast<std::size_t>(j)] < 0) summed[n++] = j;
    }
    Pxy_.setZero();
    for (int k = 0; k < kPoints; ++k) {
      for (int i = 0; i < n; ++i) Pxy_.col(summed[i]) += EX_.col(k) * EY_(summed[i], k);
    }
    Pxy_ *= wi_;
    Pxy_.noalias() += W2_ * sx * sy_.transpose();
    for (int j = 0; j < NY; ++j) {
      if (copied_state[static_cast<std::size_t>(j)] >= 0)
        Pxy_.col(j) = P.col(copied_state[static_cast<std::size_t>(j)]);
    }
    return correct(r, y);
  }

  // The same with the identity as process model (a random walk, Eq.
  // 5.50-5.52 of seed 003): the transform returns x and P unchanged, so only
  // h is evaluated; the sigma points' deviations are +-c S's columns.
  template <class H>
  bool update(const H& h, const Measurement& r, const Measurement& y) {
    if (!sigma_factor()) return false;
    X0_ = x;
    for (int d = 0; d < NX; ++d) {
      EX_.col(2 * d) = S_.col(d);
      EX_.col(2 * d + 1) = -S_.col(d);
      XP_.col(2 * d) = x + S_.col(d);
      XP_.col(2 * d + 1) = x - S_.col(d);
    }
    measure(h);
    outer_sum(EX_, EY_, Pxy_);
    Pxy_ *= wi_;
    return correct(r, y);
  }

 private:
  using Points = Eigen::Matrix<double, NX, kPoints>;
  using MeasuredPoints = Eigen::Matrix<double, NY, kPoints>;
  using MeasurementCovariance = Eigen::Matrix<double, NY, NY>;

  // The lower triangle of M = E E^T (the upper is left as it was): half
  // the products of the full outer-product sum, column by column.
  template <int N, int K>
  static void lower_outer_sum(const Eigen::Matrix<double, N, K>& E, Eigen::Matrix<double, N, N>& M) {
    M.setZero();
    for (int k = 0; k < K; ++k) {
      const double* e = E.col(k).data();
      for (int j = 0; j < N; ++j) {
        const double ej = e[j];
        double* m = M.col(j).data();
        for (int i = j; i < N; ++i) m[i] += e[i] * ej;
      }
    }
  }

  static std::array<int, NY> not_copied() {
    std::array<int, NY> a{};
    a.fill(-1);
    return a;
  }

  // M = A B^T as a sum of outer products (independent accumulations: a
  // coefficient-wise product's reductions over K would wait on each other).
  template <int N, int M, int K>
  static void outer_sum(const Eigen::Matrix<double, N, K>& A, const Eigen::Matrix<double, M, K>& B,
                        Eigen::Matrix<double, N, M>& C) {
    C.setZero();
    for (int k = 0; k < K; ++k) {
      for (int j = 0; j < M; ++j) C.col(j) += A.col(k) * B(j, k);
    }
  }

  // The scaled Cholesky factor c sqrt(P) and the weights of the augmented
  // state's 2L + 1 points (Eq. 2.18).
  bool sigma_factor() {
    nis = 0;
    rejected = false;
    constexpr double L = NX + NY;
    const double lambda = alpha * alpha * (L + kappa) - L;
    const double c = std::sqrt(L + lambda);
    wi_ = 0.5 / (L + lambda);
    W2_ = lambda / (L + lambda) + (1.0 - alpha * alpha + beta) + 2.0 * L * wi_ - 2.0;
    llt_x_.compute(P);
    if (llt_x_.info() != Eigen::Success) return false;
    S_ = c * llt_x_.matrixL().toDenseMatrix();
    return true;
  }

  // Eq. 2.19 on the centre X0_ and the points XP_: deviations EY_ from h(X0_),
  // the mean offset sy_ and Pyy_ (the points along the additive measurement
  // noises add diag(r), their deviations cancel in the mean).
  template <class H>
  void measure(const H& h) {
    h(X0_, Y0_);
    State xs;
    Measurement hy;
    for (int i = 0; i < kPoints; ++i) {
      xs = XP_.col(i);
      h(xs, hy);
      EY_.col(i) = hy - Y0_;
    }
    sy_ = wi_ * EY_.rowwise().sum();
    lower_outer_sum(EY_, Pyy_);
    Pyy_ *= wi_;
    Pyy_.noalias() += W2_ * sy_ * sy_.transpose();  // LLT reads the lower triangle only
  }

  // Eq. 2.20 with Pyy = L L^T: K (y - ym) = W^T L^-1 (y - ym) and K Pyy K^T
  // = W^T W for W = L^-1 Pxy^T; gated by the NIS |L^-1 (y - ym)|^2.
  bool correct(const Measurement& r, const Measurement& y) {
    Pyy_ += r.asDiagonal();
    llt_y_.compute(Pyy_);
    if (llt_y_.info() != Eigen::Success) return false;
    const Eigen::Matrix<double, NY, NY>& Ly = llt_y_.matrixLLT();  // lower triangle: L
    // Bt = [y - ym, Pxy^T]^T, then (L^-1 [y - ym, Pxy^T])^T: forward
    // substitution on contiguous columns.
    Eigen::Matrix<double, 1 + NX, NY> Bt;
    Bt.row(0) = (y - (Y0_ + sy_)).transpose();
    Bt.template bottomRows<NX>() = Pxy_;
    for (int i = 0; i < NY; ++i) {
      for (int j = 0; j < i; ++j) Bt.col(i) -= Ly(i, j) * Bt.col(j);
      Bt.col(i) /= Ly(i, i);
    }
    nis = Bt.row(0).squaredNorm();
    log_det_pyy = 2.0 * Ly.diagonal().array().log().sum();
    rejected = !(nis <= gate);
    if (rejected) return true;  // x and P as predicted
    const Eigen::Matrix<double, NX, NY> Wt = Bt.template bottomRows<NX>();
    x.noalias() += Wt * Bt.row(0).transpose();
    Covariance KK;
    lower_outer_sum(Wt, KK);
    P -= KK;
    P = P.template selfadjointView<Eigen::Lower>();
    return true;
  }

  double wi_ = 0, W2_ = 0;
  Eigen::LLT<Covariance> llt_x_;
  Eigen::LLT<MeasurementCovariance> llt_y_;
  Covariance S_ = Covariance::Zero(), Pxx_ = Covariance::Zero();
  State X0_ = State::Zero();
  Measurement Y0_ = Measurement::Zero(), sy_ = Measurement::Zero();
  Points XP_ = Points::Zero(), EX_ = Points::Zero();  // the points through f, their deviations from X0_
  MeasuredPoints EY_ = MeasuredPoints::Zero();
  MeasurementCovariance Pyy_ = MeasurementCovariance::Zero();
  Eigen::Matrix<double, NX, NY> Pxy_ = Eigen::Matrix<double, NX, NY>::Zero();
};

}  // namespace roverlab::estimation

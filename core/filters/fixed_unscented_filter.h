#pragma once
// A fixed-size unscented Kalman filter (seed 000 Eq. 2.18-2.20) for models
// whose state and measurement sizes are compile-time constants and whose
// noises are additive: the process noise already added to P by the caller
// (x' = f(x + w)), the measurement noise uncorrelated, y = h(x') + v, v ~
// N(0, diag(r)). The same scaled unscented transform as the generic
// UnscentedKalmanFilter (nonlinear_filter.h) on the augmented state [x; v]
// (L = NX + NY), with the same weights, gate and results up to rounding;
// its matrices live on the stack and its products are unrolled by Eigen.
// Used by the net-traction estimators (22 + 11 and 9 + 9). step_augmented
// is the generic filter's full augmented step (non-additive process and
// measurement noises besides the additive ones), used by the contact-angle
// UKF (contact_angle_ukf.cpp).

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
  // The seed's workaround inside the step (step_augmented): P is diagonal on
  // entry and only the diagonal of the updated P is computed and kept.
  bool diagonal_only = false;
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

  // The generic UnscentedKalmanFilter's step (Eq. 2.18-2.20, seed 000) on
  // the augmented state [x; w_a; w_n; v_n; v_a] with uncorrelated noises:
  // x' = f(x, w_n) + w_a (w_a ~ N(0, diag(q)), w_n ~ N(0, diag(qn)), NW of
  // them), y = h(x', v_n) + v_a (v_n ~ N(0, diag(rn)), nrn of them, v_a ~
  // N(0, diag(r))); L = 2 NX + NW + nrn + NY, the same points and weights.
  // The model m provides f(x, j, v, out): f with w_n's entry j = v (j < 0:
  // w_n = 0); h(x, out): h at zero noise, the centre the next calls refer
  // to; h_moved(x, changed, n, out): h at a point that differs from the
  // centre in the n listed states; h_noise(j, v, out): h at the centre with
  // v_n's entry j = v. Deviations are summed where they are nonzero (a point
  // moves a few states, a few measurements). Returns false when a covariance
  // is not positive definite (the state is then left as it was, or as
  // predicted).
  template <int NW, class Model>
  bool step_augmented(Model& m, const State& q, const Eigen::Matrix<double, NW, 1>& qn, const double* rn, int nrn,
                      const Measurement& r, const Measurement& y) {
    nis = 0;
    rejected = false;
    if (!augmented_factor(2.0 * NX + NW + nrn + NY)) return false;
    if (!noises_positive(q, qn, rn, nrn, r)) return false;
    m.f(x, -1, 0.0, X0_);
    m.h(X0_, Y0_);
    sx_.setZero();
    sy_.setZero();
    Pxx_.setZero();
    Pyy_.setZero();
    Pxy_.setZero();
    spread_state_points(m, qn);
    spread_additive_process_noises(m, q);
    spread_measurement_noises(m, rn, nrn);
    combine_augmented(q);
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

  // The indices of v's nonzero entries into idx; their count.
  template <int N>
  static int nonzeros(const Eigen::Matrix<double, N, 1>& v, int* idx) {
    int n = 0;
    for (int k = 0; k < N; ++k) {
      if (v(k) != 0.0) idx[n++] = k;
    }
    return n;
  }

  // M's lower triangle += e e^T over e's n nonzero entries idx (ascending).
  static void add_lower(const Measurement& e, const int* idx, int n, Eigen::Matrix<double, NY, NY>& M) {
    for (int a = 0; a < n; ++a) {
      const double ea = e(idx[a]);
      for (int b = 0; b <= a; ++b) M(idx[a], idx[b]) += ea * e(idx[b]);
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
    if (diagonal_only) {  // only P's diagonal is kept
      P.diagonal() -= Wt.rowwise().squaredNorm();
      return true;
    }
    Covariance KK;
    lower_outer_sum(Wt, KK);
    P -= KK;
    P = P.template selfadjointView<Eigen::Lower>();
    return true;
  }

  // step_augmented's steps. The scaled factor c sqrt(P) (or its diagonal)
  // and the weights of the augmented state's 2L + 1 points (Eq. 2.18).
  bool augmented_factor(double L) {
    const double lambda = alpha * alpha * (L + kappa) - L;
    c_ = std::sqrt(L + lambda);
    wi_ = 0.5 / (L + lambda);
    W2_ = lambda / (L + lambda) + (1.0 - alpha * alpha + beta) + 2.0 * L * wi_ - 2.0;
    if (diagonal_only) {
      if (!(P.diagonal().array() > 0.0).all()) return false;
      S_ = (c_ * P.diagonal().cwiseSqrt()).asDiagonal();
      return true;
    }
    llt_x_.compute(P);
    if (llt_x_.info() != Eigen::Success) return false;
    S_ = c_ * llt_x_.matrixL().toDenseMatrix();
    return true;
  }

  template <int NW>
  static bool noises_positive(const State& q, const Eigen::Matrix<double, NW, 1>& qn, const double* rn, int nrn,
                              const Measurement& r) {
    bool positive = (q.array() > 0.0).all() && (qn.array() > 0.0).all() && (r.array() > 0.0).all();
    for (int j = 0; j < nrn; ++j) positive = positive && rn[j] > 0.0;
    return positive;
  }

  // One point xp_ through h (deviations ex_ from X0_, ey_ from Y0_), summed
  // where they are nonzero (a point moves a few states, a few measurements).
  template <class Model>
  void add_state_point(Model& m) {
    ex_ = xp_ - X0_;
    int nxc = 0;
    for (int k = 0; k < NX; ++k) {
      if (ex_(k) != 0.0) changed_[nxc++] = k;
    }
    m.h_moved(xp_, changed_.data(), nxc, hy_);
    ey_ = hy_ - Y0_;
    const int nyc = nonzeros(ey_, iy_.data());
    sx_ += ex_;
    sy_ += ey_;
    for (int a = 0; a < nxc; ++a) {
      const int ia = changed_[static_cast<std::size_t>(a)];
      const double ea = ex_(ia);
      if (diagonal_only) {
        Pxx_(ia, ia) += ea * ea;
      } else {
        for (int b = 0; b <= a; ++b)
          Pxx_(ia, changed_[static_cast<std::size_t>(b)]) += ea * ex_(changed_[static_cast<std::size_t>(b)]);
      }
      for (int b = 0; b < nyc; ++b)
        Pxy_(ia, iy_[static_cast<std::size_t>(b)]) += ea * ey_(iy_[static_cast<std::size_t>(b)]);
    }
    add_lower(ey_, iy_.data(), nyc, Pyy_);
  }

  // The points along the state and along the non-additive process noises,
  // through f and h.
  template <int NW, class Model>
  void spread_state_points(Model& m, const Eigen::Matrix<double, NW, 1>& qn) {
    for (int d = 0; d < NX; ++d) {
      for (int k = 0; k < 2; ++k) {
        m.f(k == 0 ? State(x + S_.col(d)) : State(x - S_.col(d)), -1, 0.0, xp_);
        add_state_point(m);
      }
    }
    for (int j = 0; j < NW; ++j) {
      for (int k = 0; k < 2; ++k) {
        m.f(x, j, (k == 0 ? c_ : -c_) * std::sqrt(qn(j)), xp_);
        add_state_point(m);
      }
    }
  }

  // Along the additive process noises: X0 +- delta_j e_j through h only;
  // Pxy gains delta_j (ey+ - ey-)^T, Pxx q (a pair adds 2 wi delta^2 = q_j).
  template <class Model>
  void spread_additive_process_noises(Model& m, const State& q) {
    for (int j = 0; j < NX; ++j) {
      const double delta = c_ * std::sqrt(q(j));
      Measurement pair = Measurement::Zero();
      for (int k = 0; k < 2; ++k) {
        xp_ = X0_;
        xp_(j) += k == 0 ? delta : -delta;
        changed_[0] = j;
        m.h_moved(xp_, changed_.data(), 1, hy_);
        ey_ = hy_ - Y0_;
        sy_ += ey_;
        add_lower(ey_, iy_.data(), nonzeros(ey_, iy_.data()), Pyy_);
        pair += k == 0 ? ey_ : Measurement(-ey_);
      }
      Pxy_additive_.row(j) = (c_ * wi_ * std::sqrt(q(j))) * pair.transpose();
    }
  }

  // Along the non-additive measurement noises: h only.
  template <class Model>
  void spread_measurement_noises(Model& m, const double* rn, int nrn) {
    for (int j = 0; j < nrn; ++j) {
      for (int k = 0; k < 2; ++k) {
        m.h_noise(j, (k == 0 ? c_ : -c_) * std::sqrt(rn[j]), hy_);
        ey_ = hy_ - Y0_;
        sy_ += ey_;
        add_lower(ey_, iy_.data(), nonzeros(ey_, iy_.data()), Pyy_);
      }
    }
  }

  // Means X0 + wi sum ex, Y0 + wi sum ey; covariances wi sum e e^T + (W - 2) s s^T.
  void combine_augmented(const State& q) {
    sx_ *= wi_;
    sy_ *= wi_;
    Pxx_ *= wi_;
    Pyy_ *= wi_;
    Pxy_ *= wi_;
    Pxy_ += Pxy_additive_;
    Pxy_.noalias() += W2_ * sx_ * sy_.transpose();
    Pyy_.noalias() += W2_ * sy_ * sy_.transpose();
    x = X0_ + sx_;
    if (diagonal_only) {
      P = (Pxx_.diagonal() + W2_ * sx_.cwiseAbs2() + q).asDiagonal();
    } else {
      Pxx_.noalias() += W2_ * sx_ * sx_.transpose();
      P = Pxx_.template selfadjointView<Eigen::Lower>();
      P.diagonal() += q;
    }
  }

  double wi_ = 0, W2_ = 0, c_ = 0;
  // step_augmented's point in work and its deviations.
  State sx_ = State::Zero(), xp_ = State::Zero(), ex_ = State::Zero();
  Measurement hy_ = Measurement::Zero(), ey_ = Measurement::Zero();
  std::array<int, NX> changed_{};
  std::array<int, NY> iy_{};
  Eigen::Matrix<double, NX, NY> Pxy_additive_ = Eigen::Matrix<double, NX, NY>::Zero();
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

#pragma once
// The contact-angle EKF specialised to its model's structure (seed 000,
// Eq. 2.14-2.17): the fast path of ContactAngleEstimator, consuming the same
// ContactProcessModel and WheelMeasurementModel as the generic filters.
// The models' fast-path members are defined here, inline, so that they
// compile with the fast EKF (out of line, GCC stopped inlining their small
// Eigen kernels and the whole process took 8-15% longer).

#include <ceres/jet.h>

#include <cmath>

#include <Eigen/Core>

#include "core/estimation/contact_angle/model.h"

namespace roverlab::estimation {

namespace contact {

inline void ContactProcessModel::strapdown_step(double* att_v, const Inputs& in, double ts,
                                                Eigen::Matrix<double, 6, 6>& A, Eigen::Matrix<double, 6, 6>& B) const {
  // Jacobians of Eq. 4.13-4.14 with respect to attitude, velocity and the
  // accelerometer and gyro noises.
  using Jt = ceres::Jet<double, 12>;
  const Jt zero(0.0);
  const Jt zeros[3] = {zero, zero, zero};
  Jt a[3], v[3], nf[3], nw[3], an[3], vn[3];
  for (int k = 0; k < 3; ++k) {
    a[k] = Jt(att_v[k], k);
    v[k] = Jt(att_v[3 + k], 3 + k);
    nf[k] = Jt(0.0, 6 + k);
    nw[k] = Jt(0.0, 9 + k);
  }
  // The attitude's cosines and sines as Jets from one sincos each (ceres'
  // cos and sin of a Jet take a cos and a sin each): d cos = -sin, d sin = cos.
  Jt trig[6];
  for (int k = 0; k < 3; ++k) {
    const double c = std::cos(att_v[k]), s = std::sin(att_v[k]);
    trig[2 * k] = Jt(c);
    trig[2 * k].v[k] = -s;
    trig[2 * k + 1] = Jt(s);
    trig[2 * k + 1].v[k] = c;
  }
  const contact::AttitudeTrig<Jt> tr{trig[0], trig[1], trig[2], trig[3], trig[4], trig[5]};
  strapdown<Jt>(a, tr, v, zeros, zeros, nf, nw, in, g_i_, ts, an, vn);
  for (int k = 0; k < 3; ++k) {
    att_v[k] = an[k].a;
    att_v[3 + k] = vn[k].a;
    for (int c = 0; c < 6; ++c) {
      A(k, c) = an[k].v[c];
      A(3 + k, c) = vn[k].v[c];
      B(k, c) = an[k].v[6 + c];
      B(3 + k, c) = vn[k].v[6 + c];
    }
  }
}

inline WheelLinearization WheelMeasurementModel::linearize_wheel(int w, const double* x, const Inputs& in) const {
  const int na = layout_.na;
  return contact::linearize_wheel(*m_, w, frame_, x + 3, x[ContactLayout::slip(w)],
                                  na >= 6 ? x[ContactLayout::contact_angle(w)] : 0.0,
                                  na >= 12 ? x[ContactLayout::side_slip_angle(w)] : 0.0, in);
}

inline void WheelMeasurementModel::add_noise_covariance(const WheelLinearization* lin, const Eigen::VectorXd& r,
                                                        Eigen::Matrix<double, 18, 18>& S) const {
  const kinematics::RoverModel& m = *m_;
  const int nw = 6, nq = layout_.nq;
  Eigen::Matrix3d Gw[6];
  const Eigen::Vector3d gyro_sd = r.head<3>().cwiseSqrt();
  for (int w = 0; w < nw; ++w) {
    Gw[w] = lin[w].d.template block<3, 3>(0, 6) * gyro_sd.asDiagonal();
    S(3 * w, 3 * w) += r(3 + w);
    S(3 * w + 1, 3 * w + 1) += r(3 + nw + 2 * nq + w);
    S(3 * w + 2, 3 * w + 2) += r(3 + 2 * nw + 2 * nq + w);
  }
  for (int w1 = 0; w1 < nw; ++w1) {
    const auto& c1 = m.wheels[static_cast<std::size_t>(w1)];
    const int j1[2] = {c1.bogie_joint, c1.steer_joint};
    for (int w2 = 0; w2 <= w1; ++w2) {
      const auto& c2 = m.wheels[static_cast<std::size_t>(w2)];
      const int j2[2] = {c2.bogie_joint, c2.steer_joint};
      Eigen::Matrix3d B = Gw[w1] * Gw[w2].transpose();
      for (int a = 0; a < 2; ++a) {
        for (int b = 0; b < 2; ++b) {
          if (j1[a] < 0 || j1[a] != j2[b]) continue;
          const int j = j1[a];
          B.noalias() += r(3 + nw + j) * lin[w1].d.col(9 + a) * lin[w2].d.col(9 + b).transpose();
          B.noalias() += r(3 + nw + nq + j) * lin[w1].d.col(11 + a) * lin[w2].d.col(11 + b).transpose();
        }
      }
      S.template block<3, 3>(3 * w1, 3 * w2) += B;  // lower blocks only: the factorisation reads no more
    }
  }
}

}  // namespace contact

// The EKF of Eq. 2.14-2.17 specialised to this model: fixed-size matrices,
// the process Jacobian's block structure (only the attitude-velocity block
// is full) and the measurement Jacobian's (each wheel sees the velocity and
// its own slip and angles), hand-derived wheel Jacobians. Tested equal to
// the generic ExtendedKalmanFilter with ceres::Jet Jacobians.
template <int NA>
class FastEkf {
 public:
  static constexpr int NX = 12 + NA, NY = 18, NR = NX - 6;
  Eigen::Matrix<double, NX, 1> x;
  Eigen::Matrix<double, NX, NX> P;
  // The update's NIS gate (a chi-square quantile), the last update's
  // normalised innovation squared z^T z and whether the gate rejected it.
  double gate = HUGE_VAL;
  double nis = 0;
  double log_det_s = 0;  // ln det S of the last update (its innovation's likelihood)
  // When set, the update's effective degrees of freedom tr(H K) (the hat
  // matrix's trace: how much of the measurement the state absorbed).
  bool effective_dof = false;
  double dof_used = 0;
  // The last predict's strapdown Jacobian A and the private states' factor
  // d (slip, angle): F = blockdiag(A, diag(d)), for the RTS smoother.
  Eigen::Matrix<double, 6, 6> last_A = Eigen::Matrix<double, 6, 6>::Identity();
  double last_slip_keep = 1, last_angle_keep = 1;
  bool rejected = false;

  // Eq. 2.14-2.15 with F = blockdiag(A, diag(d)): P11 <- A P11 A^T + G G^T,
  // P12 <- A P12 D, P22 <- D P22 D + Q22. p_diagonal: P12 is zero and P22
  // diagonal on entry (the seed's reset), and so they stay.
  void predict(const contact::ContactProcessModel& f, const Eigen::VectorXd& q, const contact::Inputs& in, double ts,
               bool p_diagonal = false) {
    Eigen::Matrix<double, 6, 6> A, G;  // G: noise Jacobian times the noise standard deviations
    f.strapdown_step(x.data(), in, ts, A, G);
    last_A = A;
    last_slip_keep = f.slip_keep(ts);
    last_angle_keep = f.angle_keep(ts);
    for (int c = 0; c < 6; ++c) G.col(c) *= std::sqrt(q(NX + c));
    Eigen::Matrix<double, NR, 1> d;
    d.template head<6>().setConstant(f.slip_keep(ts));
    d.template tail<NA>().setConstant(f.angle_keep(ts));
    x.template tail<NR>() = d.cwiseProduct(x.template tail<NR>());
    const Eigen::Matrix<double, 6, 6> AP = A.lazyProduct(P.template topLeftCorner<6, 6>());
    Eigen::Matrix<double, 6, 6> P11 = AP.lazyProduct(A.transpose()) + G.lazyProduct(G.transpose());
    P11.diagonal() += q.template head<6>();
    P.template topLeftCorner<6, 6>() = 0.5 * (P11 + P11.transpose());
    if (p_diagonal) {
      auto P22 = P.template bottomRightCorner<NR, NR>().diagonal();
      P22 = P22.cwiseProduct(d.cwiseProduct(d)) + q.segment(6, NR);
      return;
    }
    const Eigen::Matrix<double, 6, NR> P12 = A.lazyProduct(P.template topRightCorner<6, NR>()) * d.asDiagonal();
    P.template topRightCorner<6, NR>() = P12;
    P.template bottomLeftCorner<NR, 6>() = P12.transpose();
    P.template bottomRightCorner<NR, NR>() = P.template bottomRightCorner<NR, NR>().cwiseProduct(d * d.transpose());
    P.template bottomRightCorner<NR, NR>().diagonal() += q.segment(6, NR);
  }

  // Eq. 2.16-2.17, Joseph form (I - KH) P (I - KH)^T + K R K^T expanded as
  // P - K H P - P H^T K^T + K S K^T with K S K^T = (K L)(K L)^T, S = L L^T.
  // diagonal_only keeps only P's diagonal (the seed's workaround follows).
  // An innovation whose NIS exceeds `gate` leaves x and P as predicted.
  bool update(const contact::WheelMeasurementModel& h, const Eigen::VectorXd& r, const contact::Inputs& in,
              bool diagonal_only, bool block_diagonal = false) {
    rejected = false;
    contact::WheelLinearization lin[6];
    int priv[6][3];
    constexpr int npriv = 1 + NA / 6;
    Eigen::Matrix<double, NY, 1> innov;
    for (int w = 0; w < 6; ++w) {
      lin[w] = h.linearize_wheel(w, x.data(), in);
      innov.template segment<3>(3 * w) = Eigen::Vector3d(in.wheel_rate[w], 0.0, 0.0) - lin[w].value;
      for (int p = 0; p < 3; ++p) priv[w][p] = contact::ContactLayout::wheel_state(p, w);
    }
    // P H^T and H P H^T, one wheel (three rows of H) at a time; with the
    // reset S's lower blocks straight from P11's velocity block and the
    // private variances, P H^T only if the Joseph form follows.
    Eigen::Matrix<double, NX, NY> PHt;
    Eigen::Matrix<double, NY, NY> S;
    if (block_diagonal) {
      reset_hpht(lin, S);
      if (effective_dof) S.template triangularView<Eigen::StrictlyUpper>() = S.transpose();
    } else {
      for (int w = 0; w < 6; ++w) {
        auto cols = PHt.template middleCols<3>(3 * w);
        cols.noalias() = P.template middleCols<3>(3) * lin[w].d.template leftCols<3>().transpose();
        for (int p = 0; p < npriv; ++p) cols.noalias() += P.col(priv[w][p]) * lin[w].d.col(3 + p).transpose();
      }
      for (int w = 0; w < 6; ++w) {
        auto rows = S.template middleRows<3>(3 * w);
        rows.noalias() = lin[w].d.template leftCols<3>() * PHt.template middleRows<3>(3);
        for (int p = 0; p < npriv; ++p) rows.noalias() += lin[w].d.col(3 + p) * PHt.row(priv[w][p]);
      }
    }
    Eigen::Matrix<double, NY, NY> HPHt;
    if (effective_dof) HPHt = S;
    h.add_noise_covariance(lin, r, S);
    Eigen::Matrix<double, NY, NY> Lm;
    if (!cholesky(S, Lm)) return false;
    if (effective_dof) {  // tr(H K) = tr(S^-1 H P H^T) = tr(L^-1 H P H^T L^-T)
      const auto L = Lm.template triangularView<Eigen::Lower>();
      const Eigen::Matrix<double, NY, NY> Y = L.solve(HPHt);
      dof_used = L.solve(Eigen::Matrix<double, NY, NY>(Y.transpose())).trace();
    }
    // z = L^-1 (y - h) by forward substitution.
    Eigen::Matrix<double, NY, 1> z = innov;
    for (int c = 0; c < NY; ++c) {
      z(c) *= inv_diag_(c);
      for (int r = c + 1; r < NY; ++r) z(r) -= Lm(r, c) * z(c);
    }
    nis = z.squaredNorm();  // y^T S^-1 y of Eq. 2.16's innovation (seed 000), S = L L^T; gated
    // ln det S = 2 sum ln L_ii, three logarithms of products of six (an
    // L_ii is the square root of a variance: no overflow or underflow).
    log_det_s = 0.0;
    for (int i = 0; i < NY; i += 6) log_det_s += 2.0 * std::log(Lm.diagonal().template segment<6>(i).prod());
    rejected = !(nis <= gate);
    if (rejected) return true;
    const bool reset = block_diagonal && diagonal_only;
    if (reset && reset_update(lin, Lm, z)) return true;  // else x is updated: the Joseph form follows
    if (block_diagonal) reset_pht(lin, PHt);
    Eigen::Matrix<double, NX, NY> Wt;
    gain_factor(PHt, Lm, block_diagonal, priv, Wt);
    if (!reset) x.noalias() += Wt * z;
    if (diagonal_only && !reset) {
      // The diagonal of the Joseph form with the optimal gain:
      // P_ii - (K H P)_ii - (P H^T K^T)_ii + (K S K^T)_ii = P_ii - |W_i|^2.
      const Eigen::Matrix<double, NX, 1> diag = P.diagonal() - Wt.rowwise().squaredNorm();
      if ((diag.array() > 0.0).all()) {
        P = diag.asDiagonal();
        return true;
      }
    }
    joseph(Wt, Lm, PHt, diagonal_only);
    return true;
  }

 private:
  // K from K L = W^T (backward substitution), then the Joseph form
  // P - K H P - P H^T K^T + (K L)(K L)^T.
  void joseph(const Eigen::Matrix<double, NX, NY>& Wt, const Eigen::Matrix<double, NY, NY>& Lm,
              const Eigen::Matrix<double, NX, NY>& PHt, bool diagonal_only) {
    Eigen::Matrix<double, NX, NY> K = Wt;
    for (int c = NY - 1; c >= 0; --c) {
      for (int r = c + 1; r < NY; ++r) K.col(c) -= Lm(r, c) * K.col(r);
      K.col(c) /= Lm(c, c);
    }
    Eigen::Matrix<double, NX, NY> V = Eigen::Matrix<double, NX, NY>::Zero();  // K L
    for (int c = 0; c < NY; ++c) {
      for (int r = c; r < NY; ++r) V.col(c) += Lm(r, c) * K.col(r);
    }
    const Eigen::Matrix<double, NX, NX> T = K * PHt.transpose();
    P -= T + T.transpose();
    P.noalias() += V * V.transpose();
    if (diagonal_only) P = Eigen::Matrix<double, NX, 1>(P.diagonal()).asDiagonal();  // evaluated first: no aliasing
  }

  // With the reset (P12 = 0, P22 diagonal): H P H^T's lower 3 x 3 blocks,
  // H_w P_vv H_w2^T plus each private variance's P_cc h h^T on its own
  // wheel's block (the factorisation reads only these); the rest zero.
  void reset_hpht(const contact::WheelLinearization* lin, Eigen::Matrix<double, NY, NY>& S) const {
    constexpr int npriv = 1 + NA / 6;
    const Eigen::Matrix3d Pvv = P.template block<3, 3>(3, 3);
    Eigen::Matrix3d A[6];
    for (int w = 0; w < 6; ++w) A[w].noalias() = lin[w].d.template leftCols<3>() * Pvv;
    S.setZero();
    for (int w = 0; w < 6; ++w) {
      for (int w2 = 0; w2 <= w; ++w2)
        S.template block<3, 3>(3 * w, 3 * w2).noalias() = A[w] * lin[w2].d.template leftCols<3>().transpose();
      for (int p = 0; p < npriv; ++p) {
        const double v = P(contact::ContactLayout::wheel_state(p, w), contact::ContactLayout::wheel_state(p, w));
        S.template block<3, 3>(3 * w, 3 * w).noalias() += (v * lin[w].d.col(3 + p)) * lin[w].d.col(3 + p).transpose();
      }
    }
  }

  // P H^T with the reset: the attitude and velocity rows P11's velocity
  // columns times H_v^T, a private row its own wheel's three columns only.
  void reset_pht(const contact::WheelLinearization* lin, Eigen::Matrix<double, NX, NY>& PHt) const {
    constexpr int npriv = 1 + NA / 6;
    PHt.setZero();
    for (int w = 0; w < 6; ++w) {
      PHt.template block<6, 3>(0, 3 * w).noalias() =
          P.template block<6, 3>(0, 3) * lin[w].d.template leftCols<3>().transpose();
      for (int p = 0; p < npriv; ++p) {
        const int c = contact::ContactLayout::wheel_state(p, w);
        PHt.template block<1, 3>(c, 3 * w) = P(c, c) * lin[w].d.col(3 + p).transpose();
      }
    }
  }

  // W^T = P H^T L^-T by forward substitution, so that K = W^T L^-1 and
  // K (y - h) = W^T z. Column-oriented: once W's row c is final, it is
  // taken from every later row (independent length-NX updates instead of a
  // chain of dot products).
  void gain_factor(const Eigen::Matrix<double, NX, NY>& PHt, const Eigen::Matrix<double, NY, NY>& Lm,
                   bool block_diagonal, const int (&priv)[6][3], Eigen::Matrix<double, NX, NY>& Wt) const {
    constexpr int npriv = 1 + NA / 6;
    if (block_diagonal) {
      // With the reset a private state's row of P H^T (and of W^T) is zero
      // left of its wheel's columns: with the private rows ordered by wheel,
      // wheel b's columns touch only the first 6 + npriv (b + 1) rows.
      Eigen::Matrix<double, NX, NY> Wp;
      Wp.template topRows<6>() = PHt.template topRows<6>();
      for (int w = 0; w < 6; ++w) {
        for (int p = 0; p < npriv; ++p) Wp.row(6 + npriv * w + p) = PHt.row(priv[w][p]);
      }
      substitute_by_wheel<0, 6>(Lm, Wp);
      Wt.template topRows<6>() = Wp.template topRows<6>();
      for (int w = 0; w < 6; ++w) {
        for (int p = 0; p < npriv; ++p) Wt.row(priv[w][p]) = Wp.row(6 + npriv * w + p);
      }
    } else {
      Wt = PHt;
      for (int c = 0; c < NY; ++c) {
        Wt.col(c) *= inv_diag_(c);
        for (int r = c + 1; r < NY; ++r) Wt.col(r) -= Lm(r, c) * Wt.col(c);
      }
    }
  }

  // The update with the reset (P12 = 0, P22 diagonal) that keeps only P's
  // diagonal, without W^T: x += P H^T S^-1 (y - h) = P H^T s with
  // s = L^-T z; |W_i|^2 = (P H^T S^-1 H P)_ii from V = L^-1 [H_v, the
  // private rows of P H^T] (H_v: the velocity columns of H; the attitude and
  // velocity rows of P H^T are P11's velocity columns times H_v^T). False,
  // with x updated, when a variance would not stay positive.
  bool reset_update(const contact::WheelLinearization* lin, const Eigen::Matrix<double, NY, NY>& Lm,
                    const Eigen::Matrix<double, NY, 1>& z) {
    constexpr int npriv = 1 + NA / 6;
    Eigen::Matrix<double, NY, 1> s = z;  // L^T s = z, column-oriented backward substitution
    for (int c = NY - 1; c >= 0; --c) {
      s(c) *= inv_diag_(c);
      for (int r = 0; r < c; ++r) s(r) -= Lm(c, r) * s(c);
    }
    Eigen::Matrix<double, 3 + NR, NY> V = Eigen::Matrix<double, 3 + NR, NY>::Zero();  // H_v^T, private rows by wheel
    Eigen::Vector3d hs = Eigen::Vector3d::Zero();                                     // H_v^T s
    for (int w = 0; w < 6; ++w) {
      const Eigen::Matrix3d Hw = lin[w].d.template leftCols<3>();
      V.template block<3, 3>(0, 3 * w) = Hw.transpose();
      hs.noalias() += Hw.transpose() * s.template segment<3>(3 * w);
      for (int p = 0; p < npriv; ++p) {
        const int c = contact::ContactLayout::wheel_state(p, w);
        V.template block<1, 3>(3 + npriv * w + p, 3 * w) = P(c, c) * lin[w].d.col(3 + p).transpose();
        x(c) += V.template block<1, 3>(3 + npriv * w + p, 3 * w).dot(s.template segment<3>(3 * w));
      }
    }
    x.template head<6>().noalias() += P.template block<6, 3>(0, 3) * hs;
    substitute_by_wheel<0, 3>(Lm, V);
    const Eigen::Matrix3d G = V.template topRows<3>() * V.template topRows<3>().transpose();  // H_v^T S^-1 H_v
    Eigen::Matrix<double, NX, 1> diag = P.diagonal();
    for (int i = 0; i < 6; ++i) {
      const Eigen::Vector3d a = P.template block<1, 3>(i, 3).transpose();
      diag(i) -= a.dot(G * a);
    }
    for (int w = 0; w < 6; ++w) {
      for (int p = 0; p < npriv; ++p)
        diag(contact::ContactLayout::wheel_state(p, w)) -= V.row(3 + npriv * w + p).squaredNorm();
    }
    if (!(diag.array() > 0.0).all()) return false;
    P = diag.asDiagonal();
    return true;
  }

  // The forward substitution W^T <- W^T L^-T over wheel B's three columns
  // and on, each column's nonzero head only: Top dense rows, then the
  // private rows ordered by wheel.
  template <int B, int Top, int R>
  void substitute_by_wheel(const Eigen::Matrix<double, NY, NY>& L, Eigen::Matrix<double, R, NY>& Wp) const {
    constexpr int len = Top + (1 + NA / 6) * (B + 1);
    for (int c = 3 * B; c < 3 * B + 3; ++c) {
      Wp.col(c).template head<len>() *= inv_diag_(c);
      for (int r = c + 1; r < NY; ++r) Wp.col(r).template head<len>() -= L(r, c) * Wp.col(c).template head<len>();
    }
    if constexpr (B < 5) substitute_by_wheel<B + 1, Top>(L, Wp);
  }

  // S = L L^T for a small fixed-size S, right-looking over 3 x 3 blocks
  // (one wheel's rows): factor the diagonal block, scale the blocks below it
  // by its inverse, take their outer products from the trailing lower
  // blocks; every product a fixed-size 3 x 3 one the compiler unrolls. Only
  // L's lower triangle is set; inv_diag_ keeps 1 / L_ii. False when S is not
  // positive definite.
  bool cholesky(const Eigen::Matrix<double, NY, NY>& S, Eigen::Matrix<double, NY, NY>& L) {
    constexpr int nb = NY / 3;
    L = S;
    for (int J = 0; J < nb; ++J) {
      auto D = L.template block<3, 3>(3 * J, 3 * J);
      if (!(D(0, 0) > 0.0)) return false;
      D(0, 0) = std::sqrt(D(0, 0));
      const double i0 = 1.0 / D(0, 0);
      D(1, 0) *= i0;
      D(2, 0) *= i0;
      const double d1 = D(1, 1) - D(1, 0) * D(1, 0);
      if (!(d1 > 0.0)) return false;
      D(1, 1) = std::sqrt(d1);
      const double i1 = 1.0 / D(1, 1);
      D(2, 1) = (D(2, 1) - D(2, 0) * D(1, 0)) * i1;
      const double d2 = D(2, 2) - D(2, 0) * D(2, 0) - D(2, 1) * D(2, 1);
      if (!(d2 > 0.0)) return false;
      D(2, 2) = std::sqrt(d2);
      const double i2 = 1.0 / D(2, 2);
      inv_diag_.template segment<3>(3 * J) << i0, i1, i2;
      Eigen::Matrix3d Mt = Eigen::Matrix3d::Zero();  // (L_JJ^-1)^T
      Mt(0, 0) = i0;
      Mt(1, 1) = i1;
      Mt(2, 2) = i2;
      Mt(0, 1) = -D(1, 0) * i0 * i1;
      Mt(1, 2) = -D(2, 1) * i1 * i2;
      Mt(0, 2) = -(D(2, 0) * i0 + D(2, 1) * Mt(0, 1)) * i2;
      for (int I = J + 1; I < nb; ++I) {
        auto B = L.template block<3, 3>(3 * I, 3 * J);
        B = (B * Mt).eval();
      }
      for (int I = J + 1; I < nb; ++I) {
        const Eigen::Matrix3d LIJ = L.template block<3, 3>(3 * I, 3 * J);
        for (int K = J + 1; K <= I; ++K)
          L.template block<3, 3>(3 * I, 3 * K).noalias() -=
              LIJ.lazyProduct(L.template block<3, 3>(3 * K, 3 * J).transpose());
      }
    }
    return true;
  }
  Eigen::Matrix<double, NY, 1> inv_diag_;
};

}  // namespace roverlab::estimation

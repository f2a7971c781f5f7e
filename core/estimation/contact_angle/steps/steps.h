#pragma once
// The fixed-size filter steps of ContactAngleEstimator (seed 000, Eq.
// 2.14-2.17: the fast EKF, its smoother's companion, the fixed-size UKF), for
// one number of angle states NA each. Included only by na0.cpp, na6.cpp and
// na12.cpp beside it, which instantiate them: g++ takes 35-40 s for each
// NA, and in estimator.cpp the three made one 120 s unit that an edit of any
// part recompiled whole (docs/performance.md, "The contact-angle estimator in
// four units").

#include <cmath>

#include <Eigen/Core>

#include "core/estimation/contact_angle/estimator.h"

namespace roverlab::estimation {

template <int NA>
void ContactAngleEstimator::fast_ekf_step(FastEkf<NA>& fe, std::size_t i, const contact::Inputs& in, double ts,
                                          bool update) {
  if (i == 0) {
    fe.x = x0_;
    fe.P = p0_.asDiagonal();
  }
  if (i > 0) {
    if (smooth_) companion_predict(fe, i, in, ts);                              // from the state before this predict
    fe.predict(process_, process_noise(i), in, ts, o_.reset_cross_covariance);  // with the reset P is diagonal here
    if (smooth_) record_prediction(i, fe.x.data());
  }
  // With the reset, P is blockdiag(P11, diag) after the predict.
  if (i == 0 && smooth_) {
    companion<NA>().x = x0_;
    companion<NA>().P = p0_.asDiagonal();
  }
  if (update) {
    fe.gate = health_.gate(FastEkf<NA>::NY);
    fe.effective_dof = o_.effective_dof;
    if (fe.update(measurement_, rdiag_, in, o_.reset_cross_covariance, o_.reset_cross_covariance)) {
      health_.record(imu_->time()[i], fe.nis, FastEkf<NA>::NY);
      innovations_.add(fe.nis, fe.log_det_s, FastEkf<NA>::NY, fe.dof_used);
    }
  }
  // The diagonal evaluated first: P = P.diagonal().asDiagonal() zeroes P (Eigen sets it to 0, then copies the
  // diagonal).
  if ((!update || fe.rejected) && o_.reset_cross_covariance)
    fe.P = Eigen::Matrix<double, FastEkf<NA>::NX, 1>(fe.P.diagonal()).asDiagonal();
  x_ = fe.x;
  if (smooth_) {
    if (update && !fe.rejected) {
      FastEkf<NA>& ff = companion<NA>();
      ff.gate = HUGE_VAL;
      ff.update(measurement_, rdiag_, in, false, false);
    }
    record_filtered(i, fe.x.data(), i == 0);
  }
}

// The same on the fixed-size filter of the model (the same estimates).
template <int NA>
void ContactAngleEstimator::fixed_ukf_step(ContactAngleUkf<NA>& u, std::size_t i, const contact::Inputs& in, double ts,
                                           bool update) {
  if (i > 0 && update) {
    constexpr int ny = ContactAngleUkf<NA>::NY;
    u.filter.gate = health_.gate(ny);
    if (u.step(process_, measurement_, in, ts, y_meas_)) {
      health_.record(imu_->time()[i], u.filter.nis, ny);
      innovations_.add(u.filter.nis, u.filter.log_det_pyy, ny);
    }
  } else if (i > 0) {
    u.predict(process_, in, ts);
  }
  using Covariance = typename ContactAngleUkf<NA>::Filter::Covariance;
  if (o_.reset_cross_covariance) u.filter.P = Covariance(u.filter.P.diagonal().asDiagonal());
  x_ = u.filter.x;
}

// The smoother's companion filter: the fast EKF's predict and update at the
// same linearisation points, without the reset, so that its full P holds the
// couplings the reset drops; from it the RTS gain C_k = P_k|k F^T P_k+1|k^-1.
template <int NA>
void ContactAngleEstimator::companion_predict(const FastEkf<NA>& fe, std::size_t i, const contact::Inputs& in,
                                              double ts) {
  constexpr int NX = FastEkf<NA>::NX;
  FastEkf<NA>& ff = companion<NA>();
  const Eigen::Matrix<double, NX, NX> Pf = ff.P;
  ff.x = fe.x;
  ff.predict(process_, process_noise(i), in, ts);
  Eigen::Matrix<double, NX, NX> F = Eigen::Matrix<double, NX, NX>::Zero();
  F.template topLeftCorner<6, 6>() = ff.last_A;
  for (int j = 6; j < NX; ++j) F(j, j) = j < 12 ? ff.last_slip_keep : ff.last_angle_keep;
  Eigen::Map<Eigen::Matrix<float, NX, NX>> gain(&sm_c_[(i - 1) * NX * NX]);
  gain = ff.P.ldlt().solve(F * Pf).transpose().template cast<float>();  // P symmetric: (P_k+1|k^-1 F P_k|k)^T
}

}  // namespace roverlab::estimation

// The steps' explicit instantiations for NA angle states, one line in each
// na*.cpp (at namespace scope).
#define ROVERLAB_CONTACT_ANGLE_STEPS(NA)                                                                             \
  template void roverlab::estimation::ContactAngleEstimator::fast_ekf_step<NA>(                                      \
      roverlab::estimation::FastEkf<NA>&, std::size_t, const roverlab::estimation::contact::Inputs&, double, bool);  \
  template void roverlab::estimation::ContactAngleEstimator::fixed_ukf_step<NA>(                                     \
      roverlab::estimation::ContactAngleUkf<NA>&, std::size_t, const roverlab::estimation::contact::Inputs&, double, \
      bool)

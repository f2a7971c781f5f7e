#include "core/estimation/ins_slip/filter.h"

#include <algorithm>
#include <cmath>

#include "core/filters/kalman.h"

namespace roverlab::estimation {

LocalFrame::LocalFrame(double lat, double lon, double h)
    : latitude(lat), longitude(lon), height(h), rn(meridian_radius(lat) + h), re(transverse_radius(lat) + h) {}

InsTrack::InsTrack(std::size_t n)
    : roll(n),
      pitch(n),
      yaw(n),
      east(n),
      north(n),
      up(n),
      vn(n),
      ve(n),
      vd(n),
      vx(n),
      vy(n),
      vz(n),
      bias(6, std::vector<double>(n)),
      valid(n, 1.0) {}

void InsTrack::record(std::size_t i, const InsState& s, const LocalFrame& f) {
  const Eigen::Vector3d e = euler_from_dcm(s.C_bn);
  roll[i] = e.x();
  pitch[i] = e.y();
  yaw[i] = e.z();
  north[i] = (s.latitude - f.latitude) * f.rn;
  east[i] = (s.longitude - f.longitude) * f.re * std::cos(f.latitude);
  up[i] = s.height - f.height;
  vn[i] = s.v_n.x();
  ve[i] = s.v_n.y();
  vd[i] = s.v_n.z();
  const Eigen::Vector3d vb = s.C_bn.transpose() * s.v_n;  // Eq. 29
  vx[i] = vb.x();
  vy[i] = vb.y();
  vz[i] = vb.z();
  for (int k = 0; k < 3; ++k) {
    bias[k][i] = s.accel_bias[k];
    bias[3 + k][i] = s.gyro_bias[k];
  }
}

namespace {
// IMU axes to chassis axes: the IMU rotated by the mounting roll, pitch and
// yaw against the chassis, as a body against the navigation frame.
Eigen::Matrix3d mounting_dcm(const InsSlipOptions& o) {
  const Eigen::Vector3d& m = o.imu_mounting;
  return dcm_from_euler(m.x(), m.y(), m.z());
}
}  // namespace

std::size_t InsPassInputs::wheel_index(double t) const {
  return std::min(wheels->nearest_index(t), wheel_rates.time.size() - 1);
}

InsFilterPass::InsFilterPass(const InsPassInputs& inputs, const InsSlipOptions& options, bool aiding)
    : in_(inputs),
      o_(options),
      aiding_(aiding),
      process_(options.noise, options.ins),
      zupt_{options.zupt_sigma},
      zaru_{options.zaru_sigma},
      nhc_{options.nhc_lever_arm, options.nhc_lateral_sigma, options.nhc_vertical_sigma, mounting_dcm(options)},
      wheel_speed_{options.odometry_sigma, options.odometry_gate, mounting_dcm(options)},
      health_(options.health) {}

InsErrorMatrix InsFilterPass::initial_covariance() const {
  const double L0 = in_.frame.latitude;
  InsErrorMatrix P = InsErrorMatrix::Zero();
  P.block<2, 2>(0, 0).diagonal().setConstant(o_.noise.initial_attitude * o_.noise.initial_attitude);
  P(2, 2) = o_.noise.initial_heading * o_.noise.initial_heading;
  P.block<3, 3>(3, 3).diagonal().setConstant(0.01 * 0.01);
  P(6, 6) = std::pow(0.05 / in_.frame.rn, 2);
  P(7, 7) = std::pow(0.05 / (in_.frame.re * std::max(std::cos(L0), 1e-6)), 2);
  P(8, 8) = 0.05 * 0.05;
  P.block<3, 3>(9, 9).diagonal().setConstant(std::pow(o_.noise.initial_accel_bias, 2));
  P.block<3, 3>(12, 12).diagonal().setConstant(std::pow(o_.noise.initial_gyro_bias, 2));
  return P;
}

void InsFilterPass::initialise() {
  const std::size_t n = in_.size();
  s_ = InsState{};
  s_.C_bn = dcm_from_euler(in_.roll0, in_.pitch0, in_.heading0);
  s_.latitude = in_.frame.latitude + in_.north0 / in_.frame.rn;
  s_.longitude = in_.frame.longitude + in_.east0 / (in_.frame.re * std::max(std::cos(in_.frame.latitude), 1e-6));
  s_.height = in_.frame.height;
  const InsErrorMatrix P = initial_covariance();
  P_ = P;
  track_ = InsTrack(n);
  states_.clear();
  epochs_.clear();
  if (o_.smooth) {
    states_.reserve(n);
    states_.push_back(s_);
    epochs_.push_back({0, P, P, InsErrorMatrix::Identity(), InsErrorVector::Zero(), false});
  }
  Phi_acc_.setIdentity();
  c_epoch_.setZero();
  last_update_ = (*in_.time)[0];
  w_sum_.setZero();
  w_count_ = 0;
  track_.record(0, s_, in_.frame);
}

InsTrack InsFilterPass::run(double progress_base, double progress_share) {
  initialise();
  const auto& t = *in_.time;
  const std::size_t n = in_.size();
  for (std::size_t i = 1; i < n; ++i) {
    w_sum_ += in_.rate(i);
    ++w_count_;
    predict(i);
    const bool last = i + 1 == n;
    if (t[i] - last_update_ >= o_.update_interval - 1e-9 || last) update(i);
    if (o_.smooth) states_.push_back(s_);
    track_.record(i, s_, in_.frame);
    track_.valid[i] = health_.invalid_at(t[i]) ? 0.0 : 1.0;
    if (o_.progress && i % 2000 == 0) {
      o_.progress(progress_base + progress_share * static_cast<double>(i) / static_cast<double>(n));
    }
  }
  if (o_.smooth) smooth();
  track_.health = health_.report();
  track_.health.invalid_fraction =
      static_cast<double>(std::count(track_.valid.begin(), track_.valid.end(), 0.0)) / static_cast<double>(n);
  return std::move(track_);
}

void InsFilterPass::predict(std::size_t i) {
  const auto& t = *in_.time;
  const double dt = t[i] - t[i - 1];
  const Eigen::Vector3d f = in_.force(i - 1) - s_.accel_bias;
  const Eigen::Vector3d w = in_.rate(i - 1) - s_.gyro_bias;
  const InsErrorMatrix F = process_.system_matrix(s_, f);
  mechanize(s_, f, w, dt, o_.ins);
  const InsErrorMatrix Phi = InsErrorProcess::transition(F, dt);
  InsErrorMatrix Q = process_.noise_covariance(dt);
  if (in_.screened != nullptr && in_.screened->bridged[i - 1] != 0) {
    // Eq. 14's Q (seed 002) plus a bridged input's error, the largest axis's, on attitude and velocity.
    double rate = 0, force = 0;
    for (int c = 0; c < 3; ++c) {
      rate = std::max(rate, in_.screened->added_variance(i - 1, c));
      force = std::max(force, in_.screened->added_variance(i - 1, 3 + c));
    }
    Q.block<3, 3>(0, 0).diagonal().array() += rate * dt * dt;
    Q.block<3, 3>(3, 3).diagonal().array() += force * dt * dt;
  }
  propagate_covariance(P_, Phi, Q);
  Phi_acc_ = Phi * Phi_acc_;
}

void InsFilterPass::update(std::size_t i) {
  last_update_ = (*in_.time)[i];
  last_update_index_ = i;
  const InsErrorMatrix P_prior = P_;
  c_epoch_.setZero();
  const Eigen::Vector3d w_now = in_.rate(i) - s_.gyro_bias;
  if (health_.stopped()) {  // stopped: prediction only
  } else if (in_.standstill[i]) {
    update_at_rest();
  } else {
    update_moving(i, w_now);
  }
  w_sum_.setZero();
  w_count_ = 0;
  const bool reset = !health_.stopped() && check_health(i);
  if (o_.smooth) epochs_.push_back({i, P_prior, InsErrorMatrix(P_), Phi_acc_, c_epoch_, reset});
  Phi_acc_.setIdentity();
}

void InsFilterPass::update_at_rest() {
  if (o_.zupt) apply(zupt_.at(s_), Gating::watched);
  if (o_.zaru) apply(zaru_.at(s_, w_sum_ / std::max(w_count_, 1)), Gating::watched);
}

void InsFilterPass::update_moving(std::size_t i, const Eigen::Vector3d& w_now) {
  const Eigen::Matrix3d C_nb = s_.C_bn.transpose();  // both updates linearise at the epoch's attitude
  if (o_.nhc) apply(nhc_.at(s_, C_nb, w_now), Gating::nis);
  if (aiding_) {
    const double v_odo = in_.wheel_speed(in_.wheel_index((*in_.time)[i]), o_.rover.wheel_radius);
    apply(wheel_speed_.at(s_, C_nb, v_odo), Gating::own);
  }
}

void InsFilterPass::apply(const InsMeasurement& m, Gating gating) {
  const auto dof = static_cast<int>(m.y.size());
  const double gate = gating == Gating::nis ? health_.gate(dof) : m.gate;
  const UpdateResult u = kalman_update(P_, m.H, m.R, m.y, gate);
  if (gating != Gating::own && (u.ok || u.rejected))
    health_.record((*in_.time)[last_update_index_], u.nis, dof, gating == Gating::nis);
  if (!u.ok) return;
  correct(s_, InsErrorVector(u.correction));
  c_epoch_ += u.correction;
}

// After each update epoch: P finite and positive definite, the nominal
// state finite and within its bounds (tilt, velocity, biases), the
// pseudo-measurements not gated away for long. On divergence the filter is
// reset (reset_state), or stops updating once the resets are used up.
bool InsFilterPass::check_health(std::size_t i) {
  const double t = (*in_.time)[i];
  const Eigen::Vector3d e = euler_from_dcm(s_.C_bn);
  Eigen::Matrix<double, 11, 1> x, bound;
  x << e.x(), e.y(), s_.v_n, s_.accel_bias, s_.gyro_bias;
  bound << o_.max_tilt, o_.max_tilt, Eigen::Vector3d::Constant(o_.max_speed),
      Eigen::Vector3d::Constant(o_.max_accel_bias), Eigen::Vector3d::Constant(o_.max_gyro_bias);
  if (!std::isfinite(s_.latitude + s_.longitude + s_.height)) x(0) = NAN;
  static const std::vector<std::string> names = {"roll",
                                                 "pitch",
                                                 "north velocity",
                                                 "east velocity",
                                                 "down velocity",
                                                 "accelerometer bias x",
                                                 "accelerometer bias y",
                                                 "accelerometer bias z",
                                                 "gyro bias x",
                                                 "gyro bias y",
                                                 "gyro bias z"};
  const std::string why = health_.check(t, P_, x, -bound, bound, names);
  if (why.empty() || !health_.reset(t, why)) return false;
  reset_state(i);
  return true;
}

// The reset: roll and pitch levelled over the next 0.5 s of IMU samples,
// heading and position kept (the last finite ones), velocity along the
// heading from the wheels, biases zero, the initial covariance.
void InsFilterPass::reset_state(std::size_t i) {
  const auto& t = *in_.time;
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  std::size_t k = i;
  for (; k < in_.size() && t[k] - t[i] < 0.5; ++k) f += in_.force(k);
  f /= static_cast<double>(std::max<std::size_t>(k - i, 1));
  const double roll = std::atan2(-f.y(), -f.z()), pitch = std::atan2(f.x(), std::hypot(f.y(), f.z()));
  double yaw = euler_from_dcm(s_.C_bn).z();
  if (!std::isfinite(yaw)) yaw = in_.heading0;
  const double v = in_.wheel_speed(in_.wheel_index(t[i]), o_.rover.wheel_radius);
  InsState r;
  r.C_bn = dcm_from_euler(roll, pitch, yaw);
  r.v_n = r.C_bn * Eigen::Vector3d(std::isfinite(v) ? v : 0.0, 0.0, 0.0);
  const bool position_finite = std::isfinite(s_.latitude + s_.longitude + s_.height);
  r.latitude = position_finite ? s_.latitude : in_.frame.latitude;
  r.longitude = position_finite ? s_.longitude : in_.frame.longitude;
  r.height = position_finite ? s_.height : in_.frame.height;
  s_ = r;
  P_ = initial_covariance();
  c_epoch_.setZero();
}

// Position errors (rad) in metres: the smoother inverts covariances in these units.
InsErrorVector InsFilterPass::error_scale() const {
  InsErrorVector scale = InsErrorVector::Ones();
  scale(6) = in_.frame.rn;
  scale(7) = in_.frame.re * std::max(std::cos(in_.frame.latitude), 1e-6);
  return scale;
}

// Rauch-Tung-Striebel smoother in error-state form: with the filter's error
// reset after each epoch, the smoothed error at epoch j (about its posterior
// nominal state) is e_j = A_j (c_{j+1} + e_{j+1}),
// A_j = P+_j Phi_{j+1}^T (P-_{j+1})^-1, e_last = 0. Position states are
// scaled to metres for the inversion. Returns the scaled errors.
std::vector<InsErrorVector> InsFilterPass::smoothed_epoch_errors() const {
  const InsErrorVector scale = error_scale();
  const auto S = scale.asDiagonal();
  const auto S_inv = scale.cwiseInverse().asDiagonal();
  const std::size_t m = epochs_.size();
  std::vector<InsErrorVector> e(m, InsErrorVector::Zero());  // scaled
  for (std::size_t j = m - 1; j-- > 0;) {
    const Epoch& a = epochs_[j];
    const Epoch& b = epochs_[j + 1];
    if (b.reset) continue;  // e[j] stays 0: nothing is carried back across a reset
    const InsErrorMatrix Pp = S * a.P_post * S, Pm = S * b.P_prior * S;
    const InsErrorMatrix Phi = S * b.Phi * S_inv;
    const Eigen::LDLT<InsErrorMatrix> ldlt(Pm);
    const InsErrorMatrix A = ldlt.solve(Phi * Pp).transpose();  // Pm and Pp symmetric
    e[j] = A * (S * b.correction + e[j + 1]);
  }
  return e;
}

void InsFilterPass::smooth() {
  const std::vector<InsErrorVector> e = smoothed_epoch_errors();
  const InsErrorVector scale = error_scale();
  const auto S = scale.asDiagonal();
  const auto S_inv = scale.cwiseInverse().asDiagonal();
  const auto& t = *in_.time;
  // Between epochs the error moves from e_j to c_{j+1} + e_{j+1} (both
  // about the nominal trajectory the filter propagated); interpolate.
  for (std::size_t j = 0; j + 1 < epochs_.size(); ++j) {
    const Epoch& a = epochs_[j];
    const Epoch& b = epochs_[j + 1];
    const InsErrorVector from = S_inv * e[j];
    const InsErrorVector to = b.reset ? from : InsErrorVector(S_inv * (S * b.correction + e[j + 1]));
    for (std::size_t i = a.index; i < b.index; ++i) {
      const double w = (t[i] - t[a.index]) / (t[b.index] - t[a.index]);
      InsState smoothed = states_[i];
      correct(smoothed, InsErrorVector((1.0 - w) * from + w * to));
      track_.record(i, smoothed, in_.frame);
    }
  }
}

}  // namespace roverlab::estimation

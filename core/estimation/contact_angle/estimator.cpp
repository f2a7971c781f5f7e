#include "core/estimation/contact_angle/estimator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/estimation/contact_angle/streams.h"
#include "core/log/time_checks.h"

namespace roverlab::estimation {

using contact::Inputs;

ContactAngleEstimator::ContactAngleEstimator(const log::Log& log, const kinematics::RoverModel& rover,
                                             const ContactAngleOptions& options)
    : log_(log), m_(rover), o_(options), health_(options.health) {
  if (m_.wheels.size() != 6) throw DataError("rover " + m_.name + ": the estimator expects six wheels");
  if (m_.joints.size() > 16) throw DataError("rover " + m_.name + ": more than 16 joints");
  // The RTS smoother lives here; the two-filter one runs this estimator twice.
  smooth_ = o_.smoother && o_.smoother_method == SmootherMethod::rts;
  if (smooth_ && (o_.filter != FilterKind::ekf || o_.reference_ekf || !o_.reset_cross_covariance))
    throw DataError("the RTS smoother runs over the EKF with the cross-covariance reset only");
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(o_.initial_angle_sigma) || !positive(o_.initial_slip_sigma))
    throw DataError("the initial angle and slip standard deviations must be finite and positive");
  read_channels();
  layout_.na = o_.model == ContactModel::smooth ? 0 : o_.model == ContactModel::contact ? 6 : 12;
  layout_.nq = static_cast<int>(m_.joints.size());
  frame_ = o_.model == ContactModel::smooth    ? kinematics::WheelFrame::drive
           : o_.model == ContactModel::contact ? kinematics::WheelFrame::contact
                                               : kinematics::WheelFrame::side_slip;
  level();
  assemble_process_noise();
  assemble_measurement_noise();
  if (o_.joint_rate_window > 0.0) fuse_joint_rates();
  const double angle_keep = o_.angle_model == AngleModel::damped ? 1.0 : 0.0;  // multiplies -A ts
  process_ = contact::ContactProcessModel(layout_, g_i_, o_.slip_damping, angle_keep * o_.angle_damping);
  measurement_ = contact::WheelMeasurementModel(m_, frame_, layout_);
  R_ukf_ = measurement_.ukf_noise_order(rdiag_).asDiagonal();
  state_bounds();
  initial_state();
}

namespace {
// The strapdown prediction cannot bridge an IMU gap longer than this, s.
constexpr double kMaxImuGap = 1.0;
// Joints and wheels must cover at least this share of the IMU's time span.
constexpr double kMinOverlap = 0.5;
// A sensor channel holding one exact value this long and over this share of the log is flat-lined.
constexpr double kFlatSeconds = 5.0;
constexpr double kFlatFraction = 0.25;
}  // namespace

void ContactAngleEstimator::read_channels() {
  imu_ = &log_.stream("imu");
  joints_ = &log_.stream("joints");
  wheels_ = &log_.stream("wheels");
  if (imu_->size() < 10) throw DataError("stream 'imu' has fewer than 10 samples");
  log::require_no_gap(*imu_, kMaxImuGap);
  log::require_shared_time_base(*imu_, *joints_, kMinOverlap);
  log::require_shared_time_base(*imu_, *wheels_, kMinOverlap);
  const char* imu_names[6] = {"angular_rate_x",   "angular_rate_y",   "angular_rate_z",
                              "specific_force_x", "specific_force_y", "specific_force_z"};
  std::array<const std::vector<double>*, 6> raw{};
  for (int c = 0; c < 6; ++c) raw[static_cast<std::size_t>(c)] = &imu_->channel(imu_names[c]).values;
  // An IMU channel holding one exact value (all zero: a disconnected IMU) is warned about.
  for (const char* c : imu_names) {
    const std::string flat = log::flat_lined(*imu_, c, kFlatFraction, kFlatSeconds);
    if (!flat.empty()) warnings_.push_back(flat);
  }
  // The IMU drives the prediction: outliers and missing samples never enter it.
  imu_screened_ = screen_imu("imu", imu_->time(), raw, o_.imu_screen);
  for (const auto& v : imu_screened_.values) imu_ch_.push_back(&v);
  for (const auto& j : m_.joints) {
    q_ch_.push_back(&joints_->channel(j).values);
    qd_ch_.push_back(&joints_->channel(j + "_rate").values);
  }
  for (const auto& w : m_.wheels) w_ch_.push_back(&wheels_->channel("rate_" + w.name).values);
}

// Mean specific force over the 0.5 s from sample `from`.
Eigen::Vector3d ContactAngleEstimator::mean_force(std::size_t from) const {
  const auto& t = imu_->time();
  const std::size_t n = t.size();
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();
  std::size_t h = from;
  while (h < n && t[h] - t[from] < 0.5) {
    f0 += Eigen::Vector3d((*imu_ch_[3])[h], (*imu_ch_[4])[h], (*imu_ch_[5])[h]);
    ++h;
  }
  return f0 / static_cast<double>(std::max<std::size_t>(h - from, 1));
}

// Homing: attitude by levelling and the gravity vector g^i from the first 0.5 s.
void ContactAngleEstimator::level() {
  const Eigen::Vector3d f0 = mean_force(0);
  pitch0_ = std::atan2(-f0.x(), std::hypot(f0.y(), f0.z()));  // z up: f = R^T (0, 0, g)
  roll0_ = std::atan2(f0.y(), f0.z());
  g_i_ = Eigen::Vector3d(0.0, 0.0, f0.norm());
}

// Process noise per step (section 6.2), then the IMU's n_f and n_w.
void ContactAngleEstimator::assemble_process_noise() {
  const int nx = layout_.nx();
  qdiag_.resize(layout_.np());
  qdiag_.segment(0, 3).setConstant(o_.attitude_variance);
  qdiag_.segment(contact::ContactLayout::kVelocity, 3).setConstant(o_.velocity_variance);
  qdiag_.segment(contact::ContactLayout::kSlip, 6).setConstant(o_.slip_variance);
  if (layout_.na > 0) qdiag_.segment(contact::ContactLayout::kContactAngle, layout_.na).setConstant(o_.angle_variance);
  qdiag_.segment(nx, 3) = m_.noise.accelerometer;
  qdiag_.segment(nx + 3, 3) = m_.noise.gyro;
  Q_ = qdiag_.asDiagonal();
}

// Measurement noise from the rover's sensor description: gyro, wheel rates,
// joint angles and rates (bogies by name, steering per wheel), lateral and
// normal velocity.
void ContactAngleEstimator::assemble_measurement_noise() {
  const int nq = layout_.nq, nw = layout_.nw;
  rdiag_.resize(layout_.nm());
  rdiag_.segment(0, 3) = m_.noise.gyro;
  q_var_.assign(static_cast<std::size_t>(nq), 1e-12);
  qd_var_.assign(static_cast<std::size_t>(nq), 1e-12);
  std::size_t b = 0;
  for (int j = 0; j < nq; ++j) {
    if (m_.joints[static_cast<std::size_t>(j)].rfind("bogie", 0) == 0 && b < m_.noise.bogie_angle.size()) {
      q_var_[static_cast<std::size_t>(j)] = m_.noise.bogie_angle[b];
      qd_var_[static_cast<std::size_t>(j)] = m_.noise.bogie_rate[b];
      ++b;
    }
  }
  for (int w = 0; w < nw; ++w) {
    const int j = m_.wheels[static_cast<std::size_t>(w)].steer_joint;
    if (j >= 0 && !m_.noise.steer_angle.empty()) {
      q_var_[static_cast<std::size_t>(j)] = m_.noise.steer_angle[static_cast<std::size_t>(w)];
      qd_var_[static_cast<std::size_t>(j)] = m_.noise.steer_rate[static_cast<std::size_t>(w)];
    }
  }
  for (int w = 0; w < nw; ++w) {
    rdiag_(3 + w) = m_.noise.wheel_rate.empty() ? 1e-12 : m_.noise.wheel_rate[static_cast<std::size_t>(w)];
  }
  for (int j = 0; j < nq; ++j) {
    rdiag_(3 + nw + j) = q_var_[static_cast<std::size_t>(j)];
    rdiag_(3 + nw + nq + j) = qd_var_[static_cast<std::size_t>(j)];
  }
  rdiag_.segment(3 + nw + 2 * nq, 2 * nw).setConstant(o_.lateral_variance);
}

// Joint rates fused with the slope of the joint angles (offline extension,
// not in the seed): inverse-variance weights, the fused variance into R.
void ContactAngleEstimator::fuse_joint_rates() {
  const int nq = layout_.nq, nw = layout_.nw;
  const auto& tj = joints_->time();
  const std::size_t nj = tj.size();
  const double rate_hz = joints_->mean_rate_hz();
  const auto half = static_cast<std::size_t>(std::max(1.0, 0.5 * o_.joint_rate_window * rate_hz));
  for (int j = 0; j < nq; ++j) {
    const auto& qa = *q_ch_[static_cast<std::size_t>(j)];
    const auto& qr = *qd_ch_[static_cast<std::size_t>(j)];
    // Slope variance of a line through N points spaced dt: 12 var_q / (N (N^2 - 1) dt^2).
    const double N = static_cast<double>(2 * half + 1), dt = 1.0 / rate_hz;
    const double slope_var = 12.0 * q_var_[static_cast<std::size_t>(j)] / (N * (N * N - 1.0) * dt * dt);
    const double mv = qd_var_[static_cast<std::size_t>(j)];
    const double w_slope = mv / (mv + slope_var);
    rdiag_(3 + nw + nq + j) = mv * slope_var / (mv + slope_var);
    std::vector<double> out(nj);
    for (std::size_t i = 0; i < nj; ++i) {
      const std::size_t a = i > half ? i - half : 0, b = std::min(nj - 1, i + half);
      double st = 0, sq = 0, stt = 0, stq = 0;
      const auto m_ = static_cast<double>(b - a + 1);
      for (std::size_t k = a; k <= b; ++k) {
        const double x = tj[k] - tj[i];
        st += x;
        sq += qa[k];
        stt += x * x;
        stq += x * qa[k];
      }
      const double den = m_ * stt - st * st;
      const double slope = den > 0 ? (m_ * stq - st * sq) / den : qr[i];
      out[i] = w_slope * slope + (1.0 - w_slope) * qr[i];
    }
    fused_rate_.push_back(std::move(out));
  }
}

namespace {

// The stream's sample nearest to t, IMU sample i's time: i itself when the
// stream shares the IMU's time base there (as Stream::nearest_index would
// find on its sorted times), else by that binary search.
std::size_t nearest_sample(const log::Stream& s, std::size_t i, double t) {
  const auto& ts = s.time();
  if (i < ts.size() && ts[i] == t && (i + 1 == ts.size() || ts[i + 1] > t)) return i;
  return std::min(s.nearest_index(t), s.size() - 1);
}

}  // namespace

Inputs ContactAngleEstimator::inputs_at(std::size_t i) const {
  const auto& t = imu_->time();
  const int nq = layout_.nq, nw = layout_.nw;
  Inputs in;
  in.gyro = Eigen::Vector3d((*imu_ch_[0])[i], (*imu_ch_[1])[i], (*imu_ch_[2])[i]);
  in.accel = Eigen::Vector3d((*imu_ch_[3])[i], (*imu_ch_[4])[i], (*imu_ch_[5])[i]);
  const std::size_t kj = nearest_sample(*joints_, i, t[i]);
  const std::size_t kw = nearest_sample(*wheels_, i, t[i]);
  for (int j = 0; j < nq; ++j) {
    const auto ju = static_cast<std::size_t>(j);
    in.q[j] = (*q_ch_[ju])[kj];
    in.qdot[j] = fused_rate_.empty() ? (*qd_ch_[ju])[kj] : fused_rate_[ju][kj];
  }
  for (int w = 0; w < nw; ++w) in.wheel_rate[w] = (*w_ch_[static_cast<std::size_t>(w)])[kw];
  return in;
}

// A missing joint or wheel sample: that step is a prediction only.
bool ContactAngleEstimator::measurements_finite(const Inputs& in) const {
  double sum = 0;
  for (int j = 0; j < layout_.nq; ++j) sum += in.q[j] + in.qdot[j];
  for (double w : in.wheel_rate) sum += w;
  return std::isfinite(sum);
}

// Physical bounds: attitude (pitch, roll), body velocity, slips, angles.
void ContactAngleEstimator::state_bounds() {
  const int nx = layout_.nx();
  upper_ = Eigen::VectorXd::Constant(nx, NAN);
  upper_.segment(1, 2).setConstant(o_.max_angle);
  upper_.segment(contact::ContactLayout::kVelocity, 3).setConstant(o_.max_speed);
  upper_.segment(contact::ContactLayout::kSlip, 6).setConstant(o_.max_slip);
  if (layout_.na > 0) upper_.segment(contact::ContactLayout::kContactAngle, layout_.na).setConstant(o_.max_angle);
  lower_ = -upper_;
  state_names_ = {"yaw", "pitch", "roll", "velocity x", "velocity y", "velocity z"};
  for (const char* kind : {"slip ", "contact angle ", "side-slip angle "}) {
    for (const auto& w : m_.wheels) state_names_.push_back(kind + w.name);
  }
  state_names_.resize(static_cast<std::size_t>(nx));
}

// The process noise of the step to sample i: the IMU's n_f and n_w (Eq.
// 4.13-4.14, seed 000) grow by a bridged input's error (ScreenedImu).
const Eigen::VectorXd& ContactAngleEstimator::process_noise(std::size_t i) {
  if (imu_screened_.bridged[i] == 0) return qdiag_;
  const int nx = layout_.nx();
  q_bridged_ = qdiag_;
  for (int c = 0; c < 3; ++c) {
    q_bridged_(nx + c) += imu_screened_.added_variance(i, 3 + c);  // specific force
    q_bridged_(nx + 3 + c) += imu_screened_.added_variance(i, c);  // angular rate
  }
  return q_bridged_;
}

// Initial state: levelled attitude, forward speed from the wheels, no slip,
// flat contact; the filters start from it.
void ContactAngleEstimator::initial_state() {
  const int nx = layout_.nx();
  x0_ = Eigen::VectorXd::Zero(nx);
  x0_(1) = pitch0_;
  x0_(2) = roll0_;
  {
    const Inputs in = inputs_at(0);
    std::vector<double> r(in.wheel_rate, in.wheel_rate + 6);
    std::nth_element(r.begin(), r.begin() + 3, r.end());
    x0_(3) = r[3] * m_.wheel_radius;
  }
  p0_.resize(nx);
  p0_.segment(0, 3).setConstant(1e-4);
  p0_.segment(contact::ContactLayout::kVelocity, 3).setConstant(1e-4);
  p0_.segment(contact::ContactLayout::kSlip, 6).setConstant(o_.initial_slip_sigma * o_.initial_slip_sigma);
  if (layout_.na > 0)
    p0_.segment(contact::ContactLayout::kContactAngle, layout_.na)
        .setConstant(o_.initial_angle_sigma * o_.initial_angle_sigma);
  // The fixed-size UKFs: closed forms along the additive noises (Eq. 4.15-4.17, 4.20), h per wheel reached.
  const Eigen::MatrixXd P0 = p0_.asDiagonal();
  auto init = [&](auto& u) {
    u.set_noises(qdiag_, R_ukf_.diagonal());
    u.filter.diagonal_only = o_.reset_cross_covariance;
    u.filter.x = x0_;
    u.filter.P = P0;
  };
  if (layout_.na == 0) init(ukf0_);
  if (layout_.na == 6) init(ukf6_);
  if (layout_.na == 12) init(ukf12_);
  ekf_.x = ukf_.x = x0_;
  ekf_.P = ukf_.P = Eigen::MatrixXd(p0_.asDiagonal());
  y_meas_ = Eigen::VectorXd::Zero(layout_.ny());
}

// Standstill (sections 4.1 and 5.1): every wheel and the body's rotation slow.
bool ContactAngleEstimator::at_standstill(const Inputs& in) const {
  bool still = true;
  for (double w : in.wheel_rate) still = still && std::abs(w) < o_.standstill_wheel_rate;
  return still && in.gyro.norm() < o_.standstill_gyro_rate;
}

ContactAngleResult ContactAngleEstimator::run() {
  const auto& t = imu_->time();
  const std::size_t n = t.size();
  const int nx = layout_.nx();
  out_.assign(static_cast<std::size_t>(nx), std::vector<double>(n, NAN));
  valid_.assign(n, 0.0);
  diverged_.assign(n, 0.0);
  ContactAngleResult result;
  if (smooth_) {
    const auto nxs = static_cast<std::size_t>(nx);
    sm_xf_.assign(n * nxs, 0.0);
    sm_xp_.assign(n * nxs, 0.0);
    sm_start_.assign(n, 0);
    sm_c_.assign(n * nxs * nxs, 0.0F);
  }
  if (o_.record_variance) result.variance.assign(static_cast<std::size_t>(nx), std::vector<double>(n, NAN));
  std::size_t steps = 0;  // run (fewer than n when the filter stopped)
  for (std::size_t i = 0; i < n && !stopped_; ++i, ++steps) {
    const Inputs in = inputs_at(i);
    const double ts = i == 0 ? 0.0 : t[i] - t[i - 1];
    const bool still = at_standstill(in);
    const bool measured = measurements_finite(in);
    measurements_missing_ += !measured;
    for (int w = 0; w < layout_.nw; ++w) y_meas_(w) = in.wheel_rate[static_cast<std::size_t>(w)];
    filter_step(i, in, ts, !still && measured && imu_screened_.bridged[i] == 0);
    check_health(i);
    for (int k = 0; k < nx; ++k) out_[static_cast<std::size_t>(k)][i] = x_(k);
    if (o_.record_variance) {
      const Eigen::VectorXd p = covariance_diagonal();
      for (int k = 0; k < nx; ++k) result.variance[static_cast<std::size_t>(k)][i] = p(k);
    }
    diverged_[i] = health_.invalid_at(t[i]) ? 1.0 : 0.0;
    valid_[i] = still || diverged_[i] != 0.0 ? 0.0 : 1.0;
    result.standstill_samples += still;
    if (o_.progress && i % 2000 == 0) o_.progress(static_cast<double>(i) / static_cast<double>(n));
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (stopped_ && valid_[i] == 0.0 && std::isnan(out_[0][i])) diverged_[i] = 1.0;
  }
  result.health = health_.report();
  result.health.outliers_rejected = imu_screened_.outliers;
  result.health.missing_samples = imu_screened_.missing;
  result.health.measurements_missing = measurements_missing_;
  result.health.gaps = imu_screened_.gaps;
  result.health.invalid_fraction =
      static_cast<double>(std::count(diverged_.begin(), diverged_.end(), 1.0)) / static_cast<double>(n);
  result.max_cross_correlation = max_cross_correlation();
  result.innovations = innovations_;
  result.warnings = warnings_;
  if (smooth_) {
    write_streams(result.filter_estimates);
    smooth(steps);
    result.smoothed = true;
    result.filter_health = result.health;  // RTS: one pass
  }
  write_streams(result.estimates);
  result.seconds = t.back() - t.front();
  if (o_.progress) o_.progress(1.0);
  return result;
}

void ContactAngleEstimator::filter_step(std::size_t i, const Inputs& in, double ts, bool update) {
  if (o_.filter == FilterKind::ekf && !o_.reference_ekf) {
    if (layout_.na == 0) fast_ekf_step(fast0_, i, in, ts, update);
    if (layout_.na == 6) fast_ekf_step(fast6_, i, in, ts, update);
    if (layout_.na == 12) fast_ekf_step(fast12_, i, in, ts, update);
  } else if (o_.filter == FilterKind::ekf) {
    generic_ekf_step(i, in, ts, update);
  } else {
    ukf_step(i, in, ts, update);
  }
}

// The fast EKF's reference: Jacobians by ceres::Jet, dense algebra.
void ContactAngleEstimator::generic_ekf_step(std::size_t i, const Inputs& in, double ts, bool update) {
  if (i > 0) ekf_.predict_diagonal(process_.linearize(ekf_.x, in, ts), process_noise(i));
  if (update) {
    const auto ny = static_cast<int>(y_meas_.size());
    const UpdateResult u = ekf_.update_diagonal(measurement_.linearize(ekf_.x, in), rdiag_, y_meas_, health_.gate(ny));
    if (u.ok || u.rejected) {
      health_.record(imu_->time()[i], u.nis, ny);
      innovations_.add(u.nis, u.log_det_s, ny);
    }
  }
  if (o_.reset_cross_covariance) ekf_.reset_cross_covariance();
  x_ = ekf_.x;
}

// The reference UKF: the generic augmented filter, every sigma point through f and h.
void ContactAngleEstimator::ukf_step(std::size_t i, const Inputs& in, double ts, bool update) {
  measurement_.set_inputs(in);
  if (!o_.reference_ukf) {
    if (layout_.na == 0) fixed_ukf_step(ukf0_, i, in, ts, update);
    if (layout_.na == 6) fixed_ukf_step(ukf6_, i, in, ts, update);
    if (layout_.na == 12) fixed_ukf_step(ukf12_, i, in, ts, update);
    return;
  }
  // The filter's f and h: this step's inputs bound to the models.
  const auto f = [&](const Eigen::VectorXd& xs, const Eigen::VectorXd& nz, Eigen::VectorXd& out_x) {
    process_.evaluate(xs, nz, in, ts, out_x);
  };
  const auto h = [this](const Eigen::VectorXd& xs, const Eigen::VectorXd& nz, Eigen::VectorXd& out_y) {
    measurement_.evaluate(xs, nz, out_y);
  };
  if (i > 0 && update) {
    const auto ny = static_cast<int>(y_meas_.size());
    ukf_.gate = health_.gate(ny);
    if (ukf_.step(f, Q_, h, R_ukf_, y_meas_)) {
      health_.record(imu_->time()[i], ukf_.nis, ny);
      innovations_.add(ukf_.nis, ukf_.log_det_pyy, ny);
    }
  } else if (i > 0) {  // predict only: the state's mean through f with zero noise
    Eigen::VectorXd next;
    f(ukf_.x, Eigen::VectorXd::Zero(layout_.np()), next);
    ukf_.x = next;
  }
  if (o_.reset_cross_covariance) ukf_.reset_cross_covariance();
  x_ = ukf_.x;
}

// After each step: P finite and positive definite, the state finite and
// within its bounds, the updates not gated away for long. On divergence the
// filter is reset (or stops once the resets are used up).
void ContactAngleEstimator::check_health(std::size_t i) {
  const double t = imu_->time()[i];
  // P where it lives (no copy at every step).
  const bool fast = o_.filter == FilterKind::ekf && !o_.reference_ekf;
  const auto check = [&](const Eigen::Ref<const Eigen::MatrixXd>& P) {
    return health_.check(t, P, x_, lower_, upper_, state_names_);
  };
  const std::string why =
      fast_ukf() ? (layout_.na == 0   ? check(ukf0_.filter.P)
                    : layout_.na == 6 ? check(ukf6_.filter.P)
                                      : check(ukf12_.filter.P))
      : !fast    ? health_.check(t, o_.filter == FilterKind::ekf ? ekf_.P : ukf_.P, x_, lower_, upper_, state_names_)
      : layout_.na == 0 ? health_.check(t, fast0_.P, x_, lower_, upper_, state_names_)
      : layout_.na == 6 ? health_.check(t, fast6_.P, x_, lower_, upper_, state_names_)
                        : health_.check(t, fast12_.P, x_, lower_, upper_, state_names_);
  if (why.empty()) return;
  if (!health_.reset(t, why)) {
    stopped_ = true;
    x_.setConstant(NAN);
    return;
  }
  reset_filter(i);
}

// The reset: as at the start (initial_state) from sample i: attitude levelled
// over the next 0.5 s (yaw kept), forward speed from the wheels, no slip, flat
// contact, the initial covariance.
void ContactAngleEstimator::reset_filter(std::size_t i) {
  Eigen::VectorXd x = x0_;
  const Eigen::Vector3d f = mean_force(i);
  x(0) = std::isfinite(x_(0)) ? x_(0) : 0.0;
  x(1) = std::atan2(-f.x(), std::hypot(f.y(), f.z()));
  x(2) = std::atan2(f.y(), f.z());
  const Inputs in = inputs_at(i);
  std::vector<double> r(in.wheel_rate, in.wheel_rate + 6);
  std::nth_element(r.begin(), r.begin() + 3, r.end());
  x(3) = std::isfinite(r[3]) ? r[3] * m_.wheel_radius : 0.0;
  const Eigen::MatrixXd P = p0_.asDiagonal();
  if (layout_.na == 0) fast0_.x = x, fast0_.P = P;
  if (layout_.na == 6) fast6_.x = x, fast6_.P = P;
  if (layout_.na == 12) fast12_.x = x, fast12_.P = P;
  ekf_.x = ukf_.x = x;
  ekf_.P = ukf_.P = P;
  if (layout_.na == 0) ukf0_.filter.x = x, ukf0_.filter.P = P;
  if (layout_.na == 6) ukf6_.filter.x = x, ukf6_.filter.P = P;
  if (layout_.na == 12) ukf12_.filter.x = x, ukf12_.filter.P = P;
  x_ = x;
  if (smooth_) {
    record_filtered(i, x.data(), true);
    full0_.P = P;
    full6_.P = P;
    full12_.P = P;
  }  // a new segment: no smoothing across the reset
}

void ContactAngleEstimator::record_prediction(std::size_t i, const double* x) {
  const auto nx = static_cast<std::size_t>(layout_.nx());
  std::copy(x, x + nx, sm_xp_.begin() + static_cast<std::ptrdiff_t>(i * nx));
}

void ContactAngleEstimator::record_filtered(std::size_t i, const double* x, bool segment_start) {
  const auto nx = static_cast<std::size_t>(layout_.nx());
  std::copy(x, x + nx, sm_xf_.begin() + static_cast<std::ptrdiff_t>(i * nx));
  if (segment_start) sm_start_[i] = 1;
}

// The Rauch-Tung-Striebel backward pass, x_k|N = x_k|k + C_k (x_k+1|N - x_k+1|k)
// (Rauch, Tung and Striebel 1965) over the ND filter's states, with the
// companion's gains C_k (the reset's diagonal P gives a lone random walk's
// gains, a 0.2 s memory against the filter's 3 s lag: docs/validation).
void ContactAngleEstimator::smooth(std::size_t steps) {
  const int nx = layout_.nx();
  const auto nxs = static_cast<std::size_t>(nx);
  const std::size_t n = steps;
  if (n == 0) return;
  std::vector<double> xs = sm_xf_;
  for (std::size_t k = n - 1; k-- > 0;) {
    const std::size_t k1 = k + 1;
    if (sm_start_[k1] != 0) continue;  // the end of a segment keeps its filtered state
    const Eigen::Map<const Eigen::VectorXd> xf(&sm_xf_[k * nxs], nx), xp(&sm_xp_[k1 * nxs], nx);
    const Eigen::Map<const Eigen::VectorXd> next(&xs[k1 * nxs], nx);
    Eigen::Map<Eigen::VectorXd> out(&xs[k * nxs], nx);
    const Eigen::Map<const Eigen::MatrixXf> C(&sm_c_[k * nxs * nxs], nx, nx);
    out = xf + C.cast<double>() * (next - xp);
  }
  for (std::size_t k = 0; k < nxs; ++k) {
    for (std::size_t i = 0; i < n; ++i) {
      if (std::isfinite(out_[k][i])) out_[k][i] = xs[i * nxs + k];
    }
  }
}

Eigen::MatrixXd ContactAngleEstimator::covariance() const {
  if (o_.filter == FilterKind::ekf && !o_.reference_ekf) {
    return layout_.na == 0   ? Eigen::MatrixXd(fast0_.P)
           : layout_.na == 6 ? Eigen::MatrixXd(fast6_.P)
                             : Eigen::MatrixXd(fast12_.P);
  }
  if (fast_ukf()) {
    return layout_.na == 0   ? Eigen::MatrixXd(ukf0_.filter.P)
           : layout_.na == 6 ? Eigen::MatrixXd(ukf6_.filter.P)
                             : Eigen::MatrixXd(ukf12_.filter.P);
  }
  return o_.filter == FilterKind::ekf ? ekf_.P : ukf_.P;
}

Eigen::VectorXd ContactAngleEstimator::covariance_diagonal() const {
  if (o_.filter == FilterKind::ekf && !o_.reference_ekf) {
    return layout_.na == 0   ? Eigen::VectorXd(fast0_.P.diagonal())
           : layout_.na == 6 ? Eigen::VectorXd(fast6_.P.diagonal())
                             : Eigen::VectorXd(fast12_.P.diagonal());
  }
  if (fast_ukf()) {
    return layout_.na == 0   ? Eigen::VectorXd(ukf0_.filter.P.diagonal())
           : layout_.na == 6 ? Eigen::VectorXd(ukf6_.filter.P.diagonal())
                             : Eigen::VectorXd(ukf12_.filter.P.diagonal());
  }
  return o_.filter == FilterKind::ekf ? Eigen::VectorXd(ekf_.P.diagonal()) : Eigen::VectorXd(ukf_.P.diagonal());
}

// Largest |P_ij| / sqrt(P_ii P_jj), i != j, at the end.
double ContactAngleEstimator::max_cross_correlation() const {
  const Eigen::MatrixXd P = covariance();
  double largest = 0;
  for (int a = 0; a < layout_.nx(); ++a) {
    for (int b = 0; b < a; ++b) {
      const double r = std::abs(P(a, b)) / std::sqrt(P(a, a) * P(b, b));
      if (std::isfinite(r)) largest = std::max(largest, r);
    }
  }
  return largest;
}

namespace {

std::vector<double> masked(const std::vector<double>& v, const std::vector<double>& valid) {
  std::vector<double> r = v;
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (valid[i] == 0.0) r[i] = NAN;
  }
  return r;
}

}  // namespace

std::vector<StateChannel> state_channels(const kinematics::RoverModel& m, int angle_states) {
  const char* body = contact_streams::kBody;
  const char* wheels = contact_streams::kWheels;
  std::vector<StateChannel> out = {{body, "velocity_x", "m/s", 3}, {body, "velocity_y", "m/s", 4},
                                   {body, "velocity_z", "m/s", 5}, {body, "yaw", "rad", 0},
                                   {body, "pitch", "rad", 1},      {body, "roll", "rad", 2}};
  const int nw = static_cast<int>(m.wheels.size());
  const auto add = [&](const char* prefix, const char* unit, int first) {
    for (int w = 0; w < nw; ++w)
      out.push_back({wheels, prefix + m.wheels[static_cast<std::size_t>(w)].name, unit, first + w});
  };
  add("slip_", "1", 6);
  if (angle_states >= 6) add("contact_angle_", "rad", 12);
  if (angle_states >= 12) add("side_slip_", "rad", 18);
  return out;
}

// Streams; slip and angles are invalid (NaN) at standstill, every state where the filter diverged.
void ContactAngleEstimator::write_streams(log::Log& estimates) const {
  const auto& t = imu_->time();
  estimates.metadata = log_.metadata;
  estimates.metadata.extra["estimator"] = "contact-angle (seed 000)";
  log::Stream body(contact_streams::kBody, t);
  log::Stream s(contact_streams::kWheels, t);
  std::vector<double> trusted(diverged_.size());  // the body states are invalid only where the filter diverged
  for (std::size_t i = 0; i < trusted.size(); ++i) trusted[i] = 1.0 - diverged_[i];
  for (const StateChannel& c : state_channels(m_, layout_.na)) {
    const auto& values = out_[static_cast<std::size_t>(c.state)];
    if (c.stream == body.name()) {
      body.add_channel(c.name, c.unit, masked(values, trusted), c.state == 3 ? "body frame g" : "");
    } else {
      s.add_channel(c.name, c.unit, masked(values, valid_));
    }
  }
  estimates.add_stream(std::move(body));
  s.add_channel("valid", "bool", valid_,
                "0 at standstill (slip and angles undefined, held) and where the filter diverged");
  s.add_channel("bridged", "bool", std::vector<double>(imu_screened_.bridged.begin(), imu_screened_.bridged.end()),
                "1 where the IMU sample was rejected or missing: prediction from the last usable one");
  estimates.add_stream(std::move(s));
}

}  // namespace roverlab::estimation

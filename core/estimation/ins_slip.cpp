#include "core/estimation/ins_slip.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/estimation/kalman.h"
#include "core/estimation/reference_track.h"

namespace roverlab::estimation {

namespace {

using Vec15 = Eigen::Matrix<double, 15, 1>;
using Mat15 = Eigen::Matrix<double, 15, 15>;

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

const std::vector<double>& values(const log::Stream& s, const char* name) { return s.channel(name).values; }

// Centred moving standard deviation over +-half samples.
std::vector<double> moving_std(const std::vector<double>& x, std::size_t half) {
  const std::size_t n = x.size();
  std::vector<double> s1(n + 1, 0.0), s2(n + 1, 0.0), out(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    s1[i + 1] = s1[i] + x[i];
    s2[i + 1] = s2[i] + x[i] * x[i];
  }
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i > half ? i - half : 0, b = std::min(n, i + half + 1);
    const double m = static_cast<double>(b - a);
    const double mean = (s1[b] - s1[a]) / m;
    out[i] = std::sqrt(std::max(0.0, (s2[b] - s2[a]) / m - mean * mean));
  }
  return out;
}

// Filter outputs at the IMU samples.
struct Track {
  explicit Track(std::size_t n)
      : roll(n), pitch(n), yaw(n), east(n), north(n), up(n), vn(n), ve(n), vd(n), vx(n), vy(n), vz(n),
        bias(6, std::vector<double>(n)) {}
  std::vector<double> roll, pitch, yaw, east, north, up, vn, ve, vd, vx, vy, vz;
  std::vector<std::vector<double>> bias;  // accel x y z, gyro x y z
};

struct Epoch {
  std::size_t index;  // IMU sample
  Mat15 P_prior, P_post, Phi;  // Phi: transition from the previous epoch
  Vec15 correction;            // error correction applied at this epoch
};

}  // namespace

InsSlipResult run_ins_slip(const log::Log& lg, const InsSlipOptions& o, const InsSlipChannels& names) {
  const log::Stream& imu = lg.stream(names.imu);
  const log::Stream& wheels = lg.stream(names.wheels);
  if (imu.size() < 10) throw DataError("stream '" + names.imu + "' has fewer than 10 samples");
  if (wheels.size() < 3) throw DataError("stream '" + names.wheels + "' has fewer than 3 samples");
  const auto& fx = values(imu, "specific_force_x");
  const auto& fy = values(imu, "specific_force_y");
  const auto& fz = values(imu, "specific_force_z");
  const auto& wx = values(imu, "angular_rate_x");
  const auto& wy = values(imu, "angular_rate_y");
  const auto& wz = values(imu, "angular_rate_z");
  const WheelSamples wr = wheel_rates(wheels.time(), values(wheels, "angle_FL"), values(wheels, "angle_FR"),
                                      values(wheels, "angle_RL"), values(wheels, "angle_RR"));
  const ReferenceTrack ref = reference_from_gps(lg, names.gps);
  const auto& t = imu.time();
  const std::size_t n = t.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(fx[i] + fy[i] + fz[i] + wx[i] + wy[i] + wz[i])) {
      throw DataError("stream '" + names.imu + "': missing IMU sample at t = " + std::to_string(t[i]) + " s");
    }
  }

  // Standstill: quiet IMU and wheels that do not turn.
  std::vector<double> fnorm(n), wnorm(n);
  for (std::size_t i = 0; i < n; ++i) {
    fnorm[i] = std::sqrt(fx[i] * fx[i] + fy[i] * fy[i] + fz[i] * fz[i]);
    wnorm[i] = std::sqrt(wx[i] * wx[i] + wy[i] * wy[i] + wz[i] * wz[i]);
  }
  const double rate = imu.mean_rate_hz();
  const auto half = static_cast<std::size_t>(std::max(1.0, 0.5 * o.standstill.window * rate));
  const auto fstd = moving_std(fnorm, half), wstd = moving_std(wnorm, half);
  std::vector<char> standstill(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = std::min(wheels.nearest_index(t[i]), wr.time.size() - 1);
    bool wheels_still = true;
    for (std::size_t j = (k > 0 ? k - 1 : 0); j <= std::min(k + 1, wr.time.size() - 1); ++j) {
      wheels_still = wheels_still && std::abs(wr.left_rate[j]) <= o.standstill.wheel_rate_max &&
                     std::abs(wr.right_rate[j]) <= o.standstill.wheel_rate_max;
    }
    standstill[i] = wheels_still && fstd[i] <= o.standstill.accel_std_max && wstd[i] <= o.standstill.gyro_std_max;
  }

  // Initial attitude: levelling on the first 5 s at rest (or the first 0.5 s).
  std::size_t level_end = 0;
  while (level_end < n && standstill[level_end] && t[level_end] - t[0] < 5.0) ++level_end;
  if (level_end < static_cast<std::size_t>(0.5 * rate)) level_end = std::min(n, static_cast<std::size_t>(0.5 * rate) + 1);
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < level_end; ++i) f0 += Eigen::Vector3d(fx[i], fy[i], fz[i]);
  f0 /= static_cast<double>(level_end);
  const double roll0 = std::atan2(-f0.y(), -f0.z());
  const double pitch0 = std::atan2(f0.x(), std::hypot(f0.y(), f0.z()));
  double heading0 = 0.0;
  if (o.initial_heading) {
    heading0 = *o.initial_heading;
  } else if (ref.present) {
    heading0 = initial_course(ref, o.heading_distance);
    if (!std::isfinite(heading0)) heading0 = 0.0;
  }

  const double L0 = ref.latitude, lon0 = ref.longitude, h0 = ref.height;
  const double rn0 = meridian_radius(L0) + h0, re0 = transverse_radius(L0) + h0;
  // One filter pass; `aiding` adds the wheels' forward speed as an update.
  auto run_filter = [&](bool aiding, double progress_base, double progress_share) {
    InsState s;
    s.C_bn = dcm_from_euler(roll0, pitch0, heading0);
    s.latitude = ref.latitude;
    s.longitude = ref.longitude;
    s.height = ref.height;

    Mat15 P = Mat15::Zero();
    P.block<2, 2>(0, 0).diagonal().setConstant(o.noise.initial_attitude * o.noise.initial_attitude);
    P(2, 2) = o.noise.initial_heading * o.noise.initial_heading;
    P.block<3, 3>(3, 3).diagonal().setConstant(0.01 * 0.01);
    P(6, 6) = std::pow(0.05 / rn0, 2);
    P(7, 7) = std::pow(0.05 / (re0 * std::max(std::cos(L0), 1e-6)), 2);
    P(8, 8) = 0.05 * 0.05;
    P.block<3, 3>(9, 9).diagonal().setConstant(std::pow(o.noise.initial_accel_bias, 2));
    P.block<3, 3>(12, 12).diagonal().setConstant(std::pow(o.noise.initial_gyro_bias, 2));
    Eigen::MatrixXd Pd = P;

    // Outputs at IMU rate.
    Track tr(n);
    auto record = [&](std::size_t i, const InsState& s) {
      const Eigen::Vector3d e = euler_from_dcm(s.C_bn);
      tr.roll[i] = e.x();
      tr.pitch[i] = e.y();
      tr.yaw[i] = e.z();
      tr.north[i] = (s.latitude - L0) * rn0;
      tr.east[i] = (s.longitude - lon0) * re0 * std::cos(L0);
      tr.up[i] = s.height - h0;
      tr.vn[i] = s.v_n.x();
      tr.ve[i] = s.v_n.y();
      tr.vd[i] = s.v_n.z();
      const Eigen::Vector3d vb = s.C_bn.transpose() * s.v_n;  // Eq. 29
      tr.vx[i] = vb.x();
      tr.vy[i] = vb.y();
      tr.vz[i] = vb.z();
      for (int k = 0; k < 3; ++k) {
        tr.bias[k][i] = s.accel_bias[k];
        tr.bias[3 + k][i] = s.gyro_bias[k];
      }
    };
    // For the smoother: the nominal state at every IMU sample, and at every
    // update epoch the prior and posterior covariance, the transition from
    // the previous epoch and the error correction applied.
    std::vector<InsState> states;
    if (o.smooth) states.reserve(n);
    std::vector<Epoch> epochs;
    Mat15 Phi_acc = Mat15::Identity();
    Vec15 c_epoch = Vec15::Zero();
    if (o.smooth) {
      states.push_back(s);
      epochs.push_back({0, P, P, Mat15::Identity(), Vec15::Zero()});
    }
    record(0, s);

    auto apply = [&](const Eigen::MatrixXd& H, const Eigen::MatrixXd& R, const Eigen::VectorXd& y,
                     double gate = HUGE_VAL) {
      const UpdateResult u = kalman_update(Pd, H, R, y, gate);
      if (!u.ok) return;
      correct(s, Vec15(u.correction));
      c_epoch += u.correction;
    };

    double last_update = t[0];
    Eigen::Vector3d w_sum = Eigen::Vector3d::Zero();  // raw rates since the last update (ZARU uses their mean)
    int w_count = 0;
    for (std::size_t i = 1; i < n; ++i) {
      w_sum += Eigen::Vector3d(wx[i], wy[i], wz[i]);
      ++w_count;
      const double dt = t[i] - t[i - 1];
      const Eigen::Vector3d f = Eigen::Vector3d(fx[i - 1], fy[i - 1], fz[i - 1]) - s.accel_bias;
      const Eigen::Vector3d w = Eigen::Vector3d(wx[i - 1], wy[i - 1], wz[i - 1]) - s.gyro_bias;
      const Mat15 F = error_system_matrix(s, f, o.ins);
      mechanize(s, f, w, dt, o.ins);
      // Eq. 11 (first-order transition) and a first-order Q (Eq. 14's diagonal terms).
      const Mat15 Phi = Mat15::Identity() + F * dt;
      Mat15 Q = Mat15::Zero();
      Q.block<3, 3>(0, 0).diagonal().setConstant(o.noise.gyro_arw * o.noise.gyro_arw * dt);
      Q.block<3, 3>(3, 3).diagonal().setConstant(o.noise.accel_vrw * o.noise.accel_vrw * dt);
      Q.block<3, 3>(9, 9).diagonal().setConstant(o.noise.accel_bias_walk * o.noise.accel_bias_walk * dt);
      Q.block<3, 3>(12, 12).diagonal().setConstant(o.noise.gyro_bias_walk * o.noise.gyro_bias_walk * dt);
      propagate_covariance(Pd, Phi, Q);
      Phi_acc = Phi * Phi_acc;

      const bool last = i + 1 == n;
      if (t[i] - last_update >= o.update_interval - 1e-9 || last) {
        last_update = t[i];
        const Mat15 P_prior = Pd;
        c_epoch.setZero();
        const Eigen::Vector3d w_now = Eigen::Vector3d(wx[i], wy[i], wz[i]) - s.gyro_bias;
        if (standstill[i]) {
          if (o.zupt) {  // Eq. 17-18: the velocity is zero
            Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, 15);
            H.block<3, 3>(0, 3).setIdentity();
            apply(H, Eigen::MatrixXd::Identity(3, 3) * o.zupt_sigma * o.zupt_sigma, -s.v_n);
          }
          if (o.zaru) {  // Eq. 19-20: the angular rate is zero
            Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, 15);
            H.block<3, 3>(0, 12) = -Eigen::Matrix3d::Identity();
            const Eigen::Vector3d w_meas = w_sum / std::max(w_count, 1) - s.gyro_bias;
            apply(H, Eigen::MatrixXd::Identity(3, 3) * o.zaru_sigma * o.zaru_sigma, -w_meas);
          }
        } else {
          const Eigen::Matrix3d Cnb = s.C_bn.transpose();
          if (o.nhc) {  // Eq. 21-23: no lateral or vertical velocity at the wheels
            const Eigen::Vector3d v_wheel = Cnb * s.v_n - skew(w_now) * o.nhc_lever_arm;
            Eigen::MatrixXd H = Eigen::MatrixXd::Zero(2, 15);
            H.block<2, 3>(0, 0) = (Cnb * skew(s.v_n)).bottomRows<2>();  // attitude term, dropped in Eq. 22
            H.block<2, 3>(0, 3) = Cnb.bottomRows<2>();
            Eigen::MatrixXd R = Eigen::MatrixXd::Zero(2, 2);
            R(0, 0) = o.nhc_lateral_sigma * o.nhc_lateral_sigma;
            R(1, 1) = o.nhc_vertical_sigma * o.nhc_vertical_sigma;
            apply(H, R, -v_wheel.tail<2>());
          }
          if (aiding) {  // forward speed from the wheels
            const std::size_t k = std::min(wheels.nearest_index(t[i]), wr.time.size() - 1);
            const double v_odo = o.rover.wheel_radius * 0.5 * (wr.left_rate[k] + wr.right_rate[k]);
            Eigen::MatrixXd H = Eigen::MatrixXd::Zero(1, 15);
            H.block<1, 3>(0, 0) = (Cnb * skew(s.v_n)).topRows<1>();
            H.block<1, 3>(0, 3) = Cnb.topRows<1>();
            Eigen::VectorXd y(1);
            y(0) = v_odo - (Cnb * s.v_n).x();
            apply(H, Eigen::MatrixXd::Identity(1, 1) * o.odometry_sigma * o.odometry_sigma, y, o.odometry_gate);
          }
        }
        w_sum.setZero();
        w_count = 0;
        if (o.smooth) epochs.push_back({i, P_prior, Mat15(Pd), Phi_acc, c_epoch});
        Phi_acc.setIdentity();
      }
      if (o.smooth) states.push_back(s);
      record(i, s);
      if (o.progress && i % 2000 == 0) o.progress(progress_base + progress_share * static_cast<double>(i) / static_cast<double>(n));
    }
    if (o.smooth) {
      // Rauch-Tung-Striebel smoother in error-state form: with the filter's
      // error reset after each epoch, the smoothed error at epoch j (about
      // its posterior nominal state) is e_j = A_j (c_{j+1} + e_{j+1}),
      // A_j = P+_j Phi_{j+1}^T (P-_{j+1})^-1, e_last = 0. Position states are
      // scaled to metres for the inversion.
      Vec15 scale = Vec15::Ones();
      scale(6) = rn0;
      scale(7) = re0 * std::max(std::cos(L0), 1e-6);
      const auto S = scale.asDiagonal();
      const auto S_inv = scale.cwiseInverse().asDiagonal();
      const std::size_t m = epochs.size();
      std::vector<Vec15> e(m, Vec15::Zero());  // scaled
      for (std::size_t j = m - 1; j-- > 0;) {
        const Epoch& a = epochs[j];
        const Epoch& b = epochs[j + 1];
        const Mat15 Pp = S * a.P_post * S, Pm = S * b.P_prior * S;
        const Mat15 Phi = S * b.Phi * S_inv;
        const Eigen::LDLT<Mat15> ldlt(Pm);
        const Mat15 A = ldlt.solve(Phi * Pp).transpose();  // Pm and Pp symmetric
        e[j] = A * (S * b.correction + e[j + 1]);
      }
      // Between epochs the error moves from e_j to c_{j+1} + e_{j+1} (both
      // about the nominal trajectory the filter propagated); interpolate.
      for (std::size_t j = 0; j + 1 < m; ++j) {
        const Epoch& a = epochs[j];
        const Epoch& b = epochs[j + 1];
        const Vec15 from = S_inv * e[j], to = S_inv * (S * b.correction + e[j + 1]);
        for (std::size_t i = a.index; i < b.index; ++i) {
          const double w = (t[i] - t[a.index]) / (t[b.index] - t[a.index]);
          InsState smoothed = states[i];
          correct(smoothed, Vec15((1.0 - w) * from + w * to));
          record(i, smoothed);
        }
      }
    }
    return tr;
  };
  // The localisation filter (with wheel-speed aiding if asked), and the slip
  // detector: a filter that never sees the wheel speed it is judged against.
  const double share = o.odometry_aiding ? 0.5 : 1.0;
  const Track track = run_filter(o.odometry_aiding, 0.0, share);
  const Track detector_track = o.odometry_aiding ? run_filter(false, 0.5, 0.5) : Track(0);
  const Track& detector = o.odometry_aiding ? detector_track : track;
  std::vector<double> still(n);
  for (std::size_t i = 0; i < n; ++i) still[i] = standstill[i] ? 1.0 : 0.0;

  InsSlipResult result;
  result.estimates.metadata = lg.metadata;
  result.estimates.metadata.extra["estimator"] = "ins-slip (seed 002)";
  {
    log::Stream pose("estimate/ins/pose", t);
    pose.add_channel("roll", "rad", track.roll);
    pose.add_channel("pitch", "rad", track.pitch);
    pose.add_channel("yaw", "rad", track.yaw, "heading, clockwise from north");
    pose.add_channel("east", "m", track.east, "from the initial position");
    pose.add_channel("north", "m", track.north);
    pose.add_channel("up", "m", track.up);
    result.estimates.add_stream(std::move(pose));
    log::Stream vel("estimate/ins/velocity", t);
    vel.add_channel("north", "m/s", track.vn);
    vel.add_channel("east", "m/s", track.ve);
    vel.add_channel("down", "m/s", track.vd);
    vel.add_channel("forward", "m/s", track.vx, "body x (Eq. 29)");
    vel.add_channel("lateral", "m/s", track.vy, "body y");
    vel.add_channel("vertical", "m/s", track.vz, "body z (down)");
    result.estimates.add_stream(std::move(vel));
    log::Stream b("estimate/ins/bias", t);
    const char* names_b[6] = {"accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"};
    for (int k = 0; k < 6; ++k) b.add_channel(names_b[k], k < 3 ? "m/s^2" : "rad/s", track.bias[static_cast<std::size_t>(k)]);
    result.estimates.add_stream(std::move(b));
    log::Stream st("estimate/ins/standstill", t);
    st.add_channel("standstill", "bool", still, "1 where ZUPT/ZARU applied");
    result.estimates.add_stream(std::move(st));
  }

  // Slip at the wheel samples within the IMU span (Eq. 1 with Eq. 29; Eq. 30 against GPS).
  const log::Stream* truth_slip = lg.find_stream(names.truth_slip);
  if (truth_slip != nullptr && truth_slip->find_channel("slip_ratio") == nullptr) truth_slip = nullptr;
  std::vector<double> st_, s_est, c_est, s_ref, c_ref, wspeed, vfwd, vref;
  ConfusionMatrix confusion;
  for (std::size_t k = 0; k < wr.time.size(); ++k) {
    const double tk = wr.time[k];
    if (tk < t.front() || tk > t.back()) continue;
    const double wheel_speed = o.rover.wheel_radius * 0.5 * (wr.left_rate[k] + wr.right_rate[k]);
    const double v = log::interpolate_linear(t, detector.vx, tk);
    // At standstill slip is 0 (Eq. 1's third case). Between standstill and
    // min_slip_speed the ratio is ill-conditioned: reported as NaN and left
    // out of the confusion matrix.
    const bool slow_wheels = std::abs(wheel_speed) < o.min_slip_speed;
    const bool at_rest = standstill[std::min(imu.nearest_index(tk), n - 1)] != 0;
    const bool undefined = !at_rest && slow_wheels && std::abs(v) < o.min_slip_speed;
    const double s_e = at_rest ? 0.0 : undefined ? NAN : slip_ratio(v, wheel_speed);
    st_.push_back(tk);
    s_est.push_back(s_e);
    c_est.push_back(undefined ? NAN : static_cast<double>(classify_slip(s_e, o.no_slip)));
    wspeed.push_back(wheel_speed);
    vfwd.push_back(v);
    if (truth_slip != nullptr) {
      const std::size_t j = truth_slip->nearest_index(tk);
      const double s_r = truth_slip->channel("slip_ratio").values[j];
      s_ref.push_back(s_r);
      c_ref.push_back(static_cast<double>(classify_slip(s_r, o.no_slip)));
      vref.push_back(NAN);
      if (!undefined) confusion.add(classify_slip(s_e, o.no_slip), classify_slip(s_r, o.no_slip));
    } else if (ref.present) {
      const double psi = log::interpolate_linear(t, detector.yaw, tk);
      const double v_r = log::interpolate_linear(ref.time, ref.v_east, tk) * std::sin(psi) +
                         log::interpolate_linear(ref.time, ref.v_north, tk) * std::cos(psi);
      const double s_r = (slow_wheels && std::abs(v_r) < o.min_slip_speed) ? 0.0 : slip_ratio(v_r, wheel_speed);
      s_ref.push_back(s_r);
      c_ref.push_back(static_cast<double>(classify_slip(s_r, o.no_slip)));
      vref.push_back(v_r);
      if (std::isfinite(v_r) && !undefined) confusion.add(classify_slip(s_e, o.no_slip), classify_slip(s_r, o.no_slip));
    }
  }
  {
    log::Stream slip("estimate/ins/slip", st_);
    slip.add_channel("slip_ratio", "1", s_est, "Eq. 1: INS forward speed against wheel speed (NaN: too slow to tell)");
    slip.add_channel("slip_class", "1", c_est, "0 none, 1 low, 2 medium, 3 high, 4 extreme");
    slip.add_channel("wheel_speed", "m/s", wspeed, "r omega, mean of the four wheels");
    slip.add_channel("forward_speed", "m/s", vfwd, "INS body forward speed");
    if (truth_slip != nullptr || ref.present) {
      slip.add_channel("reference_speed", "m/s", vref, "GPS velocity along the INS heading (NaN: truth used)");
      slip.add_channel("reference_slip", "1", s_ref, truth_slip ? "truth" : "Eq. 30, from GPS");
      slip.add_channel("reference_class", "1", c_ref);
    }
    result.estimates.add_stream(std::move(slip));
  }

  // Plain wheel odometry from the same initial pose.
  const OdometryTrack odo = dead_reckon(wr, o.rover, OdometryCorrections{}, 0.0, 0.0, heading0);
  {
    log::Stream p("estimate/odometry/pose", odo.time);
    p.add_channel("east", "m", odo.east);
    p.add_channel("north", "m", odo.north);
    p.add_channel("heading", "rad", odo.heading, "clockwise from north, from the wheel rate difference");
    p.add_channel("forward_speed", "m/s", odo.forward_speed);
    result.estimates.add_stream(std::move(p));
  }

  // Metrics against GPS.
  InsSlipMetrics& m = result.metrics;
  m.duration = t.back() - t.front();
  m.standstill_fraction = std::count(standstill.begin(), standstill.end(), 1) / static_cast<double>(n);
  m.confusion = confusion;
  if (ref.present) {
    m.has_reference = true;
    double se = 0, sn = 0, su = 0, sv = 0, so = 0;
    std::size_t count = 0;
    for (std::size_t g = 0; g < ref.time.size(); ++g) {
      const double tg = ref.time[g];
      if (tg < t.front() || tg > t.back()) continue;
      const double de = log::interpolate_linear(t, track.east, tg) - ref.east[g];
      const double dn = log::interpolate_linear(t, track.north, tg) - ref.north[g];
      const double du = log::interpolate_linear(t, track.up, tg) - ref.up[g];
      se += de * de;
      sn += dn * dn;
      su += du * du;
      const double dve = log::interpolate_linear(t, track.ve, tg) - ref.v_east[g];
      const double dvn = log::interpolate_linear(t, track.vn, tg) - ref.v_north[g];
      sv += dve * dve + dvn * dvn;
      const double oe = log::interpolate_linear(odo.time, odo.east, tg) - ref.east[g];
      const double on = log::interpolate_linear(odo.time, odo.north, tg) - ref.north[g];
      if (std::isfinite(oe + on)) so += oe * oe + on * on;
      ++count;
      m.final_position_error = std::hypot(de, dn);
      m.final_position_error_3d = std::sqrt(de * de + dn * dn + du * du);
      result.odometry.final_position_error = std::isfinite(oe + on) ? std::hypot(oe, on) : result.odometry.final_position_error;
    }
    m.distance = distance_along(ref).back();
    if (count > 0) {
      const double c = static_cast<double>(count);
      m.position_rmse_axes = {std::sqrt(se / c), std::sqrt(sn / c), std::sqrt(su / c)};
      m.position_rmse = std::sqrt((se + sn) / c);
      m.velocity_rmse = std::sqrt(sv / c);
      result.odometry.position_rmse = std::sqrt(so / c);
    }
    // Heading drift: INS heading minus GPS course over the last 5 s of driving.
    double last_moving = -INFINITY;
    for (std::size_t g = 0; g < ref.time.size(); ++g) {
      if (std::hypot(ref.v_east[g], ref.v_north[g]) > 0.3) last_moving = ref.time[g];
    }
    double sum = 0;
    int k = 0;
    for (std::size_t g = 0; g < ref.time.size(); ++g) {
      const double speed = std::hypot(ref.v_east[g], ref.v_north[g]);
      if (speed > 0.3 && ref.time[g] >= last_moving - 5.0 && ref.time[g] <= t.back()) {
        sum += wrap(log::interpolate_linear(t, track.yaw, ref.time[g]) - std::atan2(ref.v_east[g], ref.v_north[g]));
        ++k;
      }
    }
    m.heading_drift = k > 0 ? sum / k : NAN;
  }
  if (o.progress) o.progress(1.0);
  return result;
}

}  // namespace roverlab::estimation

#include "core/estimation/ins_slip/estimator.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/estimation/ins_slip/streams.h"
#include "core/log/time_checks.h"

namespace roverlab::estimation {

namespace {

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
    const auto m = static_cast<double>(b - a);
    const double mean = (s1[b] - s1[a]) / m;
    out[i] = std::sqrt(std::max(0.0, (s2[b] - s2[a]) / m - mean * mean));
  }
  return out;
}

}  // namespace

InsSlipEstimator::InsSlipEstimator(const log::Log& log, const InsSlipOptions& options, const InsSlipChannels& channels)
    : log_(log), o_(options), channels_(channels) {
  read_samples();
  detect_standstill();
  level();
}

namespace {
// The strapdown mechanisation cannot bridge an IMU gap longer than this, s.
constexpr double kMaxImuGap = 1.0;
// The wheels must cover at least this share of the IMU's time span.
constexpr double kMinOverlap = 0.5;
}  // namespace

void InsSlipEstimator::read_samples() {
  const std::string& imu_name = channels_.imu;
  imu_ = &log_.stream(imu_name);
  in_.wheels = &log_.stream(channels_.wheels);
  if (imu_->size() < 10) throw DataError("stream '" + imu_name + "' has fewer than 10 samples");
  if (in_.wheels->size() < 3) throw DataError("stream '" + channels_.wheels + "' has fewer than 3 samples");
  log::require_no_gap(*imu_, kMaxImuGap);
  log::require_overlap(*imu_, *in_.wheels, kMinOverlap);
  // The IMU drives the mechanisation: outliers and missing samples never enter it.
  imu_screened_ = screen_imu(
      imu_name, imu_->time(),
      {&values(*imu_, "angular_rate_x"), &values(*imu_, "angular_rate_y"), &values(*imu_, "angular_rate_z"),
       &values(*imu_, "specific_force_x"), &values(*imu_, "specific_force_y"), &values(*imu_, "specific_force_z")},
      o_.imu_screen);
  in_.screened = &imu_screened_;
  in_.wx = &imu_screened_.values[0];
  in_.wy = &imu_screened_.values[1];
  in_.wz = &imu_screened_.values[2];
  in_.fx = &imu_screened_.values[3];
  in_.fy = &imu_screened_.values[4];
  in_.fz = &imu_screened_.values[5];
  const log::Stream& w = *in_.wheels;
  in_.wheel_rates =
      wheel_rates(w.time(), values(w, "angle_FL"), values(w, "angle_FR"), values(w, "angle_RL"), values(w, "angle_RR"));
  reference_ = reference_from_gps(log_, channels_.gps);
  smooth_reference(reference_);
  in_.time = &imu_->time();
  truth_slip_ = log_.find_stream(channels_.truth_slip);
  if (truth_slip_ != nullptr && truth_slip_->find_channel("slip_ratio") == nullptr) truth_slip_ = nullptr;
}

// Standstill: quiet IMU and wheels that do not turn.
void InsSlipEstimator::detect_standstill() {
  const std::size_t n = in_.size();
  const auto& t = *in_.time;
  std::vector<double> fnorm(n), wnorm(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double fx = (*in_.fx)[i], fy = (*in_.fy)[i], fz = (*in_.fz)[i];
    const double wx = (*in_.wx)[i], wy = (*in_.wy)[i], wz = (*in_.wz)[i];
    fnorm[i] = std::sqrt(fx * fx + fy * fy + fz * fz);
    wnorm[i] = std::sqrt(wx * wx + wy * wy + wz * wz);
  }
  const double rate = imu_->mean_rate_hz();
  const auto half = static_cast<std::size_t>(std::max(1.0, 0.5 * o_.standstill.window * rate));
  const auto fstd = moving_std(fnorm, half), wstd = moving_std(wnorm, half);
  const WheelSamples& wr = in_.wheel_rates;
  const double wheel_rate_max = o_.standstill.wheel_rate_max;
  in_.standstill.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = in_.wheel_index(t[i]);
    bool wheels_still = true;
    for (std::size_t j = (k > 0 ? k - 1 : 0); j <= std::min(k + 1, wr.time.size() - 1); ++j) {
      wheels_still =
          wheels_still && std::abs(wr.left_rate[j]) <= wheel_rate_max && std::abs(wr.right_rate[j]) <= wheel_rate_max;
    }
    const bool still = wheels_still && fstd[i] <= o_.standstill.accel_std_max && wstd[i] <= o_.standstill.gyro_std_max;
    in_.standstill[i] = still ? 1 : 0;
  }
}

// Initial attitude: levelling on the first 5 s at rest (or the first 0.5 s);
// initial heading from the options, else north until align_initial_pose.
void InsSlipEstimator::level() {
  const std::size_t n = in_.size();
  const auto& t = *in_.time;
  const double rate = imu_->mean_rate_hz();
  std::size_t level_end = 0;
  while (level_end < n && in_.standstill[level_end] && t[level_end] - t[0] < 5.0) ++level_end;
  if (level_end < static_cast<std::size_t>(0.5 * rate))
    level_end = std::min(n, static_cast<std::size_t>(0.5 * rate) + 1);
  Eigen::Vector3d f0 = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < level_end; ++i) f0 += in_.force(i);
  f0 /= static_cast<double>(level_end);
  in_.roll0 = std::atan2(-f0.y(), -f0.z());
  in_.pitch0 = std::atan2(f0.x(), std::hypot(f0.y(), f0.z()));
  in_.heading0 = 0.0;
  if (o_.initial_heading) {
    in_.heading0 = *o_.initial_heading;
    heading_.method = InitialHeading::Method::given;
    heading_.heading = in_.heading0;
  }
  in_.frame = LocalFrame(reference_.latitude, reference_.longitude, reference_.height);
}

// Initial heading and position: a first pass from heading 0 at the origin,
// then the rigid rotation and translation that best align its track with the
// GPS fixes (gate-rejected ones left out) over the first alignment_distance
// metres of GPS track, or longer until the fix noise alone leaves the heading
// known to alignment_heading_sigma. The filter is heading-invariant to within
// the Earth rate's effect, so the second pass from the aligned pose follows
// the rotated first track.
double InsSlipEstimator::pass_share() const {
  const int passes = (o_.initial_heading || !reference_.present ? 0 : 1) + (o_.odometry_aiding ? 2 : 1);
  return 1.0 / passes;
}

void InsSlipEstimator::align_initial_pose() {
  if (o_.initial_heading || !reference_.present) return;
  const auto& t = *in_.time;
  // Progress (and, through it, cancellation) in thirds or halves: this pass first.
  const InsTrack track = InsFilterPass(in_, o_, o_.odometry_aiding).run(0.0, pass_share());
  const std::vector<double> along = distance_along(reference_);
  const double fix_variance = std::isfinite(reference_.fix_sigma) ? reference_.fix_sigma * reference_.fix_sigma : 0.0;
  std::vector<double> xe, xn, ye, yn;
  double stretch = 0, se = 0, sn = 0, sq = 0;  // running sums of the first pass's points
  for (std::size_t g = 0; g < reference_.time.size(); ++g) {
    const double tg = reference_.time[g];
    if (tg < t.front() || tg > t.back()) continue;
    if (along[g] > o_.alignment_distance && xe.size() >= 10) {
      // Heading variance the fix noise alone leaves: sigma^2 / spread of the points.
      const auto k = static_cast<double>(xe.size());
      const double spread = sq - (se * se + sn * sn) / k;
      if (spread > 0 && fix_variance / spread <= o_.alignment_heading_sigma * o_.alignment_heading_sigma) break;
    }
    stretch = along[g];
    if (!reference_.outlier.empty() && reference_.outlier[g] != 0) continue;
    xe.push_back(log::interpolate_linear(t, track.east, tg));
    xn.push_back(log::interpolate_linear(t, track.north, tg));
    ye.push_back(reference_.east[g]);
    yn.push_back(reference_.north[g]);
    se += xe.back();
    sn += xn.back();
    sq += xe.back() * xe.back() + xn.back() * xn.back();
  }
  // Too short a stretch to tell a heading (the rover never left the spot).
  if (stretch < 2.0 || xe.size() < 10) return;
  const RigidAlignment a = rigid_alignment(xe, xn, ye, yn);
  in_.heading0 = a.rotation;
  in_.east0 = a.east;
  in_.north0 = a.north;
  // The stated sigma: the fix noise's or the residuals', whichever is larger.
  const double spread = sq - (se * se + sn * sn) / static_cast<double>(xe.size());
  const double noise_sigma = spread > 0 ? std::sqrt(fix_variance / spread) : NAN;
  const double sigma = std::isfinite(noise_sigma) ? std::max(noise_sigma, a.rotation_sigma) : a.rotation_sigma;
  heading_ = {InitialHeading::Method::aligned, a.rotation, sigma, a.east, a.north, stretch, a.points, a.residual_rms};
}

log::Log InsSlipEstimator::run() {
  align_initial_pose();
  const double share = pass_share();
  const double base = o_.initial_heading || !reference_.present ? 0.0 : share;
  // The localisation filter (with wheel-speed aiding if asked), and the slip
  // detector: a filter that never sees the wheel speed it is judged against.
  const InsTrack track = InsFilterPass(in_, o_, o_.odometry_aiding).run(base, share);
  const InsTrack detector_track =
      o_.odometry_aiding ? InsFilterPass(in_, o_, false).run(base + share, share) : InsTrack(0);
  const InsTrack& detector = o_.odometry_aiding ? detector_track : track;
  health_ = track.health;
  if (o_.odometry_aiding) health_.merge(detector_track.health);
  health_.outliers_rejected = imu_screened_.outliers;
  health_.missing_samples = imu_screened_.missing;
  health_.gaps = imu_screened_.gaps;

  log::Log out;
  out.metadata = log_.metadata;
  out.metadata.extra["estimator"] = "ins-slip (seed 002)";
  add_navigation_streams(out, track);
  add_slip_stream(out, detector);
  add_odometry_stream(out);
  if (o_.progress) o_.progress(1.0);
  return out;
}

void InsSlipEstimator::add_navigation_streams(log::Log& out, const InsTrack& track) const {
  const auto& t = *in_.time;
  log::Stream pose(ins_streams::kPose, t);
  pose.add_channel("roll", "rad", track.roll);
  pose.add_channel("pitch", "rad", track.pitch);
  pose.add_channel("yaw", "rad", track.yaw, "heading, clockwise from north");
  pose.add_channel("east", "m", track.east, "from the initial position");
  pose.add_channel("north", "m", track.north);
  pose.add_channel("up", "m", track.up);
  pose.add_channel("valid", "bool", track.valid, "0 where the filter had diverged (reset, recovering, or stopped)");
  std::vector<double> bridged(imu_screened_.bridged.begin(), imu_screened_.bridged.end());
  pose.add_channel("bridged", "bool", std::move(bridged),
                   "1 where the IMU sample was rejected or missing: prediction from the last usable one");
  out.add_stream(std::move(pose));
  log::Stream vel(ins_streams::kVelocity, t);
  vel.add_channel("north", "m/s", track.vn);
  vel.add_channel("east", "m/s", track.ve);
  vel.add_channel("down", "m/s", track.vd);
  vel.add_channel("forward", "m/s", track.vx, "body x (Eq. 29)");
  vel.add_channel("lateral", "m/s", track.vy, "body y");
  vel.add_channel("vertical", "m/s", track.vz, "body z (down)");
  out.add_stream(std::move(vel));
  log::Stream b(ins_streams::kBias, t);
  const char* names_b[6] = {"accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z"};
  for (int k = 0; k < 6; ++k)
    b.add_channel(names_b[k], k < 3 ? "m/s^2" : "rad/s", track.bias[static_cast<std::size_t>(k)]);
  out.add_stream(std::move(b));
  std::vector<double> still(in_.size());
  for (std::size_t i = 0; i < still.size(); ++i) still[i] = in_.standstill[i] ? 1.0 : 0.0;
  log::Stream st(ins_streams::kStandstill, t);
  st.add_channel("standstill", "bool", still, "1 where ZUPT/ZARU applied");
  out.add_stream(std::move(st));
}

double InsSlipEstimator::no_slip() const {
  if (o_.no_slip) return *o_.no_slip;
  return truth_slip_ == nullptr && reference_.present ? 0.0 : 0.02;
}

// Slip at the wheel samples within the IMU span (Eq. 1 with Eq. 29).
InsSlipEstimator::SlipColumns InsSlipEstimator::slip_columns(const InsTrack& detector) const {
  const auto& t = *in_.time;
  const WheelSamples& wr = in_.wheel_rates;
  const double r = o_.rover.wheel_radius;
  SlipColumns c;
  for (std::size_t k = 0; k < wr.time.size(); ++k) {
    const double tk = wr.time[k];
    if (tk < t.front() || tk > t.back()) continue;
    const double wheel_speed = in_.wheel_speed(k, r);
    const double v = log::interpolate_linear(t, detector.vx, tk);
    // At standstill slip is 0 (Eq. 1's third case). Moving slower than
    // min_slip_speed the ratio is ill-conditioned, and turning in place
    // (one side's wheels backwards) it has no forward speed to refer to:
    // NaN, left out of the confusion matrix.
    const bool at_rest = in_.standstill[std::min(imu_->nearest_index(tk), in_.size() - 1)] != 0;
    const bool turning = wr.left_rate[k] * wr.right_rate[k] < 0.0 &&
                         0.5 * r * std::abs(wr.left_rate[k] - wr.right_rate[k]) > std::abs(wheel_speed);
    const bool slow = std::abs(wheel_speed) < o_.min_slip_speed && std::abs(v) < o_.min_slip_speed;
    const bool undefined = !at_rest && (slow || turning);
    const double s_e = at_rest ? 0.0 : undefined ? NAN : slip_ratio(v, wheel_speed);
    c.time.push_back(tk);
    c.slip.push_back(s_e);
    c.slip_class.push_back(undefined ? NAN : static_cast<double>(classify_slip(s_e, no_slip())));
    c.wheel_speed.push_back(wheel_speed);
    c.forward_speed.push_back(v);
    c.at_rest.push_back(at_rest ? 1.0 : 0.0);
    add_reference_slip(c, tk, wheel_speed, at_rest, turning);
  }
  return c;
}

// The reference slip: the log's truth when present, else Eq. 30 from the
// RTS-smoothed GPS velocity projected on the GPS course (its speed), signed
// by the wheels' direction, so that no heading estimate enters it.
void InsSlipEstimator::add_reference_slip(SlipColumns& c, double tk, double wheel_speed, bool at_rest,
                                          bool turning) const {
  if (truth_slip_ != nullptr) {
    const std::size_t j = truth_slip_->nearest_index(tk);
    const double s_r = truth_slip_->channel("slip_ratio").values[j];
    c.reference_slip.push_back(s_r);
    c.reference_class.push_back(static_cast<double>(classify_slip(s_r, no_slip())));
    c.reference_speed.push_back(NAN);
  } else if (reference_.present) {
    const ReferenceTrack& ref = reference_;
    const double speed = std::hypot(log::interpolate_linear(ref.time, ref.v_east, tk),
                                    log::interpolate_linear(ref.time, ref.v_north, tk));
    const double v_r = wheel_speed < 0.0 ? -speed : speed;
    const bool slow = std::abs(wheel_speed) < o_.min_slip_speed && speed < o_.min_slip_speed;
    double s_r = slip_ratio(v_r, wheel_speed);
    if (at_rest) {
      s_r = 0.0;
    } else if (slow || turning) {
      s_r = NAN;
    }
    c.reference_slip.push_back(s_r);
    c.reference_class.push_back(std::isfinite(s_r) ? static_cast<double>(classify_slip(s_r, no_slip())) : NAN);
    c.reference_speed.push_back(std::isfinite(s_r) ? v_r : NAN);
  }
}

void InsSlipEstimator::add_slip_stream(log::Log& out, const InsTrack& detector) const {
  SlipColumns c = slip_columns(detector);
  log::Stream slip(ins_streams::kSlip, std::move(c.time));
  slip.add_channel("slip_ratio", "1", std::move(c.slip),
                   "Eq. 1: INS forward speed against wheel speed (NaN: too slow to tell)");
  slip.add_channel("slip_class", "1", std::move(c.slip_class), "0 none, 1 low, 2 medium, 3 high, 4 extreme");
  slip.add_channel("wheel_speed", "m/s", std::move(c.wheel_speed), "r omega, mean of the four wheels");
  slip.add_channel("forward_speed", "m/s", std::move(c.forward_speed), "INS body forward speed");
  slip.add_channel("at_rest", "bool", std::move(c.at_rest), "1 at standstill (slip 0 by Eq. 1's third case)");
  if (truth_slip_ != nullptr || reference_.present) {
    slip.add_channel("reference_speed", "m/s", std::move(c.reference_speed),
                     "smoothed GPS speed, signed by the wheels (NaN: truth used, or slip undefined)");
    slip.add_channel("reference_slip", "1", std::move(c.reference_slip), truth_slip_ ? "truth" : "Eq. 30, from GPS");
    slip.add_channel("reference_class", "1", std::move(c.reference_class));
  }
  out.add_stream(std::move(slip));
}

namespace {
// Window over which the vertical velocity increments are taken: long enough
// that real bumps (bounded vertical speed) add little to a random walk.
constexpr double kWalkWindow = 4.0;  // s
// Vibration: deviation from a centred moving mean over this span.
constexpr double kVibrationSpan = 0.2;  // s

// Gravity in body axes for the drive [a, b): the summed specific force over
// up to 2 s of standstill before it, else after it; count the samples.
template <class Input>
Eigen::Vector3d standstill_force(const Input& in, std::size_t a, std::size_t b, std::size_t& count) {
  const auto& t = *in.time;
  const std::size_t n = in.size();
  Eigen::Vector3d g = Eigen::Vector3d::Zero();
  for (std::size_t i = a; i-- > 0 && in.standstill[i] != 0 && t[a] - t[i] < 2.0;) {
    g += in.force(i);
    ++count;
  }
  if (count == 0) {
    for (std::size_t i = b; i < n && in.standstill[i] != 0 && t[i] - t[b] < 2.0; ++i) {
      g += in.force(i);
      ++count;
    }
  }
  return g;
}

// The specific force along g minus |g| integrated over windows of
// kWalkWindow in the drive [a, b): each window adds dv^2 / its length.
template <class Input>
void add_vertical_walk(const Input& in, std::size_t a, std::size_t b, const Eigen::Vector3d& g, double& walk,
                       std::size_t& windows) {
  const auto& t = *in.time;
  const double g_norm = g.norm();
  const Eigen::Vector3d up = g / g_norm;
  double dv = 0, start = t[a];
  for (std::size_t i = a + 1; i < b; ++i) {
    dv += (in.force(i - 1).dot(up) - g_norm) * (t[i] - t[i - 1]);
    if (t[i] - start >= kWalkWindow) {
      walk += dv * dv / (t[i] - start);
      ++windows;
      dv = 0;
      start = t[i];
    }
  }
}
}  // namespace

// Vertical velocity random walk while moving: the specific force along the
// gravity direction of the nearest standstill, minus g, integrated over
// windows of kWalkWindow; a white acceleration error q gives increments of
// q^2 W. Over a drive of T s between two ZUPTs the smoothed speed error is a
// Brownian bridge, RMS q sqrt(T / 6); with one end open, q sqrt(T / 2).
ImuVibration InsSlipEstimator::vibration() const {
  ImuVibration v;
  v.modelled_walk = o_.noise.accel_vrw;
  const auto& t = *in_.time;
  const std::size_t n = in_.size();
  const auto half = static_cast<std::size_t>(std::max(1.0, 0.5 * kVibrationSpan * imu_->mean_rate_hz()));
  std::vector<double> fx(n), fz(n);
  for (std::size_t i = 0; i < n; ++i) {
    fx[i] = (*in_.fx)[i];
    fz[i] = (*in_.fz)[i];
  }
  const std::vector<double> sx = moving_std(fx, half), sz = moving_std(fz, half);
  std::vector<double> speeds;  // the wheels', while moving and not too slow to count
  double vib_x = 0, vib_z = 0, walk = 0;
  std::size_t moving = 0, windows = 0;
  bool bridge = false;
  for (std::size_t a = 0; a < n;) {
    if (in_.standstill[a] != 0) {
      ++a;
      continue;
    }
    std::size_t b = a;
    while (b < n && in_.standstill[b] == 0) ++b;
    std::size_t count = 0;
    Eigen::Vector3d g = standstill_force(in_, a, b, count);
    if (t[b - 1] - t[a] > v.longest_drive) {
      v.longest_drive = t[b - 1] - t[a];
      bridge = a > 0 && b < n;  // a ZUPT at both ends
    }
    for (std::size_t i = a; i < b; ++i) {
      vib_x += sx[i] * sx[i];
      vib_z += sz[i] * sz[i];
      const double speed = std::abs(in_.wheel_speed(in_.wheel_index(t[i]), o_.rover.wheel_radius));
      if (speed >= o_.min_slip_speed) speeds.push_back(speed);
    }
    moving += b - a;
    if (count > 0) add_vertical_walk(in_, a, b, g / static_cast<double>(count), walk, windows);
    a = b;
  }
  if (moving == 0) return v;
  v.forward_vibration = std::sqrt(vib_x / static_cast<double>(moving));
  v.vertical_vibration = std::sqrt(vib_z / static_cast<double>(moving));
  if (windows == 0 || v.vertical_vibration <= 0) return v;
  v.vertical_walk = std::sqrt(walk / static_cast<double>(windows));
  // The vertical channel's error scaled by the vibration ratio, never above it
  // (without vibration the forward RMS is the manoeuvres, not an error).
  v.forward_walk = v.vertical_walk * std::min(1.0, v.forward_vibration / v.vertical_vibration);
  v.speed_error = v.forward_walk * std::sqrt(v.longest_drive / (bridge ? 6.0 : 2.0));
  if (!speeds.empty()) {
    const auto mid = speeds.begin() + static_cast<std::ptrdiff_t>(speeds.size() / 2);
    std::nth_element(speeds.begin(), mid, speeds.end());
    v.median_speed = *mid;
    v.slip_resolution = v.speed_error / v.median_speed;
  }
  return v;
}

// Plain wheel odometry from the same initial pose.
void InsSlipEstimator::add_odometry_stream(log::Log& out) const {
  const OdometryTrack odo =
      dead_reckon(in_.wheel_rates, o_.rover, OdometryCorrections{}, in_.east0, in_.north0, in_.heading0);
  log::Stream p(ins_streams::kOdometryPose, odo.time);
  p.add_channel("east", "m", odo.east);
  p.add_channel("north", "m", odo.north);
  p.add_channel("heading", "rad", odo.heading, "clockwise from north, from the wheel rate difference");
  p.add_channel("forward_speed", "m/s", odo.forward_speed);
  out.add_stream(std::move(p));
}

}  // namespace roverlab::estimation

#include "core/estimation/ins_slip/metrics.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/estimation/ins_slip/streams.h"
#include "core/models/reference_track.h"

namespace roverlab::analysis {

namespace {

using estimation::ReferenceTrack;

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

const std::vector<double>& values(const log::Stream& s, const char* name) { return s.channel(name).values; }

// Position (east, north, up) and velocity (east, north) errors against GPS at
// the GPS samples within the INS span (seed 002 Table 1).
void score_track(const ReferenceTrack& ref, const log::Stream& pose, const log::Stream& velocity, InsSlipMetrics& m) {
  const auto& t = pose.time();
  const auto &east = values(pose, "east"), &north = values(pose, "north"), &up = values(pose, "up");
  const auto &ve = values(velocity, "east"), &vn = values(velocity, "north");
  double se = 0, sn = 0, su = 0, sv = 0;
  std::size_t count = 0;
  for (std::size_t g = 0; g < ref.time.size(); ++g) {
    const double tg = ref.time[g];
    if (tg < t.front() || tg > t.back()) continue;
    const double de = log::interpolate_linear(t, east, tg) - ref.east[g];
    const double dn = log::interpolate_linear(t, north, tg) - ref.north[g];
    const double du = log::interpolate_linear(t, up, tg) - ref.up[g];
    se += de * de;
    sn += dn * dn;
    su += du * du;
    const double dve = log::interpolate_linear(t, ve, tg) - ref.v_east[g];
    const double dvn = log::interpolate_linear(t, vn, tg) - ref.v_north[g];
    sv += dve * dve + dvn * dvn;
    ++count;
    m.final_position_error = std::hypot(de, dn);
    m.final_position_error_3d = std::sqrt(de * de + dn * dn + du * du);
  }
  if (count > 0) {
    const auto c = static_cast<double>(count);
    m.position_rmse_axes = {std::sqrt(se / c), std::sqrt(sn / c), std::sqrt(su / c)};
    m.position_rmse = std::sqrt((se + sn) / c);
    m.velocity_rmse = std::sqrt(sv / c);
  }
}

// Errors after the best rigid alignment of (east, north) onto GPS over the
// first `distance` metres of GPS track: RMSE and final error over the whole
// track, and the rotation the alignment needed.
struct AlignedErrors {
  double rmse = NAN, final_error = NAN, rotation = NAN;
};
AlignedErrors aligned_errors(const ReferenceTrack& ref, const std::vector<double>& t, const std::vector<double>& east,
                             const std::vector<double>& north, double distance) {
  AlignedErrors out;
  const std::vector<double> along = estimation::distance_along(ref);
  std::vector<double> xe, xn, ye, yn;
  for (std::size_t g = 0; g < ref.time.size() && along[g] <= distance; ++g) {
    const double tg = ref.time[g];
    if (tg < t.front() || tg > t.back()) continue;
    xe.push_back(log::interpolate_linear(t, east, tg));
    xn.push_back(log::interpolate_linear(t, north, tg));
    ye.push_back(ref.east[g]);
    yn.push_back(ref.north[g]);
  }
  if (xe.size() < 3) return out;
  const estimation::RigidAlignment a = estimation::rigid_alignment(xe, xn, ye, yn);
  double ss = 0;
  std::size_t count = 0;
  for (std::size_t g = 0; g < ref.time.size(); ++g) {
    const double tg = ref.time[g];
    if (tg < t.front() || tg > t.back()) continue;
    double e = log::interpolate_linear(t, east, tg), n = log::interpolate_linear(t, north, tg);
    if (!std::isfinite(e + n)) continue;
    estimation::apply_alignment(a, e, n);
    ss += (e - ref.east[g]) * (e - ref.east[g]) + (n - ref.north[g]) * (n - ref.north[g]);
    out.final_error = std::hypot(e - ref.east[g], n - ref.north[g]);
    ++count;
  }
  if (count > 0) out.rmse = std::sqrt(ss / static_cast<double>(count));
  out.rotation = a.rotation;
  return out;
}

// Heading minus GPS course over the last 5 s of driving (faster than 0.3 m/s).
double heading_drift(const ReferenceTrack& ref, const log::Stream& pose) {
  const auto& t = pose.time();
  const auto& yaw = values(pose, "yaw");
  double last_moving = -std::numeric_limits<double>::infinity();
  for (std::size_t g = 0; g < ref.time.size(); ++g) {
    if (std::hypot(ref.v_east[g], ref.v_north[g]) > 0.3) last_moving = ref.time[g];
  }
  double sum = 0;
  int k = 0;
  for (std::size_t g = 0; g < ref.time.size(); ++g) {
    const double speed = std::hypot(ref.v_east[g], ref.v_north[g]);
    if (speed > 0.3 && ref.time[g] >= last_moving - 5.0 && ref.time[g] <= t.back()) {
      sum += wrap(log::interpolate_linear(t, yaw, ref.time[g]) - std::atan2(ref.v_east[g], ref.v_north[g]));
      ++k;
    }
  }
  return k > 0 ? sum / k : NAN;
}

// Estimated against reference slip classes (seed 002 Table 2), from the
// estimator's slip stream. Left out: samples too slow to tell (class NaN)
// and, against GPS, samples without a GPS velocity.
void slip_confusion(const log::Log& input, const log::Stream& slip, const InsReferenceStreams& reference,
                    InsSlipMetrics& m) {
  const log::Channel* reference_class = slip.find_channel("reference_class");
  if (reference_class == nullptr) return;
  const log::Stream* truth = input.find_stream(reference.truth_slip);
  const bool against_truth = truth != nullptr && truth->find_channel("slip_ratio") != nullptr;
  const auto& estimated_class = values(slip, "slip_class");
  const auto& reference_speed = values(slip, "reference_speed");
  const log::Channel* at_rest = slip.find_channel("at_rest");
  for (std::size_t k = 0; k < estimated_class.size(); ++k) {
    if (!std::isfinite(estimated_class[k]) || !std::isfinite(reference_class->values[k])) continue;
    if (!against_truth && !std::isfinite(reference_speed[k])) continue;
    const auto e = static_cast<estimation::SlipClass>(static_cast<int>(estimated_class[k]));
    const auto r = static_cast<estimation::SlipClass>(static_cast<int>(reference_class->values[k]));
    m.confusion.add(e, r);
    if (at_rest == nullptr || at_rest->values[k] == 0.0) m.confusion_moving.add(e, r);
  }
}

}  // namespace

InsSlipMetrics score_ins_slip(const log::Log& input, const log::Log& estimates, const InsReferenceStreams& reference) {
  const log::Stream& pose = estimates.stream(estimation::ins_streams::kPose);
  const auto& t = pose.time();
  const auto& standstill = values(estimates.stream(estimation::ins_streams::kStandstill), "standstill");
  InsSlipMetrics m;
  m.duration = t.back() - t.front();
  m.standstill_fraction =
      static_cast<double>(std::count(standstill.begin(), standstill.end(), 1.0)) / static_cast<double>(t.size());
  slip_confusion(input, estimates.stream(estimation::ins_streams::kSlip), reference, m);
  ReferenceTrack ref = estimation::reference_from_gps(input, reference.gps);
  estimation::smooth_reference(ref);  // velocity and distance from the smoothed track
  if (!ref.present) return m;
  m.has_reference = true;
  score_track(ref, pose, estimates.stream(estimation::ins_streams::kVelocity), m);
  m.distance = estimation::distance_along(ref).back();
  m.heading_drift = heading_drift(ref, pose);
  const AlignedErrors a =
      aligned_errors(ref, t, values(pose, "east"), values(pose, "north"), reference.alignment_distance);
  m.aligned_position_rmse = a.rmse;
  m.aligned_final_position_error = a.final_error;
  m.alignment_rotation = a.rotation;
  return m;
}

OdometryMetrics score_wheel_odometry(const log::Log& input, const log::Log& estimates,
                                     const InsReferenceStreams& reference) {
  OdometryMetrics m;
  ReferenceTrack ref = estimation::reference_from_gps(input, reference.gps);
  estimation::smooth_reference(ref);  // velocity and distance from the smoothed track
  if (!ref.present) return m;
  const auto& t = estimates.stream(estimation::ins_streams::kPose).time();
  const log::Stream& odometry = estimates.stream(estimation::ins_streams::kOdometryPose);
  const auto &east = values(odometry, "east"), &north = values(odometry, "north");
  double so = 0;
  std::size_t count = 0;
  for (std::size_t g = 0; g < ref.time.size(); ++g) {
    const double tg = ref.time[g];
    if (tg < t.front() || tg > t.back()) continue;
    const double oe = log::interpolate_linear(odometry.time(), east, tg) - ref.east[g];
    const double on = log::interpolate_linear(odometry.time(), north, tg) - ref.north[g];
    if (std::isfinite(oe + on)) {
      so += oe * oe + on * on;
      m.final_position_error = std::hypot(oe, on);
    }
    ++count;
  }
  if (count > 0) m.position_rmse = std::sqrt(so / static_cast<double>(count));
  m.aligned_position_rmse = aligned_errors(ref, odometry.time(), east, north, reference.alignment_distance).rmse;
  return m;
}

}  // namespace roverlab::analysis

#include "core/estimation/net_traction/net_traction.h"

#include <chrono>
#include <cmath>
#include <string>
#include <utility>

#include "core/common/error.h"
#include "core/estimation/net_traction/streams.h"
#include "core/filters/filter_health.h"
#include "core/log/time_checks.h"

namespace roverlab::estimation {

namespace nt = net_traction;
namespace gen = net_traction::general;
namespace wf = net_traction::wheel_force;

namespace {

constexpr double kDeg = M_PI / 180.0;
// A wheel whose load along its link is below this has left the ground: its
// contact angle is not measured.
constexpr double kAirborneLoad = 1.0;  // N
// Variance of a measurement that is not available (gated out).
constexpr double kUnavailable = 1e8;
// The NIS gate (issue 17) closes after this many samples (the filters'
// convergence, 5 s at 50 Hz) and opens again for as long after this many
// rejections in a row (0.5 s).
constexpr std::size_t kGateSettle = 250;
constexpr std::size_t kMaxRejected = 25;
// The streams must share the joints' time base: each covers at least this
// share of the other's span, with no gap longer than kMaxGap.
constexpr double kMinOverlap = 0.5;
constexpr double kMaxGap = 1.0;  // s
// No sensor of the rover reads beyond this (SI units: N, N m, rad, m/s, m/s^2).
constexpr double kMaxReading = 1e9;
// A sensor channel holding one exact value this long (and over this share of
// the log) is flat-lined: warned about.
constexpr double kFlatSeconds = 5.0;
constexpr double kFlatFraction = 0.25;

const char* const kStreams[] = {"joints", "imu", "velocimeter", "forces", "commands"};

std::string index_name(const char* stem, int i) { return stem + std::to_string(i + 1); }

}  // namespace

ForceSensors parse_force_sensors(const std::string& name) {
  if (name == "two-axis") return ForceSensors::two_axis;
  if (name == "single-axis") return ForceSensors::single_axis;
  throw DataError("force sensors '" + name + "': expected two-axis or single-axis");
}

std::string force_sensors_name(ForceSensors sensors) {
  return sensors == ForceSensors::two_axis ? "two-axis" : "single-axis";
}

std::string net_traction_missing(const log::Log& lg) {
  for (const char* s : kStreams) {
    if (lg.find_stream(s) == nullptr) return std::string("no ") + s + " stream";
  }
  const struct {
    const char* stream;
    std::vector<std::string> channels;
  } needs[] = {
      {"joints", {"bogie_angle", "wheel_angle_1", "wheel_angle_2", "wheel_angle_3"}},
      {"imu", {"pitch_rate", "specific_force_x", "specific_force_z"}},
      {"velocimeter", {"forward_speed"}},
      {"forces", {"load_1", "load_2", "load_3"}},
      {"commands", {"wheel_torque_1", "wheel_torque_2", "wheel_torque_3"}},
  };
  for (const auto& n : needs) {
    const log::Stream& st = *lg.find_stream(n.stream);
    for (const auto& c : n.channels) {
      if (st.find_channel(c) == nullptr) return "no channel " + c + " in stream '" + n.stream + "'";
    }
  }
  return "";
}

bool has_two_axis_force_sensors(const log::Log& lg) {
  const log::Stream* f = lg.find_stream("forces");
  if (f == nullptr) return false;
  for (int i = 0; i < 3; ++i) {
    if (f->find_channel(index_name("perpendicular_", i)) == nullptr) return false;
  }
  return true;
}

NetTractionEstimator::NetTractionEstimator(const log::Log& log, const nt::RoverConstants& rover,
                                           const NetTractionOptions& options)
    : log_(log), rover_(rover), o_(options), measurement_(rover.parameters.gravity) {
  const std::string missing = net_traction_missing(log_);
  if (!missing.empty()) throw DataError(missing);
  const bool has_two_axis = has_two_axis_force_sensors(log_);
  const ForceSensors chosen =
      o_.force_sensors.value_or(has_two_axis ? ForceSensors::two_axis : ForceSensors::single_axis);
  if (chosen == ForceSensors::two_axis && !has_two_axis) {
    throw DataError("two-axis force estimation needs perpendicular_1..3 in stream 'forces'");
  }
  result_.force_sensors = chosen;
  two_axis_ = chosen == ForceSensors::two_axis;
  run_single_axis_ = !two_axis_ || o_.compare_single_axis;
  read_sensors();
  process_ = nt::GeneralProcessModel(rover_, step_);
  assemble_noise();
  initial_state();
}

// Every sensor on the joints stream's time base (Eq. 5.17) and the torques.
void NetTractionEstimator::read_sensors() {
  const log::Stream& joints = log_.stream("joints");
  const std::vector<double>& t = joints.time();
  for (const char* name : kStreams) {
    const log::Stream& st = log_.stream(name);
    log::require_samples(st, 10);
    log::require_no_gap(st, kMaxGap);
    log::require_shared_time_base(joints, st, kMinOverlap);
  }
  step_ = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  if (!(step_ > 0.0) || step_ > 0.5) throw DataError("stream 'joints' is not sampled at 2 Hz or faster");
  const auto at = [&](const char* stream, const std::string& channel) {
    const log::Stream& st = log_.stream(stream);
    log::require_finite_within(st, channel, kMaxReading);
    const std::string flat = log::flat_lined(st, channel, kFlatFraction, kFlatSeconds);
    if (!flat.empty()) result_.warnings.push_back(flat);
    if (&st == &joints) return st.channel(channel).values;
    std::vector<double> v = st.interpolate(channel, t);
    for (std::size_t k = 0; k < v.size(); ++k) {  // hold the ends where the streams' spans differ
      if (std::isnan(v[k])) v[k] = st.channel(channel).values[t[k] < st.start_time() ? 0 : st.size() - 1];
    }
    return v;
  };
  const std::vector<double> bogie = at("joints", "bogie_angle"), rate = at("imu", "pitch_rate"),
                            fx = at("imu", "specific_force_x"), fz = at("imu", "specific_force_z"),
                            speed = at("velocimeter", "forward_speed");
  samples_.resize(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    samples_[k].bogie = bogie[k];
    samples_[k].pitch_rate = rate[k];
    samples_[k].specific_force_x = fx[k];
    samples_[k].specific_force_z = fz[k];
    samples_[k].forward_speed = speed[k];
  }
  for (int i = 0; i < 3; ++i) {
    const std::vector<double> angle = at("joints", index_name("wheel_angle_", i)),
                              load = at("forces", index_name("load_", i)),
                              torque = at("commands", index_name("wheel_torque_", i));
    std::vector<double> perp(t.size(), 0.0);
    if (two_axis_) perp = at("forces", index_name("perpendicular_", i));
    for (std::size_t k = 0; k < t.size(); ++k) {
      samples_[k].wheel_angle(i) = angle[k];
      samples_[k].load(i) = load[k];
      samples_[k].torque(i) = torque[k];
      samples_[k].perpendicular(i) = perp[k];
    }
  }
  for (const auto& s : samples_) {
    const bool finite = std::isfinite(s.bogie) && std::isfinite(s.pitch_rate) && std::isfinite(s.forward_speed) &&
                        std::isfinite(s.specific_force_x) && std::isfinite(s.specific_force_z) &&
                        s.wheel_angle.allFinite() && s.load.allFinite() && s.torque.allFinite() &&
                        s.perpendicular.allFinite();
    if (!finite) throw DataError("a sensor sample is missing (NaN) in the net-traction streams");
  }
  result_.time = t;
}

// Process noise per step and Table 5.1's measurement noise, propagated to
// the measurements built from the sensors.
void NetTractionEstimator::assemble_noise() {
  using namespace gen;  // NOLINT(google-build-using-namespace)
  nt::GeneralState& q = q1_;
  q.segment<3>(kWheelRate).setConstant(1e-9);
  q.segment<3>(kResistiveTorque).setConstant(4e-6);
  q(kPitch) = q(kBogie) = 1e-10;
  q(kPitchRate) = q(kBogieRate) = 1e-8;
  q(kPitchAcceleration) = q(kBogieAcceleration) = 1e-5;
  q(kAccelerationX) = q(kAccelerationZ) = 1e-6;
  q(kMomentBody) = q(kMomentBogie) = 2e-3;
  q(kForceX) = q(kForceZ) = 2e-3;
  q(kForwardSpeed) = 1e-8;
  q.segment<3>(kSlip).setConstant(2e-6);
  const double encoder = 2.143e-5 * kDeg, accel = 1.245e-3;
  r1_.head<3>().setConstant(2.0 * encoder * encoder / (step_ * step_));  // Eq. 5.38 of two readings
  r1_(3) = 1e-3 * 1e-3;  // Eq. 5.39: accelerometer noise and the rover's own accelerations
  r1_(4) = std::pow(9.155e-4 * kDeg, 2);
  r1_(5) = r1_(6) = accel * accel;
  r1_(7) = 1e-3 * 1e-3;
  r1_.tail<3>().setConstant(0.06 * 0.06);  // the velocimeter's 1 mm/s over a 2 cm/s rim speed
  q2_.head<3>().setConstant(2e-7);
  q2_.tail<6>().setConstant(2.5e-3);
  r2_.head<3>().setConstant(0.03 * 0.03);
  r2_.tail<6>().setConstant(3.255e-2 * 3.255e-2);
  r3_ = r2_;
  r3_.tail<3>().setConstant(0.5 * 0.5);  // Eq. 5.64-5.66: built from Estimator 1's net forces
}

void NetTractionEstimator::initial_state() {
  open_until_.fill(kGateSettle);
  using namespace gen;  // NOLINT(google-build-using-namespace)
  const nt::SensorSample& s0 = samples_.front();
  nt::GeneralState x = nt::GeneralState::Zero();
  x(kPitch) = std::atan2(-s0.specific_force_x, s0.specific_force_z);
  x(kBogie) = s0.bogie;
  x.segment<3>(kResistiveTorque) = s0.torque;
  x(kForwardSpeed) = s0.forward_speed;
  // At rest: the net wheel forces hold the weight (Eq. 5.30-5.33 with no accelerations).
  const nt::ConfigurationTerms c = nt::configuration_terms(rover_, x(kPitch), x(kBogie));
  x(kMomentBody) = c.gravity(2) + s0.torque.sum();
  x(kMomentBogie) = c.gravity(3) + s0.torque(1) + s0.torque(2);
  x(kForceZ) = c.gravity(1);
  nt::GeneralState p;
  p.segment<3>(kWheelRate).setConstant(1e-4);
  p.segment<3>(kResistiveTorque).setConstant(1.0);
  p(kPitch) = 1e-4;
  p(kBogie) = 1e-6;
  p(kPitchRate) = p(kBogieRate) = 1e-4;
  p(kPitchAcceleration) = p(kBogieAcceleration) = 1e-2;
  p(kAccelerationX) = p(kAccelerationZ) = 1e-2;
  p.segment<4>(kMomentBody).setConstant(25.0);
  p(kForwardSpeed) = 1e-4;
  p.segment<3>(kSlip).setConstant(0.25);
  general_.x = x;
  general_.P = p.asDiagonal();
  general_.copied_state = kCopiedStates;  // Pxy's columns of those measurements are Pxx's
  nt::WheelForceState x2 = nt::WheelForceState::Zero(), p2;
  x2.segment<3>(wf::kNormalLoad) = s0.load;
  p2.head<3>().setConstant(0.1);
  p2.tail<6>().setConstant(100.0);
  for (WheelForceFilter* f : {&two_axis_filter_, &single_axis_filter_}) {
    f->x = x2;
    f->P = p2.asDiagonal();
  }
}

NetTractionResult NetTractionEstimator::run() {
  const auto start = std::chrono::steady_clock::now();
  filter_pass();
  result_.filter_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  path_positions();
  write_streams();
  if (o_.progress) o_.progress(1.0);
  return std::move(result_);
}

// Each sample: Estimator 1, then the wheel-force estimators on its estimate.
void NetTractionEstimator::filter_pass() {
  const auto n = static_cast<Eigen::Index>(samples_.size());
  const auto sized = [&](FilterTrack& t, Eigen::Index states) {
    t.state.resize(n, states);
    t.sigma.resize(n, states);
  };
  sized(result_.general, gen::kStates);
  if (two_axis_) sized(result_.two_axis, wf::kStates);
  if (run_single_axis_) sized(result_.single_axis, wf::kStates);
  result_.wheel_acceleration.resize(n, 3);
  const auto store = [](FilterTrack& t, const GeneralFilter& f, Eigen::Index k) {
    t.state.row(k) = f.x.transpose();
    t.sigma.row(k) = f.P.diagonal().cwiseMax(0.0).cwiseSqrt().transpose();
  };
  for (std::size_t k = 0; k < samples_.size(); ++k) {
    const auto r = static_cast<Eigen::Index>(k);
    if (k > 0) general_step(k);
    store(result_.general, general_, r);
    process_.set_torques(samples_[k].torque);
    result_.wheel_acceleration.row(r) = process_.wheel_accelerations(general_.x).transpose();
    if (k > 0) contact_angles_ = nt::contact_angle_measurement(rover_, general_.x);  // Eq. 5.56, for both
    if (two_axis_) wheel_force_step(k, two_axis_filter_, true, result_.two_axis);
    if (run_single_axis_) wheel_force_step(k, single_axis_filter_, false, result_.single_axis);
    if (o_.progress && k % 500 == 0) o_.progress(static_cast<double>(k) / static_cast<double>(samples_.size()));
  }
}

// Where each wheel is along the path, with no truth: the body's x from
// Estimator 1's forward speed (Eq. 5.20, zdot_0^R = 0: xdot_0 = xdot_0^R cos
// theta), trapezoids, plus each wheel's offset at the estimated pitch and
// bogie angle (Eq. 4.19-4.21); wheel 1 starts at x = 0.
void NetTractionEstimator::path_positions() {
  const Eigen::MatrixXd& g = result_.general.state;
  const auto n = g.rows();
  result_.wheel_x.resize(n, 3);
  const auto& geo = rover_.geometry;
  const auto offsets = [&](Eigen::Index k) {
    const double th = g(k, gen::kPitch), tb = th + g(k, gen::kBogie);
    const Eigen::Vector2d pivot = simulation::rocker_bogie::rotate(th, geo.rocker_to_bogie);
    return Eigen::Vector3d(simulation::rocker_bogie::rotate(th, geo.rocker_to_wheel1).x(),
                           (pivot + simulation::rocker_bogie::rotate(tb, geo.bogie_to_wheel2)).x(),
                           (pivot + simulation::rocker_bogie::rotate(tb, geo.bogie_to_wheel3)).x());
  };
  const auto speed = [&](Eigen::Index k) { return g(k, gen::kForwardSpeed) * std::cos(g(k, gen::kPitch)); };
  double x0 = n > 0 ? -offsets(0)(0) : 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (k > 0)
      x0 += 0.5 * (speed(k) + speed(k - 1)) *
            (result_.time[static_cast<std::size_t>(k)] - result_.time[static_cast<std::size_t>(k - 1)]);
    result_.wheel_x.row(k) = (offsets(k).array() + x0).transpose();
  }
}

// Eq. 5.10-5.16 for Estimator 1 with the torques held since the last sample;
// slips a standing rover cannot measure are gated out.
void NetTractionEstimator::general_step(std::size_t k) {
  const Eigen::Vector2d rates(general_.x(gen::kPitchRate), general_.x(gen::kBogieRate));
  nt::GeneralMeasurement y = nt::general_measurement(rover_, samples_[k], samples_[k - 1], step_, &rates);
  nt::GeneralMeasurement r = r1_;
  bool standing = false;
  for (int i = 0; i < 3; ++i) {
    if (std::isnan(y(gen::kMeasurements - 3 + i))) {
      y(gen::kMeasurements - 3 + i) = general_.x(gen::kSlip + i);
      r(gen::kMeasurements - 3 + i) = kUnavailable;
      standing = true;
    }
  }
  if (standing) ++result_.standstill_samples;
  general_.gate = gate(0, k, static_cast<int>((r.array() < kUnavailable).count()));
  process_.set_torques(samples_[k - 1].torque);
  const auto f = [this](const nt::GeneralState& x, nt::GeneralState& out) { process_(x, out); };
  const auto h = [this](const nt::GeneralState& x, nt::GeneralMeasurement& out) { measurement_(x, out); };
  // Eq. 5.12's Q added before the sigma points rather than after them: the
  // same for the random walks, f(x + w) ~ f(x) + F w for the rest, and the
  // UKF then needs no sigma points along the 22 process noises (half the
  // augmented state's).
  general_.P.diagonal() += q1_;
  general_.step(f, h, r, y);
  count_rejection(0, k, general_.rejected);
}

// Filter `which`'s NIS gate at sample k (issue 17): the chi-square quantile
// of the gate probability for `dof` measurements; none while the filters
// converge (the first kGateSettle samples), nor for kGateSettle samples after
// kMaxRejected rejections in a row (a lasting change, not an outlier: the
// filter converges on it again).
double NetTractionEstimator::gate(int which, std::size_t k, int dof) {
  if (!(o_.gate_probability < 1.0) || dof <= 0 || k < open_until_.at(static_cast<std::size_t>(which))) {
    return HUGE_VAL;
  }
  double& g = gates_.at(static_cast<std::size_t>(std::min(dof, static_cast<int>(gates_.size()) - 1)));
  if (g == 0.0) g = chi_square_quantile(dof, o_.gate_probability);
  return g;
}

void NetTractionEstimator::count_rejection(int which, std::size_t k, bool rejected) {
  const auto i = static_cast<std::size_t>(which);
  if (rejected) ++result_.rejected_updates.at(i);
  rejected_in_a_row_.at(i) = rejected ? rejected_in_a_row_.at(i) + 1 : 0;
  if (rejected_in_a_row_.at(i) >= kMaxRejected) {  // open for a new convergence
    open_until_.at(i) = k + kGateSettle;
    rejected_in_a_row_.at(i) = 0;
  }
}

// Eq. 5.49-5.67 for Estimator 2 (two_axis) or 3 at sample k.
void NetTractionEstimator::wheel_force_step(std::size_t k, WheelForceFilter& filter, bool two_axis,
                                            FilterTrack& track) {
  const auto r = static_cast<Eigen::Index>(k);
  if (k > 0) {
    const nt::SensorSample& s = samples_[k];
    const nt::GeneralState& x1 = general_.x;
    nt::WheelForceMeasurement y;
    y.head<3>() = contact_angles_;
    y.segment<3>(3) = s.load;
    if (two_axis) {
      y.tail<3>() = s.perpendicular;
    } else if (o_.bogie_split_shape) {
      y.tail<3>() = nt::perpendicular_from_net_forces(rover_, x1, s.load, contact_angles_, o_.bogie_split_shape);
    } else {
      y.tail<3>() = nt::perpendicular_from_net_forces(rover_, x1, s.load);  // Eq. 5.66
    }
    nt::WheelForceMeasurement R = two_axis ? r2_ : r3_;
    for (int i = 0; i < 3; ++i) {
      if (std::isnan(y(i)) || std::abs(s.load(i)) < kAirborneLoad) {  // standing, or off the ground
        y(i) = filter.x(i);
        R(i) = kUnavailable;
      }
    }
    force_measurement_.set_sensor_angles(nt::sensor_angles(x1(gen::kPitch), x1(gen::kBogie)));
    const auto h = [this](const nt::WheelForceState& x, nt::WheelForceMeasurement& out) { force_measurement_(x, out); };
    filter.P.diagonal() += q2_;  // Eq. 5.50-5.52: x + w through the identity, as Q after it
    const int which = two_axis ? 1 : 2;
    filter.gate = gate(which, k, static_cast<int>((R.array() < kUnavailable).count()));
    filter.update(h, R, y);  // Eq. 5.50-5.52, 5.61: the identity process model
    count_rejection(which, k, filter.rejected);
  }
  track.state.row(r) = filter.x.transpose();
  track.sigma.row(r) = filter.P.diagonal().cwiseMax(0.0).cwiseSqrt().transpose();
}

void NetTractionEstimator::write_streams() {
  const FilterTrack& g = result_.general;
  const FilterTrack& w = result_.wheel_forces();
  const auto column = [](const Eigen::MatrixXd& m, int c) {
    std::vector<double> v(static_cast<std::size_t>(m.rows()));
    for (Eigen::Index k = 0; k < m.rows(); ++k) v[static_cast<std::size_t>(k)] = m(k, c);
    return v;
  };
  log::Stream wheels(net_traction_streams::kWheels, result_.time);
  const struct {
    const char* name;
    const char* unit;
    const FilterTrack* track;
    int first;
  } quantities[] = {
      {"normal_load_", "N", &w, wf::kNormalLoad},
      {"drawbar_pull_", "N", &w, wf::kDrawbarPull},
      {"resistive_torque_", "N*m", &g, gen::kResistiveTorque},
      {"slip_", "1", &g, gen::kSlip},
      {"contact_angle_", "rad", &w, wf::kContactAngle},
  };
  for (const auto& q : quantities) {
    for (int i = 0; i < 3; ++i) {
      wheels.add_channel(index_name(q.name, i), q.unit, column(q.track->state, q.first + i));
      wheels.add_channel(std::string(q.name) + "sigma_" + std::to_string(i + 1), q.unit,
                         column(q.track->sigma, q.first + i), "1-sigma");
    }
  }
  for (int i = 0; i < 3; ++i) {
    wheels.add_channel(index_name("wheel_acceleration_", i), "rad/s^2", column(result_.wheel_acceleration, i),
                       "Eq. 5.24");
  }
  for (int i = 0; i < 3; ++i) {
    wheels.add_channel(index_name("path_x_", i), "m", column(result_.wheel_x, i),
                       "wheel centre's x, dead-reckoned from wheel 1 at 0");
  }
  result_.estimates.add_stream(std::move(wheels));
  log::Stream body(net_traction_streams::kBody, result_.time);
  const struct {
    const char* name;
    const char* unit;
    int index;
  } states[] = {{"pitch", "rad", gen::kPitch},
                {"bogie_angle", "rad", gen::kBogie},
                {"pitch_rate", "rad/s", gen::kPitchRate},
                {"forward_speed", "m/s", gen::kForwardSpeed},
                {"net_moment_body", "N*m", gen::kMomentBody},
                {"net_moment_bogie", "N*m", gen::kMomentBogie},
                {"net_force_x", "N", gen::kForceX},
                {"net_force_z", "N", gen::kForceZ}};
  for (const auto& s : states) {
    body.add_channel(s.name, s.unit, column(g.state, s.index));
    body.add_channel(std::string(s.name) + "_sigma", s.unit, column(g.sigma, s.index), "1-sigma");
  }
  result_.estimates.add_stream(std::move(body));
  result_.estimates.metadata.extra["net_traction/force_sensors"] = force_sensors_name(result_.force_sensors);
}

NetTractionErrors tracking_errors(const log::Log& lg, const NetTractionResult& r, const FilterTrack& w,
                                  double settle_seconds) {
  NetTractionErrors e;
  const log::Stream* truth = lg.find_stream("truth/wheels");
  if (truth == nullptr || r.time.empty() || w.empty()) return e;
  const struct {
    const char* name;
    const FilterTrack* track;
    int first;
    Eigen::Vector3d* out;
  } quantities[] = {{"normal_load_", &w, wf::kNormalLoad, &e.normal_load},
                    {"drawbar_pull_", &w, wf::kDrawbarPull, &e.drawbar_pull},
                    {"resistive_torque_", &r.general, gen::kResistiveTorque, &e.resistive_torque},
                    {"slip_", &r.general, gen::kSlip, &e.slip},
                    {"contact_angle_", &w, wf::kContactAngle, &e.contact_angle}};
  for (const auto& q : quantities) {
    for (int i = 0; i < 3; ++i) {
      const std::string channel = index_name(q.name, i);
      if (truth->find_channel(channel) == nullptr) return NetTractionErrors{};
      const std::vector<double> t = truth->interpolate(channel, r.time);
      double sum = 0;
      std::size_t n = 0;
      for (std::size_t k = 0; k < t.size(); ++k) {
        if (r.time[k] - r.time.front() < settle_seconds || !std::isfinite(t[k])) continue;
        const double d = q.track->state(static_cast<Eigen::Index>(k), q.first + i) - t[k];
        sum += d * d;
        ++n;
      }
      (*q.out)(i) = n > 0 ? std::sqrt(sum / static_cast<double>(n)) : NAN;
      e.samples = n;
    }
  }
  e.has_truth = e.samples > 0;
  return e;
}

NetTractionResult run_net_traction(const log::Log& log, const nt::RoverConstants& rover,
                                   const NetTractionOptions& options) {
  return NetTractionEstimator(log, rover, options).run();
}

}  // namespace roverlab::estimation

#include "core/simulation/skid_steer_scenario.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "core/common/error.h"
#include "core/models/ins.h"
#include "core/models/slip.h"

namespace roverlab::simulation {

SkidSteerScenario default_slip_scenario(unsigned seed) {
  SkidSteerScenario s;
  s.seed = seed;
  // duration, speed, yaw rate, slip. Driving on loose soil always slips a
  // little: the "nominal" runs, and braking into a stop, slip 6 % (low
  // class); a stop segment's slip applies only while the rover still moves.
  // Two stretches of firm ground (slip 0) give the no-slip class moving samples.
  const double base = 0.06;
  s.segments = {
      {5.0, 0.0, 0.0, 0.0},   {15.0, 0.5, 0.0, base},  {3.0, 0.0, 0.0, base},   {8.0, 0.5, 0.0, 0.0},
      {3.0, 0.0, 0.0, 0.0},   {8.0, 0.5, 0.05, base},  {6.0, 0.5, 0.0, 0.12},   {6.0, 0.5, 0.0, base},
      {3.0, 0.0, 0.0, base},  {6.0, 0.5, 0.0, 0.3},    {6.0, 0.5, -0.05, base}, {5.0, 0.5, 0.0, 0.15},
      {3.0, 0.0, 0.0, base},  {5.0, 0.4, 0.0, 0.55},   {8.0, 0.5, 0.0, base},   {3.0, 0.0, 0.0, base},
      {4.0, 0.2, 0.0, 0.85},  {10.0, 0.5, 0.03, base}, {6.0, 0.5, 0.0, 0.08},   {3.0, 0.0, 0.0, base},
      {12.0, 0.5, 0.0, base}, {3.0, 0.0, 0.0, base},   {10.0, 0.5, -0.03, 0.0}, {5.0, 0.0, 0.0, 0.0},
  };
  return s;
}

SkidSteerScenario loop_slip_scenario(unsigned seed) {
  SkidSteerScenario s;
  s.seed = seed;
  s.heading = 2.3;  // rad: south-east
  s.gps_sigma = 3.0;
  const double turn = 0.5, quarter = 0.5 * M_PI / turn;  // rad/s, s
  s.segments = {{5.0, 0.0, 0.0, 0.0}, {quarter, 0.0, -turn, 0.0}, {2.0, 0.0, 0.0, 0.0}};
  // Each side: 25 s at 0.8 m/s with the side's slip and one episode, a stop, a
  // quarter turn in place (clockwise), a pause at rest.
  const double steady[4] = {0.0, 0.04, 0.0, 0.04};
  const double episode[8] = {0.12, 0.3, 0.55, 0.85, 0.3, 0.12, 0.85, 0.55};
  for (int side = 0; side < 8; ++side) {
    const double base = steady[side % 4];
    const double burst_speed = episode[side] > 0.7 ? 0.3 : 0.8;  // a deep episode slows the rover
    s.segments.push_back({10.0, 0.8, 0.0, base});
    s.segments.push_back({4.0, burst_speed, 0.0, episode[side]});
    s.segments.push_back({9.0, 0.8, 0.0, base});
    s.segments.push_back({2.5, 0.0, 0.0, base});
    s.segments.push_back({quarter, 0.0, turn, 0.0});
    s.segments.push_back({1.5, 0.0, 0.0, 0.0});
  }
  return s;
}

void set_effect(SkidSteerScenario& s, const std::string& name, double value) {
  if (!std::isfinite(value)) throw DataError("effect " + name + ": value is not a number");
  if (name == "left-radius-scale") {
    s.left_radius_scale = value;
  } else if (name == "right-radius-scale") {
    s.right_radius_scale = value;
  } else if (name == "radius-scale") {
    s.left_radius_scale = s.right_radius_scale = value;
  } else if (name == "turning-track-factor") {
    s.turning_track_factor = value;
  } else if (name == "wheel-time-offset") {
    if (!(std::abs(value) <= 1)) throw DataError("effect wheel-time-offset (s) must be -1..1");
    s.wheel_time_offset = value;
  } else if (name == "slip") {
    // A switch: slip episodes on (1) or firm ground (0).
    if (value != 0.0 && value != 1.0) throw DataError("effect slip must be 0 (firm ground) or 1 (slip episodes)");
    s.slip = value != 0.0;
  } else {
    throw DataError("unknown effect '" + name +
                    "' (left-radius-scale, right-radius-scale, radius-scale, turning-track-factor, "
                    "wheel-time-offset, slip)");
  }
  if ((name.find("scale") != std::string::npos || name == "turning-track-factor") && !(value > 0.1 && value < 10.0)) {
    throw DataError("effect " + name + " = " + std::to_string(value) + ": outside 0.1 .. 10");
  }
}

namespace {

// The drive at the IMU rate: IMU samples, truth and wheel angles.
struct DriveSamples {
  std::vector<double> t, fx, fy, fz, wx, wy, wz;
  std::vector<double> east, north, yaw, speed, slip, left_angle, right_angle;
};

// The generator's steps: turn-on biases, the drive integrated segment by
// segment, then the streams at their own rates. One random stream in this
// order (biases, IMU noise, GPS noise), so a seed gives one log.
class SkidSteerSimulator {
 public:
  explicit SkidSteerSimulator(const SkidSteerScenario& scenario)
      : sc_(scenario), rng_(scenario.seed), dt_(1.0 / scenario.imu_rate) {}
  log::Log run();

 private:
  void draw_biases();
  void drive(const DriveSegment& seg);
  void write_metadata(log::Log& out) const;
  void add_imu_and_truth_streams(log::Log& out) const;
  void add_wheel_and_slip_streams(log::Log& out) const;
  void add_gps_stream(log::Log& out);
  std::size_t every(double rate) const { return static_cast<std::size_t>(std::llround(sc_.imu_rate / rate)); }

  const SkidSteerScenario& sc_;
  std::mt19937 rng_;
  std::normal_distribution<double> unit_{0.0, 1.0};
  const double dt_;
  Eigen::Vector3d ba_, bg_;  // accelerometer and gyro biases
  DriveSamples d_;
  // Motion state: speed, heading, position, time, left and right wheel angle.
  double v_ = 0.0, psi_ = 0.0, e_ = 0.0, n_ = 0.0, time_ = 0.0, al_ = 0.0, ar_ = 0.0;
};

log::Log SkidSteerSimulator::run() {
  draw_biases();
  psi_ = sc_.heading;
  for (const auto& seg : sc_.segments) drive(seg);
  log::Log out;
  write_metadata(out);
  add_imu_and_truth_streams(out);
  // Wheels, GPS and slip truth at their own rates, sampled from the IMU-rate truth.
  add_wheel_and_slip_streams(out);
  add_gps_stream(out);
  return out;
}

void SkidSteerSimulator::draw_biases() {
  std::bernoulli_distribution coin(0.5);
  for (int k = 0; k < 3; ++k) {
    ba_[k] = (coin(rng_) ? 1.0 : -1.0) * sc_.accel_bias;
    bg_[k] = (coin(rng_) ? 1.0 : -1.0) * sc_.gyro_bias;
  }
}

void SkidSteerSimulator::drive(const DriveSegment& seg) {
  const double g = estimation::gravity_down(sc_.latitude, sc_.height);
  const double r = sc_.rover.wheel_radius, track = sc_.rover.track, dt = dt_;
  const auto steps = static_cast<long>(std::llround(seg.duration * sc_.imu_rate));
  for (long k = 0; k < steps; ++k) {
    const double dv = seg.speed - v_;
    const double a = std::clamp(dv / dt, -sc_.max_acceleration, sc_.max_acceleration);
    // A stop segment with a yaw rate brakes while turning, then turns in place.
    const double yaw_rate = seg.yaw_rate;
    // IMU at this sample: specific force f = a_b - g_b on level ground (FRD body axes).
    d_.t.push_back(time_);
    d_.fx.push_back(a + ba_.x() + sc_.accel_vrw / std::sqrt(dt) * unit_(rng_));
    d_.fy.push_back(v_ * yaw_rate + ba_.y() + sc_.accel_vrw / std::sqrt(dt) * unit_(rng_));
    d_.fz.push_back(-g + ba_.z() + sc_.accel_vrw / std::sqrt(dt) * unit_(rng_));
    d_.wx.push_back(bg_.x() + sc_.gyro_arw / std::sqrt(dt) * unit_(rng_));
    d_.wy.push_back(bg_.y() + sc_.gyro_arw / std::sqrt(dt) * unit_(rng_));
    d_.wz.push_back(yaw_rate + bg_.z() + sc_.gyro_arw / std::sqrt(dt) * unit_(rng_));
    d_.east.push_back(e_);
    d_.north.push_back(n_);
    d_.yaw.push_back(psi_);
    d_.speed.push_back(v_);
    const double seg_slip = sc_.slip ? seg.slip : 0.0;
    d_.slip.push_back(v_ > 1e-6 ? seg_slip : 0.0);
    d_.left_angle.push_back(al_);
    d_.right_angle.push_back(ar_);
    // Wheels: ground speed of each side, turned faster by slip s (v = r w (1 - s)).
    const double keep = 1.0 - (v_ > 1e-6 ? seg_slip : 0.0);
    const double half = 0.5 * yaw_rate * track * sc_.turning_track_factor;
    al_ += (v_ + half) / (r * sc_.left_radius_scale * keep) * dt;
    ar_ += (v_ - half) / (r * sc_.right_radius_scale * keep) * dt;
    // Motion over the step (exact for constant acceleration and yaw rate, to second order).
    const double v_next = v_ + a * dt;
    const double mid_psi = psi_ + 0.5 * yaw_rate * dt;
    const double dist = 0.5 * (v_ + v_next) * dt;
    e_ += dist * std::sin(mid_psi);
    n_ += dist * std::cos(mid_psi);
    psi_ += yaw_rate * dt;
    v_ = v_next;
    time_ += dt;
  }
}

void SkidSteerSimulator::write_metadata(log::Log& out) const {
  out.metadata.rover_id = "wvu_pathfinder";
  out.metadata.description = "simulated skid-steer drive with slip episodes (RoverLab kinematic generator)";
  out.metadata.extra["truth/generator"] = "skid-steer-slip";
  out.metadata.extra["truth/seed"] = std::to_string(sc_.seed);
  for (int k = 0; k < 3; ++k) {
    const char axis[2] = {static_cast<char>('x' + k), 0};
    out.metadata.extra[std::string("truth/gyro_bias_") + axis] = std::to_string(bg_[k]);
    out.metadata.extra[std::string("truth/accel_bias_") + axis] = std::to_string(ba_[k]);
  }
  auto effect = [&](const char* name, double value, double neutral) {
    if (value != neutral) out.metadata.extra[std::string("truth/effect/") + name] = std::to_string(value);
  };
  effect("left-radius-scale", sc_.left_radius_scale, 1.0);
  effect("right-radius-scale", sc_.right_radius_scale, 1.0);
  effect("turning-track-factor", sc_.turning_track_factor, 1.0);
  effect("wheel-time-offset", sc_.wheel_time_offset, 0.0);
  if (!sc_.slip) out.metadata.extra["truth/effect/slip"] = "0";
}

void SkidSteerSimulator::add_imu_and_truth_streams(log::Log& out) const {
  log::Stream imu("imu", d_.t);
  imu.add_channel("specific_force_x", "m/s^2", d_.fx);
  imu.add_channel("specific_force_y", "m/s^2", d_.fy);
  imu.add_channel("specific_force_z", "m/s^2", d_.fz);
  imu.add_channel("angular_rate_x", "rad/s", d_.wx);
  imu.add_channel("angular_rate_y", "rad/s", d_.wy);
  imu.add_channel("angular_rate_z", "rad/s", d_.wz);
  out.add_stream(std::move(imu));
  log::Stream truth("truth/motion", d_.t);
  truth.add_channel("east", "m", d_.east);
  truth.add_channel("north", "m", d_.north);
  truth.add_channel("yaw", "rad", d_.yaw);
  truth.add_channel("forward_speed", "m/s", d_.speed);
  out.add_stream(std::move(truth));
}

void SkidSteerSimulator::add_wheel_and_slip_streams(log::Log& out) const {
  std::vector<double> tw, tt, fl, fr, rl, rr, s, c;
  for (std::size_t i = 0; i < d_.t.size(); i += every(sc_.wheel_rate)) {
    tw.push_back(d_.t[i] + sc_.wheel_time_offset);
    tt.push_back(d_.t[i]);
    fl.push_back(d_.left_angle[i]);
    rl.push_back(d_.left_angle[i]);
    fr.push_back(d_.right_angle[i]);
    rr.push_back(d_.right_angle[i]);
    s.push_back(d_.slip[i]);
    c.push_back(static_cast<double>(estimation::classify_slip(d_.slip[i])));
  }
  log::Stream w("wheels", tw);
  w.add_channel("angle_FL", "rad", fl);
  w.add_channel("angle_FR", "rad", fr);
  w.add_channel("angle_RL", "rad", rl);
  w.add_channel("angle_RR", "rad", rr);
  out.add_stream(std::move(w));
  log::Stream ts("truth/slip", tt);
  ts.add_channel("slip_ratio", "1", s);
  ts.add_channel("slip_class", "1", c);
  out.add_stream(std::move(ts));
}

void SkidSteerSimulator::add_gps_stream(log::Log& out) {
  std::vector<double> tg, ge, gn, gu, lat, lon, h;
  const double rn = estimation::meridian_radius(sc_.latitude) + sc_.height;
  const double re = estimation::transverse_radius(sc_.latitude) + sc_.height;
  for (std::size_t i = 0; i < d_.t.size(); i += every(sc_.gps_rate)) {
    tg.push_back(d_.t[i]);
    ge.push_back(d_.east[i] + sc_.gps_sigma * unit_(rng_));
    gn.push_back(d_.north[i] + sc_.gps_sigma * unit_(rng_));
    gu.push_back(sc_.gps_sigma * unit_(rng_));
    lat.push_back(sc_.latitude + d_.north[i] / rn);
    lon.push_back(sc_.longitude + d_.east[i] / (re * std::cos(sc_.latitude)));
    h.push_back(sc_.height);
  }
  log::Stream gps("gps", tg);
  gps.add_channel("east", "m", ge);
  gps.add_channel("north", "m", gn);
  gps.add_channel("up", "m", gu);
  gps.add_channel("latitude", "rad", lat);
  gps.add_channel("longitude", "rad", lon);
  gps.add_channel("height", "m", h);
  out.add_stream(std::move(gps));
}

}  // namespace

log::Log simulate_skid_steer(const SkidSteerScenario& sc) {
  if (sc.segments.empty()) throw DataError("skid-steer scenario without segments");
  return SkidSteerSimulator(sc).run();
}

}  // namespace roverlab::simulation

#include "core/simulation/flying_rover.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <utility>

#include "core/common/error.h"

namespace roverlab::simulation {

namespace {

int need(const kinematics::RoverModel& m, const std::string& joint) {
  const int j = m.joint_index(joint);
  if (j < 0) throw DataError("rover " + m.name + " has no joint '" + joint + "'");
  return j;
}

// Raised-cosine bump of height h and duration T starting at t0: height and rate.
std::pair<double, double> bump(double t, double t0, double T, double h) {
  if (t < t0 || t > t0 + T) return {0.0, 0.0};
  const double w = 2.0 * M_PI / T;
  return {0.5 * h * (1.0 - std::cos(w * (t - t0))), 0.5 * h * w * std::sin(w * (t - t0))};
}

}  // namespace

void check_steering_manoeuvre(const FlyingRoverScenario& s) {
  // Values as given, to ten digits (45.0000001 is not "45.000000"; 1e300 not 301 digits).
  const auto shown = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.10g", v);
    return std::string(text);
  };
  if (std::isnan(s.turn_radius) || !(std::abs(s.turn_radius) >= 1.0))
    throw DataError("turn radius " + shown(s.turn_radius) + " m: |R| must be at least 1 m (or infinite)");
  if (!(std::abs(s.slip_angle) <= M_PI / 4))
    throw DataError("slip angle " + shown(s.slip_angle * 180 / M_PI) + " deg: must be within +-45 deg");
  if (!(s.slip_angle_from >= 0 && s.slip_angle_from < s.duration))
    throw DataError("slip angle from " + shown(s.slip_angle_from) + " s: must be within the run (0 to " +
                    shown(s.duration) + " s)");
}

std::vector<std::string> flying_rover_scenarios() {
  return {"fl-bogie-rotation", "rear-bogie-rotation", "bump-crossing", "flat-turn"};
}

FlyingRoverScenario flying_rover_scenario(const std::string& name, const kinematics::RoverModel& m) {
  FlyingRoverScenario s;
  s.name = name;
  const std::size_t nq = m.joints.size();
  if (name == "fl-bogie-rotation" || name == "rear-bogie-rotation") {
    const int j = need(m, name == "fl-bogie-rotation" ? "bogie_FL" : "bogie_R");
    s.duration = 30.0;
    s.joints = [j, nq](double t, std::vector<double>& q, std::vector<double>& qd) {
      q.assign(nq, 0.0);
      qd.assign(nq, 0.0);
      const double rate = 0.06, t0 = 5.0, t1 = 15.0;  // seed 000 section 6.3: 0.06 rad/s for 10 s
      q[static_cast<std::size_t>(j)] = rate * std::clamp(t - t0, 0.0, t1 - t0);
      qd[static_cast<std::size_t>(j)] = (t >= t0 && t < t1) ? rate : 0.0;
    };
  } else if (name == "bump-crossing") {
    // The left wheels cross an 8 cm, 30 cm long bump at 5 cm/s; the side
    // bogie and the rear bogie turn as the wheels' height difference
    // says; every wheel steers (front and rear opposite, 0.15 rad, 20 s period).
    const int bfl = need(m, "bogie_FL"), br = need(m, "bogie_R");
    std::vector<int> steer;
    for (const char* w : {"steer_FL", "steer_ML", "steer_RL", "steer_RR", "steer_MR", "steer_FR"})
      steer.push_back(need(m, w));
    s.duration = 45.0;
    s.speed = 0.05;
    s.joints = [=](double t, std::vector<double>& q, std::vector<double>& qd) {
      q.assign(nq, 0.0);
      qd.assign(nq, 0.0);
      const double v = 0.05, T = 0.3 / v, H = 0.08;
      const auto [h_fl, dh_fl] = bump(t, 5.0, T, H);
      const auto [h_ml, dh_ml] = bump(t, 5.0 + 0.64 / v, T, H);
      const auto [h_rl, dh_rl] = bump(t, 5.0 + 1.35 / v, T, H);
      // Side bogie: the pair FL-ML 0.64 m apart; rear bogie: RL-RR 1.2 m apart.
      const double a = (h_fl - h_ml) / 0.64, da = (dh_fl - dh_ml) / 0.64;
      q[static_cast<std::size_t>(bfl)] = std::atan(a);
      qd[static_cast<std::size_t>(bfl)] = da / (1.0 + a * a);
      const double b = h_rl / 1.2, db = dh_rl / 1.2;
      q[static_cast<std::size_t>(br)] = std::atan(b);
      qd[static_cast<std::size_t>(br)] = db / (1.0 + b * b);
      const double w = 2.0 * M_PI / 20.0, amp = 0.15;
      const double sign[6] = {1, 0, -1, -1, 0, 1};  // FL ML RL RR MR FR
      for (int k = 0; k < 6; ++k) {
        q[static_cast<std::size_t>(steer[static_cast<std::size_t>(k)])] = sign[k] * amp * std::sin(w * t);
        qd[static_cast<std::size_t>(steer[static_cast<std::size_t>(k)])] = sign[k] * amp * w * std::cos(w * t);
      }
    };
  } else if (name == "flat-turn") {
    // No joint moves of its own: the steering manoeuvre alone (a 1 m left
    // turn unless the caller sets turn_radius; slip_angle 0 unless set).
    s.duration = 30.0;
    s.turn_radius = 1.0;
    s.joints = [nq](double, std::vector<double>& q, std::vector<double>& qd) {
      q.assign(nq, 0.0);
      qd.assign(nq, 0.0);
    };
  } else {
    std::string known;
    for (const auto& n : flying_rover_scenarios()) known += (known.empty() ? "" : ", ") + n;
    throw DataError("unknown scenario '" + name + "' (" + known + ")");
  }
  return s;
}

namespace {

// The variance of joint j's angle (or rate) in the rover's noise table:
// bogie joints first in the table, then the steering joints per wheel.
double joint_variance(const kinematics::RoverModel& m, std::size_t j, bool of_rate) {
  if (m.noise.bogie_angle.empty()) return 1e-12;  // no noise table
  std::size_t b = 0;
  for (std::size_t k = 0; k < m.joints.size(); ++k) {
    if (m.joints[k].rfind("bogie", 0) != 0) continue;
    if (k == j) return of_rate ? m.noise.bogie_rate[b] : m.noise.bogie_angle[b];
    ++b;
  }
  for (std::size_t w = 0; w < m.wheels.size(); ++w) {
    if (m.wheels[w].steer_joint == static_cast<int>(j)) return of_rate ? m.noise.steer_rate[w] : m.noise.steer_angle[w];
  }
  return 1e-12;
}

// The flying rover sampled at the scenario's rate: the sensors with the noise
// of Table 6.1 and the truth from the kinematics, then the log's streams.
class FlyingRoverSimulator {
 public:
  FlyingRoverSimulator(const kinematics::RoverModel& m, const FlyingRoverScenario& sc)
      : m_(m),
        sc_(sc),
        nq_(m.joints.size()),
        nw_(m.wheels.size()),
        n_(static_cast<std::size_t>(std::llround(sc.duration * sc.rate)) + 1),
        rng_(sc.seed),
        t_(n_),
        imu_(6, std::vector<double>(n_)),
        joints_(2 * nq_, std::vector<double>(n_)),
        wheel_rate_(nw_, std::vector<double>(n_)),
        body_(6, std::vector<double>(n_, 0.0)),
        truth_(3 * nw_, std::vector<double>(n_)) {
    plan_manoeuvre();
  }

  log::Log run() {
    for (std::size_t i = 0; i < n_; ++i) sample(i);
    return streams();
  }

 private:
  double noisy(double value, double variance) { return sc_.noise ? value + std::sqrt(variance) * unit_(rng_) : value; }
  void plan_manoeuvre();
  void sample(std::size_t i);
  log::Log streams() const;

  const kinematics::RoverModel& m_;
  const FlyingRoverScenario& sc_;
  const std::size_t nq_, nw_, n_;  // joints, wheels, samples
  std::mt19937 rng_;
  std::normal_distribution<double> unit_{0.0, 1.0};
  std::vector<double> t_, q_, qd_;
  double yaw_rate_ = 0;  // rad/s, the turn's
  // Per joint: the turn's steering offset (rad) and d heading / d angle;
  // per wheel: its speed along its plane without a slip angle (m/s).
  std::vector<double> steer_offset_, steer_slope_, roll_speed_;
  std::vector<std::vector<double>> imu_, joints_, wheel_rate_, body_, truth_;
};

// The steering manoeuvre (FlyingRoverScenario::turn_radius): each steering
// joint's offset that points its wheel's drive frame along the wheel's
// travel in the turn (Newton on the heading, the drive frame may sit off the
// steering axis), the heading's slope in the joint angle (the slip angle's
// share, slip_angle_at) and each wheel's speed along its plane. Straight:
// no offset and the body's speed (section 6.3).
void FlyingRoverSimulator::plan_manoeuvre() {
  yaw_rate_ = std::isfinite(sc_.turn_radius) ? sc_.speed / sc_.turn_radius : 0.0;
  steer_offset_.assign(nq_, 0.0);
  steer_slope_.assign(nq_, 1.0);
  roll_speed_.assign(nw_, sc_.speed);
  if (yaw_rate_ == 0.0 && sc_.slip_angle == 0.0) return;
  std::vector<double> q0, qd0;
  sc_.joints(0.0, q0, qd0);
  const Eigen::Vector3d v(sc_.speed, 0.0, 0.0), omega(0.0, 0.0, yaw_rate_);
  const auto heading_and_travel = [&](int w, std::vector<double> q) {
    for (std::size_t j = 0; j < nq_; ++j) q[j] += steer_offset_[j];
    const auto p = kinematics::wheel_pose<double>(m_, w, q.data(), 0.0, 0.0, kinematics::WheelFrame::drive);
    const Eigen::Vector3d travel = v + omega.cross(p.r);
    return std::pair{std::atan2(p.R(1, 0), p.R(0, 0)), std::atan2(travel.y(), travel.x())};
  };
  for (std::size_t w = 0; w < nw_; ++w) {
    const int wheel = static_cast<int>(w), s = m_.wheels[w].steer_joint;
    for (int iteration = 0; s >= 0 && iteration < 4; ++iteration) {
      const auto [heading, travel] = heading_and_travel(wheel, q0);
      std::vector<double> nudged = q0;
      nudged[static_cast<std::size_t>(s)] += 1e-6;
      const double slope = (heading_and_travel(wheel, nudged).first - heading) / 1e-6;
      steer_slope_[static_cast<std::size_t>(s)] = slope;
      steer_offset_[static_cast<std::size_t>(s)] += std::remainder(travel - heading, 2 * M_PI) / slope;
    }
    std::vector<double> q = q0;
    for (std::size_t j = 0; j < nq_; ++j) q[j] += steer_offset_[j];
    const Eigen::Vector3d vd = kinematics::wheel_velocity<double>(m_, wheel, q.data(), qd0.data(), v, omega, 0.0, 0.0,
                                                                  kinematics::WheelFrame::drive);
    roll_speed_[w] = kinematics::wheel_angles(vd).speed_in_plane;
  }
}

// The slip angle at t and its rate: from the start, or ramped in over
// FlyingRoverScenario::kSlipAngleRamp seconds from slip_angle_from.
std::pair<double, double> slip_angle_at(const FlyingRoverScenario& sc, double t) {
  if (!(sc.slip_angle_from > 0)) return {sc.slip_angle, 0.0};
  const double u = (t - sc.slip_angle_from) / FlyingRoverScenario::kSlipAngleRamp;
  if (u <= 0) return {0.0, 0.0};
  if (u >= 1) return {sc.slip_angle, 0.0};
  return {sc.slip_angle * u, sc.slip_angle / FlyingRoverScenario::kSlipAngleRamp};
}

// Sample i: a level body at constant speed in body axes, so the IMU reads
// gravity and, in a turn, the yaw rate and the centripetal force.
void FlyingRoverSimulator::sample(std::size_t i) {
  const Eigen::Vector3d v(sc_.speed, 0.0, 0.0), omega(0.0, 0.0, yaw_rate_);
  t_[i] = static_cast<double>(i) / sc_.rate;
  sc_.joints(t_[i], q_, qd_);
  // Seed 000 section 5.2: beta = atan(v . y_c / v . x_c), the travel's angle
  // left of the heading, so the heading turns by -beta from the travel.
  const auto [beta, beta_rate] = slip_angle_at(sc_, t_[i]);
  for (std::size_t j = 0; j < nq_; ++j) q_[j] += steer_offset_[j];
  for (const auto& wheel : m_.wheels) {
    if (wheel.steer_joint < 0 || (beta_rate == 0.0 && beta == 0.0)) continue;
    const auto s = static_cast<std::size_t>(wheel.steer_joint);
    q_[s] -= beta / steer_slope_[s];
    qd_[s] -= beta_rate / steer_slope_[s];
  }
  const Eigen::Vector3d specific_force = omega.cross(v) + Eigen::Vector3d(0.0, 0.0, sc_.gravity);
  for (int k = 0; k < 3; ++k) {
    imu_[static_cast<std::size_t>(k)][i] = noisy(omega[k], m_.noise.gyro[k]);
    imu_[static_cast<std::size_t>(3 + k)][i] = noisy(specific_force[k], m_.noise.accelerometer[k]);
  }
  for (std::size_t j = 0; j < nq_; ++j) {
    joints_[j][i] = noisy(q_[j], joint_variance(m_, j, false));
    joints_[nq_ + j][i] = noisy(qd_[j], joint_variance(m_, j, true));
  }
  body_[0][i] = sc_.speed;
  body_[5][i] = std::remainder(yaw_rate_ * t_[i], 2 * M_PI);
  for (std::size_t w = 0; w < nw_; ++w) {
    const double rate = roll_speed_[w] * std::cos(beta) / m_.wheel_radius;  // rolls without slip (Eq. 5.3, s = 0)
    wheel_rate_[w][i] = noisy(rate, m_.noise.wheel_rate.empty() ? 1e-12 : m_.noise.wheel_rate[w]);
    const Eigen::Vector3d vd = kinematics::wheel_velocity<double>(m_, static_cast<int>(w), q_.data(), qd_.data(), v,
                                                                  omega, 0.0, 0.0, kinematics::WheelFrame::drive);
    const kinematics::WheelAngles a = kinematics::wheel_angles(vd);
    truth_[w][i] = 1.0 - a.speed_in_plane / (rate * m_.wheel_radius);  // slip against v . x_c (section 5.3)
    truth_[nw_ + w][i] = a.contact;
    truth_[2 * nw_ + w][i] = a.side_slip;
  }
}

log::Log FlyingRoverSimulator::streams() const {
  log::Log out;
  out.metadata.rover_id = m_.name;
  out.metadata.description =
      "hypothetical flying-rover scenario '" + sc_.name + "' (seed 000 sections 6.3-6.4; RoverLab)";
  out.metadata.extra["truth/generator"] = "flying-rover";
  out.metadata.extra["truth/scenario"] = sc_.name;
  out.metadata.extra["truth/seed"] = std::to_string(sc_.seed);
  if (std::isfinite(sc_.turn_radius)) out.metadata.extra["truth/turn_radius_m"] = std::to_string(sc_.turn_radius);
  if (sc_.slip_angle != 0.0) out.metadata.extra["truth/slip_angle_deg"] = std::to_string(sc_.slip_angle * 180.0 / M_PI);
  if (sc_.slip_angle != 0.0 && sc_.slip_angle_from > 0)
    out.metadata.extra["truth/slip_angle_from_s"] = std::to_string(sc_.slip_angle_from);
  {
    log::Stream s("imu", t_);
    const char* names[6] = {"angular_rate_x",   "angular_rate_y",   "angular_rate_z",
                            "specific_force_x", "specific_force_y", "specific_force_z"};
    for (std::size_t k = 0; k < 6; ++k) {
      s.add_channel(names[k], k < 3 ? "rad/s" : "m/s^2", imu_[k], "rover body axes (x forward, y left, z up)");
    }
    out.add_stream(std::move(s));
  }
  {
    log::Stream s("joints", t_);
    for (std::size_t j = 0; j < nq_; ++j) s.add_channel(m_.joints[j], "rad", joints_[j]);
    for (std::size_t j = 0; j < nq_; ++j) s.add_channel(m_.joints[j] + "_rate", "rad/s", joints_[nq_ + j]);
    out.add_stream(std::move(s));
  }
  {
    log::Stream s("wheels", t_);
    for (std::size_t w = 0; w < nw_; ++w) s.add_channel("rate_" + m_.wheels[w].name, "rad/s", wheel_rate_[w]);
    out.add_stream(std::move(s));
  }
  {
    log::Stream s("truth/body", t_);
    const char* names[6] = {"velocity_x", "velocity_y", "velocity_z", "roll", "pitch", "yaw"};
    for (std::size_t k = 0; k < 6; ++k) s.add_channel(names[k], k < 3 ? "m/s" : "rad", body_[k]);
    out.add_stream(std::move(s));
  }
  log::Stream s("truth/wheels", t_);
  for (std::size_t w = 0; w < nw_; ++w) s.add_channel("slip_" + m_.wheels[w].name, "1", truth_[w]);
  for (std::size_t w = 0; w < nw_; ++w) s.add_channel("contact_angle_" + m_.wheels[w].name, "rad", truth_[nw_ + w]);
  for (std::size_t w = 0; w < nw_; ++w) s.add_channel("side_slip_" + m_.wheels[w].name, "rad", truth_[2 * nw_ + w]);
  out.add_stream(std::move(s));
  return out;
}

}  // namespace

log::Log simulate_flying_rover(const kinematics::RoverModel& m, const FlyingRoverScenario& sc) {
  if (!sc.joints) throw DataError("scenario without joint motion");
  check_steering_manoeuvre(sc);
  return FlyingRoverSimulator(m, sc).run();
}

}  // namespace roverlab::simulation

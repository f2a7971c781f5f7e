#include "core/simulation/flying_rover.h"

#include <cmath>
#include <random>

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

std::vector<std::string> flying_rover_scenarios() { return {"fl-bogie-rotation", "rear-bogie-rotation", "bump-crossing"}; }

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
    for (const char* w : {"steer_FL", "steer_ML", "steer_RL", "steer_RR", "steer_MR", "steer_FR"}) steer.push_back(need(m, w));
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
  } else {
    throw DataError("unknown scenario '" + name + "' (fl-bogie-rotation, rear-bogie-rotation, bump-crossing)");
  }
  return s;
}

log::Log simulate_flying_rover(const kinematics::RoverModel& m, const FlyingRoverScenario& sc) {
  if (!sc.joints) throw DataError("scenario without joint motion");
  const std::size_t nq = m.joints.size(), nw = m.wheels.size();
  const auto n = static_cast<std::size_t>(std::llround(sc.duration * sc.rate)) + 1;
  std::mt19937 rng(sc.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  auto noisy = [&](double value, double variance) { return sc.noise ? value + std::sqrt(variance) * unit(rng) : value; };
  std::vector<double> t(n);
  std::vector<std::vector<double>> imu(6, std::vector<double>(n)), joints(2 * nq, std::vector<double>(n)),
      wheel_rate(nw, std::vector<double>(n)), body(6, std::vector<double>(n, 0.0)),
      truth(3 * nw, std::vector<double>(n));
  std::vector<double> q, qd;
  const Eigen::Vector3d v(sc.speed, 0.0, 0.0), omega = Eigen::Vector3d::Zero();
  const double rate = sc.speed / m.wheel_radius;  // the same for every wheel (section 6.3)
  auto bogie_variance = [&](std::size_t j, bool of_rate) {
    // Bogie joints come first in the noise table, steering joints per wheel.
    std::size_t b = 0;
    for (std::size_t k = 0; k < nq; ++k) {
      if (m.joints[k].rfind("bogie", 0) != 0) continue;
      if (k == j) return of_rate ? m.noise.bogie_rate[b] : m.noise.bogie_angle[b];
      ++b;
    }
    for (std::size_t w = 0; w < nw; ++w) {
      if (m.wheels[w].steer_joint == static_cast<int>(j)) return of_rate ? m.noise.steer_rate[w] : m.noise.steer_angle[w];
    }
    return 1e-12;
  };
  const bool have_noise_table = !m.noise.bogie_angle.empty();
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = static_cast<double>(i) / sc.rate;
    sc.joints(t[i], q, qd);
    for (int k = 0; k < 3; ++k) {
      imu[static_cast<std::size_t>(k)][i] = noisy(0.0, m.noise.gyro[k]);
      imu[static_cast<std::size_t>(3 + k)][i] = noisy(k == 2 ? sc.gravity : 0.0, m.noise.accelerometer[k]);
    }
    for (std::size_t j = 0; j < nq; ++j) {
      joints[j][i] = noisy(q[j], have_noise_table ? bogie_variance(j, false) : 1e-12);
      joints[nq + j][i] = noisy(qd[j], have_noise_table ? bogie_variance(j, true) : 1e-12);
    }
    body[0][i] = sc.speed;
    for (std::size_t w = 0; w < nw; ++w) {
      wheel_rate[w][i] = noisy(rate, m.noise.wheel_rate.empty() ? 1e-12 : m.noise.wheel_rate[w]);
      const Eigen::Vector3d vd = kinematics::wheel_velocity<double>(m, static_cast<int>(w), q.data(), qd.data(), v, omega,
                                                                    0.0, 0.0, kinematics::WheelFrame::drive);
      const kinematics::WheelAngles a = kinematics::wheel_angles(vd);
      truth[w][i] = 1.0 - a.speed_in_plane / (rate * m.wheel_radius);  // slip against v . x_c (section 5.3)
      truth[nw + w][i] = a.contact;
      truth[2 * nw + w][i] = a.side_slip;
    }
  }
  log::Log out;
  out.metadata.rover_id = m.name;
  out.metadata.description = "hypothetical flying-rover scenario '" + sc.name + "' (seed 000 sections 6.3-6.4; RoverLab)";
  out.metadata.extra["truth/generator"] = "flying-rover";
  out.metadata.extra["truth/scenario"] = sc.name;
  out.metadata.extra["truth/seed"] = std::to_string(sc.seed);
  {
    log::Stream s("imu", t);
    const char* names[6] = {"angular_rate_x", "angular_rate_y", "angular_rate_z", "specific_force_x", "specific_force_y", "specific_force_z"};
    for (int k = 0; k < 6; ++k) {
      s.add_channel(names[k], k < 3 ? "rad/s" : "m/s^2", imu[static_cast<std::size_t>(k)], "rover body axes (x forward, y left, z up)");
    }
    out.add_stream(std::move(s));
  }
  {
    log::Stream s("joints", t);
    for (std::size_t j = 0; j < nq; ++j) s.add_channel(m.joints[j], "rad", joints[j]);
    for (std::size_t j = 0; j < nq; ++j) s.add_channel(m.joints[j] + "_rate", "rad/s", joints[nq + j]);
    out.add_stream(std::move(s));
  }
  {
    log::Stream s("wheels", t);
    for (std::size_t w = 0; w < nw; ++w) s.add_channel("rate_" + m.wheels[w].name, "rad/s", wheel_rate[w]);
    out.add_stream(std::move(s));
  }
  {
    log::Stream s("truth/body", t);
    const char* names[6] = {"velocity_x", "velocity_y", "velocity_z", "roll", "pitch", "yaw"};
    for (int k = 0; k < 6; ++k) s.add_channel(names[k], k < 3 ? "m/s" : "rad", body[static_cast<std::size_t>(k)]);
    out.add_stream(std::move(s));
  }
  {
    log::Stream s("truth/wheels", t);
    for (std::size_t w = 0; w < nw; ++w) s.add_channel("slip_" + m.wheels[w].name, "1", truth[w]);
    for (std::size_t w = 0; w < nw; ++w) s.add_channel("contact_angle_" + m.wheels[w].name, "rad", truth[nw + w]);
    for (std::size_t w = 0; w < nw; ++w) s.add_channel("side_slip_" + m.wheels[w].name, "rad", truth[2 * nw + w]);
    out.add_stream(std::move(s));
  }
  return out;
}

}  // namespace roverlab::simulation

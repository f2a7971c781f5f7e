#include "core/simulation/rocker_bogie_simulator.h"

#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/simulation/effects.h"

namespace roverlab::simulation {

using rocker_bogie::DynamicsReport;
using rocker_bogie::Kinematics;
using rocker_bogie::N;
using rocker_bogie::Vec2;

namespace {

// Wheel-centre heights above the path and wheel 1's distance from its start
// x: zero where the rover stands on the path.
Eigen::Vector4d placement_residual(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p,
                                   const RockerBogieRun& run, const rocker_bogie::Vec& x) {
  const Kinematics k = rocker_bogie::kinematics(g, p, x);
  Eigen::Vector4d r;
  for (int i = 0; i < 3; ++i) r(i) = k.wheel[i].y() - run.path.z(k.wheel[i].x());
  r(3) = k.wheel[0].x() - run.start_x;
  return r;
}

}  // namespace

RockerBogieSimulator::RockerBogieSimulator(const PlanarRockerBogieGeometry& geometry,
                                           const RockerBogieParameters& parameters, const RockerBogieRun& run)
    : g_(geometry),
      p_(parameters),
      run_(run),
      dynamics_(geometry, parameters, run),
      dt_(1.0 / parameters.control_rate),
      steps_(static_cast<std::size_t>(std::llround(run.duration * parameters.control_rate))),
      state_(2 * N, 0.0),
      stepper_(boost::numeric::odeint::make_controlled(
          1e-8, 1e-8, boost::numeric::odeint::runge_kutta_dopri5<rocker_bogie::State>())),
      rng_(run.seed),
      t_(steps_ + 1),
      rec_(4 + 6 * 3 + 3 + 3, std::vector<double>(steps_ + 1)),
      geo_(8, std::vector<double>(steps_ + 1)) {
  for (auto& v : sensors_.values) v.assign(steps_ + 1, 0.0);
}

RockerBogieResult RockerBogieSimulator::run() {
  place_on_path();
  for (std::size_t k = 0; k <= steps_; ++k) {
    control_step(k);
    if (k == steps_) break;
    integrate_step(static_cast<double>(k) * dt_);
    if (run_.progress && k % 100 == 0) run_.progress(static_cast<double>(k) / static_cast<double>(steps_));
  }
  result_.unsupported = dynamics_.unsupported();
  write_metadata();
  write_sensor_streams();
  write_truth_streams();
  if (run_.progress) run_.progress(1.0);
  return std::move(result_);
}

// Wheel 1 at start_x and all three wheel centres on the path: Newton on x0,
// z0, pitch and bogie angle with a central-difference Jacobian.
void RockerBogieSimulator::place_on_path() {
  Vec q = Vec::Zero();
  q(0) = run_.start_x - g_.rocker_to_wheel1.x();
  q(1) = run_.path.z(run_.start_x) - g_.rocker_to_wheel1.y();
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector4d r = placement_residual(g_, p_, run_, q);
    if (r.norm() < 1e-12) break;
    Eigen::Matrix4d J;
    for (int c = 0; c < 4; ++c) {
      Vec d = Vec::Zero();
      d(c) = 1e-7;
      J.col(c) = (placement_residual(g_, p_, run_, q + d) - placement_residual(g_, p_, run_, q - d)) / 2e-7;
    }
    q.head<4>() -= J.fullPivLu().solve(r);
  }
  for (int i = 0; i < N; ++i) state_[N + static_cast<std::size_t>(i)] = q(i);
}

// One control step at t = k dt: the dynamics at the current state (the normal
// loads for the next step), the controller, the sensors and the truth.
void RockerBogieSimulator::control_step(std::size_t k) {
  const double time = static_cast<double>(k) * dt_;
  Vec q, qd, qdd;
  rocker_bogie::split_state(state_, q, qd);
  DynamicsReport out;
  dynamics_.hold(torque_, normal_);
  dynamics_.accelerations(q, qd, qdd, &out);
  normal_ = out.lambda;
  const Kinematics kin = rocker_bogie::kinematics(g_, p_, q);
  check_constraints(kin);
  controller(qd);
  read_sensors(k, q, qd, out);
  t_[k] = time;
  record_truth(k, q, kin, out);
}

// Eq. 4.49-4.50 integrated over one control step with the torques and normal loads held.
void RockerBogieSimulator::integrate_step(double time) {
  dynamics_.hold(torque_, normal_);
  boost::numeric::odeint::integrate_adaptive(stepper_, rocker_bogie::OdeSystem{&dynamics_}, state_, time, time + dt_,
                                             step_size_);
  for (double v : state_) {
    if (!std::isfinite(v)) throw DataError("the simulation diverged at t = " + std::to_string(time) + " s");
  }
}

void RockerBogieSimulator::check_constraints(const Kinematics& kin) {
  for (int i = 0; i < 3; ++i) {
    result_.max_constraint_error =
        std::max(result_.max_constraint_error, std::abs(kin.wheel[i].y() - run_.path.z(kin.wheel[i].x())));
  }
}

// Wheel-speed control at the control rate (section 4.2.4) on the wheel
// rate error (rad/s). Table 4.1's derivative gain is not used: with the
// torque held over each 20 ms step, Kd = 12.5 on the rate error gives the
// loop a gain of 12 through the drivetrain's 1.08 kg m^2 and it diverges;
// the proportional and integral gains alone track the speed.
void RockerBogieSimulator::controller(const Vec& qd) {
  for (int i = 0; i < 3; ++i) {
    const double e = p_.desired_speed / g_.wheel_radius - qd(4 + i);
    integral_(i) += e * dt_;
    torque_(i) = p_.kp * e + p_.ki * integral_(i);
  }
}

double RockerBogieSimulator::noise(double sigma) { return run_.sensor_noise ? sigma * unit_(rng_) : 0.0; }

// Sensor values from the true state; noise of Table 5.1, then the effects.
void RockerBogieSimulator::read_sensors(std::size_t k, const Vec& q, const Vec& qd, const DynamicsReport& out) {
  const double deg = M_PI / 180.0;
  const double th = q(2);
  const Vec2 xb(std::cos(th), -std::sin(th)), zb(std::sin(th), std::cos(th));  // rover axes in the world
  const Vec2 acc(out.qdd(0), out.qdd(1));
  const Vec2 f = acc + Vec2(0.0, p_.gravity);  // specific force
  const Vec2 vel(qd(0), qd(1));
  auto& v = sensors_.values;
  v[0][k] = q(3) + noise(9.155e-4 * deg);
  for (int i = 0; i < 3; ++i) v[1 + static_cast<std::size_t>(i)][k] = q(4 + i) + noise(2.143e-5 * deg);
  v[4][k] = qd(2) + noise(0.56 * deg);
  v[5][k] = f.dot(xb) + noise(1.245e-3);
  v[6][k] = f.dot(zb) + noise(1.245e-3);
  v[7][k] = vel.dot(xb) + noise(1e-3);
  read_force_sensors(k, q, out);
}

// The soil's force on each wheel (normal load and drawbar pull) in the axes of the link carrying it.
void RockerBogieSimulator::read_force_sensors(std::size_t k, const Vec& q, const DynamicsReport& out) {
  const double th = q(2);
  for (int i = 0; i < 3; ++i) {
    const double gm = out.gamma(i), Wn = normal_(i) / std::cos(gm);
    const Vec2 n(-std::sin(gm), std::cos(gm)), tt(std::cos(gm), std::sin(gm));
    const Vec2 F = Wn * n + out.dp(i) * tt;
    const double a = i == 0 ? th : th + q(3);
    const Vec2 lx(std::cos(a), -std::sin(a)), lz(std::sin(a), std::cos(a));
    const auto ii = static_cast<std::size_t>(i);
    sensors_.values[8 + ii][k] = F.dot(lz) + noise(3.255e-2);
    sensors_.values[11 + ii][k] = F.dot(lx) + noise(3.255e-2);
  }
}

void RockerBogieSimulator::record_truth(std::size_t k, const Vec& q, const Kinematics& kin, const DynamicsReport& out) {
  const Vec2 pivot = Vec2(q(0), q(1)) + rocker_bogie::rotate(q(2), g_.rocker_to_bogie);
  geo_[0][k] = pivot.x();
  geo_[1][k] = pivot.y();
  for (int i = 0; i < 3; ++i) {
    geo_[2 + 2 * static_cast<std::size_t>(i)][k] = kin.wheel[i].x();
    geo_[3 + 2 * static_cast<std::size_t>(i)][k] = kin.wheel[i].y();
  }
  for (std::size_t c = 0; c < 4; ++c) rec_[c][k] = q(static_cast<int>(c));
  for (int i = 0; i < 3; ++i) {
    const auto ii = static_cast<std::size_t>(i);
    rec_[4 + ii][k] = out.slip(i);
    rec_[7 + ii][k] = normal_(i) / std::cos(out.gamma(i));
    rec_[10 + ii][k] = out.dp(i);
    rec_[13 + ii][k] = out.tau(i);
    rec_[16 + ii][k] = out.gamma(i);
    rec_[19 + ii][k] = out.rate(i);
    rec_[22 + ii][k] = torque_(i);
    rec_[25 + ii][k] = out.sinkage(i);
  }
}

// The effects switched on (in truth/ metadata only), the seed and the run's description.
void RockerBogieSimulator::write_metadata() {
  log::Log& lg = result_.log;
  const RockerBogieEffects& fx = run_.effects;
  lg.metadata.rover_id = "kapvik_planar";
  for (const auto& e : effect_table()) {
    const double value = fx.*(e.member);
    if (value == e.neutral) continue;
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", value);  // all digits: a study's fit is judged against it
    lg.metadata.extra[std::string("truth/effect/") + e.name] = text;
  }
  lg.metadata.extra["truth/seed"] = std::to_string(run_.seed);
  lg.metadata.description = "planar rocker-bogie simulation (seed 003 chapter 4) on path: " + run_.path.name;
  lg.metadata.extra["truth/generator"] = "rocker-bogie";
  lg.metadata.extra["truth/soil"] = run_.soil.name;
  lg.metadata.extra["truth/traction"] = run_.traction == TractionSource::polynomial ? "polynomial" : "wong-reece";
  lg.metadata.extra["truth/wheel_radius_m"] = std::to_string(g_.wheel_radius);
}

// Table 5.1's sensors with their noise, then the sensor effects (sensor_effects.h).
void RockerBogieSimulator::write_sensor_streams() {
  sensors_.time = t_;
  apply_sensor_effects(run_.effects, sensors_);
  const auto& channels = sensor_channels();
  std::size_t c = 0;
  while (c < kSensorChannels) {
    const std::string name = channels[c].stream;
    log::Stream st(name, name == "imu" ? sensors_.imu_time : sensors_.time);
    for (; c < kSensorChannels && name == channels[c].stream; ++c) {
      st.add_channel(channels[c].name, channels[c].unit, sensors_.values[c], channels[c].description);
    }
    result_.log.add_stream(std::move(st));
  }
}

void RockerBogieSimulator::write_truth_streams() {
  log::Log& lg = result_.log;
  {
    log::Stream st("truth/pose", t_);
    st.add_channel("x", "m", rec_[0], "body centre of mass");
    st.add_channel("z", "m", rec_[1]);
    st.add_channel("pitch", "rad", rec_[2], "clockwise positive (nose down)");
    st.add_channel("bogie_angle", "rad", rec_[3], "clockwise positive");
    st.add_channel("bogie_pivot_x", "m", geo_[0]);
    st.add_channel("bogie_pivot_z", "m", geo_[1]);
    lg.add_stream(std::move(st));
  }
  {
    log::Stream st("truth/wheels", t_);
    const char* names[6] = {"slip_",          "normal_load_", "drawbar_pull_", "resistive_torque_",
                            "contact_angle_", "wheel_rate_"};
    const char* units[6] = {"1", "N", "N", "N*m", "rad", "rad/s"};
    for (std::size_t c = 0; c < 6; ++c) {
      for (std::size_t i = 0; i < 3; ++i)
        st.add_channel(std::string(names[c]) + std::to_string(i + 1), units[c], rec_[4 + 3 * c + i]);
    }
    for (std::size_t i = 0; i < 3; ++i) st.add_channel("sinkage_" + std::to_string(i + 1), "m", rec_[25 + i]);
    for (std::size_t i = 0; i < 3; ++i) {
      st.add_channel("centre_x_" + std::to_string(i + 1), "m", geo_[2 + 2 * i], "wheel centre (on the path)");
      st.add_channel("centre_z_" + std::to_string(i + 1), "m", geo_[3 + 2 * i]);
    }
    lg.add_stream(std::move(st));
  }
  log::Stream st("commands", t_);
  for (std::size_t i = 0; i < 3; ++i) st.add_channel("wheel_torque_" + std::to_string(i + 1), "N*m", rec_[22 + i]);
  lg.add_stream(std::move(st));
}

}  // namespace roverlab::simulation

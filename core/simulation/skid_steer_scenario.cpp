#include "core/simulation/skid_steer_scenario.h"

#include <cmath>
#include <random>

#include "core/common/error.h"
#include "core/estimation/ins.h"
#include "core/estimation/slip.h"

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
      {5.0, 0.0, 0.0, 0.0},     {15.0, 0.5, 0.0, base},   {3.0, 0.0, 0.0, base},
      {8.0, 0.5, 0.0, 0.0},     {3.0, 0.0, 0.0, 0.0},
      {8.0, 0.5, 0.05, base},   {6.0, 0.5, 0.0, 0.12},    {6.0, 0.5, 0.0, base}, {3.0, 0.0, 0.0, base},
      {6.0, 0.5, 0.0, 0.3},     {6.0, 0.5, -0.05, base},  {5.0, 0.5, 0.0, 0.15}, {3.0, 0.0, 0.0, base},
      {5.0, 0.4, 0.0, 0.55},    {8.0, 0.5, 0.0, base},    {3.0, 0.0, 0.0, base},
      {4.0, 0.2, 0.0, 0.85},    {10.0, 0.5, 0.03, base},  {6.0, 0.5, 0.0, 0.08}, {3.0, 0.0, 0.0, base},
      {12.0, 0.5, 0.0, base},   {3.0, 0.0, 0.0, base},   {10.0, 0.5, -0.03, 0.0}, {5.0, 0.0, 0.0, 0.0},
  };
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
    s.wheel_time_offset = value;
  } else if (name == "slip") {
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

log::Log simulate_skid_steer(const SkidSteerScenario& sc) {
  if (sc.segments.empty()) throw DataError("skid-steer scenario without segments");
  std::mt19937 rng(sc.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  std::bernoulli_distribution coin(0.5);
  const double dt = 1.0 / sc.imu_rate;
  Eigen::Vector3d ba, bg;
  for (int k = 0; k < 3; ++k) {
    ba[k] = (coin(rng) ? 1.0 : -1.0) * sc.accel_bias;
    bg[k] = (coin(rng) ? 1.0 : -1.0) * sc.gyro_bias;
  }
  const double g = estimation::gravity_down(sc.latitude, sc.height);
  const double r = sc.rover.wheel_radius, track = sc.rover.track;

  std::vector<double> t, fx, fy, fz, wx, wy, wz, east, north, yaw, speed, slip_now, left_angle, right_angle;
  double v = 0.0, psi = sc.heading, e = 0.0, n = 0.0, time = 0.0, al = 0.0, ar = 0.0;
  for (const auto& seg : sc.segments) {
    const auto steps = static_cast<long>(std::llround(seg.duration * sc.imu_rate));
    for (long k = 0; k < steps; ++k) {
      const double dv = seg.speed - v;
      const double a = std::clamp(dv / dt, -sc.max_acceleration, sc.max_acceleration);
      const double yaw_rate = v > 1e-6 || seg.speed > 0.0 ? seg.yaw_rate : 0.0;
      // IMU at this sample: specific force f = a_b - g_b on level ground (FRD body axes).
      t.push_back(time);
      fx.push_back(a + ba.x() + sc.accel_vrw / std::sqrt(dt) * unit(rng));
      fy.push_back(v * yaw_rate + ba.y() + sc.accel_vrw / std::sqrt(dt) * unit(rng));
      fz.push_back(-g + ba.z() + sc.accel_vrw / std::sqrt(dt) * unit(rng));
      wx.push_back(bg.x() + sc.gyro_arw / std::sqrt(dt) * unit(rng));
      wy.push_back(bg.y() + sc.gyro_arw / std::sqrt(dt) * unit(rng));
      wz.push_back(yaw_rate + bg.z() + sc.gyro_arw / std::sqrt(dt) * unit(rng));
      east.push_back(e);
      north.push_back(n);
      yaw.push_back(psi);
      speed.push_back(v);
      const double seg_slip = sc.slip ? seg.slip : 0.0;
      slip_now.push_back(v > 1e-6 ? seg_slip : 0.0);
      left_angle.push_back(al);
      right_angle.push_back(ar);
      // Wheels: ground speed of each side, turned faster by slip s (v = r w (1 - s)).
      const double keep = 1.0 - (v > 1e-6 ? seg_slip : 0.0);
      const double half = 0.5 * yaw_rate * track * sc.turning_track_factor;
      al += (v + half) / (r * sc.left_radius_scale * keep) * dt;
      ar += (v - half) / (r * sc.right_radius_scale * keep) * dt;
      // Motion over the step (exact for constant acceleration and yaw rate, to second order).
      const double v_next = v + a * dt;
      const double mid_psi = psi + 0.5 * yaw_rate * dt;
      const double dist = 0.5 * (v + v_next) * dt;
      e += dist * std::sin(mid_psi);
      n += dist * std::cos(mid_psi);
      psi += yaw_rate * dt;
      v = v_next;
      time += dt;
    }
  }

  log::Log out;
  out.metadata.rover_id = "wvu_pathfinder";
  out.metadata.description = "simulated skid-steer drive with slip episodes (RoverLab kinematic generator)";
  out.metadata.extra["truth/generator"] = "skid-steer-slip";
  out.metadata.extra["truth/seed"] = std::to_string(sc.seed);
  for (int k = 0; k < 3; ++k) {
    const char axis[2] = {static_cast<char>('x' + k), 0};
    out.metadata.extra[std::string("truth/gyro_bias_") + axis] = std::to_string(bg[k]);
    out.metadata.extra[std::string("truth/accel_bias_") + axis] = std::to_string(ba[k]);
  }
  auto effect = [&](const char* name, double value, double neutral) {
    if (value != neutral) out.metadata.extra[std::string("truth/effect/") + name] = std::to_string(value);
  };
  effect("left-radius-scale", sc.left_radius_scale, 1.0);
  effect("right-radius-scale", sc.right_radius_scale, 1.0);
  effect("turning-track-factor", sc.turning_track_factor, 1.0);
  effect("wheel-time-offset", sc.wheel_time_offset, 0.0);
  if (!sc.slip) out.metadata.extra["truth/effect/slip"] = "0";
  {
    log::Stream imu("imu", t);
    imu.add_channel("specific_force_x", "m/s^2", fx);
    imu.add_channel("specific_force_y", "m/s^2", fy);
    imu.add_channel("specific_force_z", "m/s^2", fz);
    imu.add_channel("angular_rate_x", "rad/s", wx);
    imu.add_channel("angular_rate_y", "rad/s", wy);
    imu.add_channel("angular_rate_z", "rad/s", wz);
    out.add_stream(std::move(imu));
    log::Stream truth("truth/motion", t);
    truth.add_channel("east", "m", east);
    truth.add_channel("north", "m", north);
    truth.add_channel("yaw", "rad", yaw);
    truth.add_channel("forward_speed", "m/s", speed);
    out.add_stream(std::move(truth));
  }
  // Wheels, GPS and slip truth at their own rates, sampled from the IMU-rate truth.
  const auto every = [&](double rate) { return static_cast<std::size_t>(std::llround(sc.imu_rate / rate)); };
  {
    std::vector<double> tw, tt, fl, fr, rl, rr, s, c;
    for (std::size_t i = 0; i < t.size(); i += every(sc.wheel_rate)) {
      tw.push_back(t[i] + sc.wheel_time_offset);
      tt.push_back(t[i]);
      fl.push_back(left_angle[i]);
      rl.push_back(left_angle[i]);
      fr.push_back(right_angle[i]);
      rr.push_back(right_angle[i]);
      s.push_back(slip_now[i]);
      c.push_back(static_cast<double>(estimation::classify_slip(slip_now[i])));
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
  {
    std::vector<double> tg, ge, gn, gu, lat, lon, h;
    const double rn = estimation::meridian_radius(sc.latitude) + sc.height;
    const double re = estimation::transverse_radius(sc.latitude) + sc.height;
    for (std::size_t i = 0; i < t.size(); i += every(sc.gps_rate)) {
      tg.push_back(t[i]);
      ge.push_back(east[i] + sc.gps_sigma * unit(rng));
      gn.push_back(north[i] + sc.gps_sigma * unit(rng));
      gu.push_back(sc.gps_sigma * unit(rng));
      lat.push_back(sc.latitude + north[i] / rn);
      lon.push_back(sc.longitude + east[i] / (re * std::cos(sc.latitude)));
      h.push_back(sc.height);
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
  return out;
}

}  // namespace roverlab::simulation

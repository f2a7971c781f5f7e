#include "core/models/skid_steer_odometry.h"

#include <cmath>

namespace roverlab::estimation {

WheelSamples wheel_rates(const std::vector<double>& t, const std::vector<double>& fl, const std::vector<double>& fr,
                         const std::vector<double>& rl, const std::vector<double>& rr) {
  WheelSamples w;
  w.time = t;
  const std::size_t n = t.size();
  w.left_rate.assign(n, 0.0);
  w.right_rate.assign(n, 0.0);
  if (n < 2) return w;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 < n ? i + 1 : n - 1;
    const double dt = t[b] - t[a];
    w.left_rate[i] = 0.5 * ((fl[b] - fl[a]) + (rl[b] - rl[a])) / dt;
    w.right_rate[i] = 0.5 * ((fr[b] - fr[a]) + (rr[b] - rr[a])) / dt;
  }
  return w;
}

OdometryTrack dead_reckon(const WheelSamples& w, const SkidSteerGeometry& g, const OdometryCorrections& c, double east0,
                          double north0, double heading0) {
  OdometryTrack tr;
  const std::size_t n = w.time.size();
  double e = east0, nn = north0, psi = heading0;
  const double r = g.wheel_radius * c.radius_scale;
  const double track = g.track * c.track_factor;
  double v_prev = 0, yaw_prev = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double keep = c.slip.empty() ? 1.0 : 1.0 - c.slip[i];
    const double vl = r * c.left_scale * w.left_rate[i] * keep;
    const double vr = r * c.right_scale * w.right_rate[i] * keep;
    const double v = 0.5 * (vl + vr);
    const double yaw_rate = (vl - vr) / track;  // left faster: turning right (clockwise)
    if (i > 0) {
      // Trapezoid over [t_{i-1}, t_i]: the rates are centred on their
      // samples, so the rate at t_i alone would run the track half a wheel
      // sample early (50 ms at 10 Hz, which the odometry study then names
      // as a time offset on drives without one).
      const double dt = w.time[i] - w.time[i - 1];
      const double v_mid = 0.5 * (v + v_prev), yaw_mid = 0.5 * (yaw_rate + yaw_prev);
      const double mid = psi + 0.5 * yaw_mid * dt;
      e += v_mid * std::sin(mid) * dt;
      nn += v_mid * std::cos(mid) * dt;
      psi += yaw_mid * dt;
    }
    v_prev = v;
    yaw_prev = yaw_rate;
    tr.time.push_back(w.time[i] + c.time_offset);
    tr.east.push_back(e);
    tr.north.push_back(nn);
    tr.heading.push_back(psi);
    tr.forward_speed.push_back(v);
    tr.yaw_rate.push_back(yaw_rate);
  }
  return tr;
}

}  // namespace roverlab::estimation

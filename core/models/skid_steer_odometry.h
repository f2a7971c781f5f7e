#pragma once
// Wheel odometry of a four-wheel skid-steer rover (seed 002 section 5.1:
// WVU Pathfinder): wheel rates from wheel angles, forward speed and yaw rate,
// dead reckoning in the local east-north plane.

#include <vector>

namespace roverlab::estimation {

struct SkidSteerGeometry {
  double wheel_radius = 0.12;  // m (24 cm wheels)
  double track = 0.685;        // m
  double wheelbase = 0.544;    // m
};

// Corrections a model-discrepancy study may fit; neutral values do nothing.
struct OdometryCorrections {
  double radius_scale = 1.0;  // all wheels
  double left_scale = 1.0;    // left wheels, on top of radius_scale
  double right_scale = 1.0;   // right wheels
  double track_factor = 1.0;  // effective track = track_factor * track (skid-steer turning)
  double time_offset = 0.0;   // s added to the wheel time stamps
  std::vector<double> slip;   // per wheel sample, the wheel speed is multiplied by (1 - slip); empty: none
};

struct WheelSamples {
  std::vector<double> time;
  std::vector<double> left_rate, right_rate;  // rad/s, mean of front and rear, forward positive
};

// Rates by central differences of the wheel angles (one-sided at the ends).
WheelSamples wheel_rates(const std::vector<double>& time, const std::vector<double>& fl, const std::vector<double>& fr,
                         const std::vector<double>& rl, const std::vector<double>& rr);

struct OdometryTrack {
  std::vector<double> time, east, north, heading;  // heading: rad clockwise from north
  std::vector<double> forward_speed, yaw_rate;     // yaw rate about down, rad/s
};

// Dead reckoning from (east0, north0, heading0): v = r (wL + wR) / 2,
// heading rate = r (wL - wR) / track (clockwise positive).
OdometryTrack dead_reckon(const WheelSamples& w, const SkidSteerGeometry& g, const OdometryCorrections& c, double east0,
                          double north0, double heading0);

}  // namespace roverlab::estimation

#pragma once
// A kinematic skid-steer rover on flat ground with scripted slip episodes:
// the log generator behind the slip-detection tests (seed 002). It writes the
// streams a real Pathfinder log has (imu, wheels, gps) plus truth/ streams.

#include <string>
#include <vector>

#include "core/log/log.h"
#include "core/models/skid_steer_odometry.h"

namespace roverlab::simulation {

struct DriveSegment {
  double duration;  // s
  double speed;     // m/s commanded forward speed (reached with max_acceleration)
  double yaw_rate;  // rad/s, clockwise positive; with speed 0, a turn in place once stopped
  double slip;      // wheel slip ratio during the segment, 0..0.95
};

struct SkidSteerScenario {
  std::vector<DriveSegment> segments;
  estimation::SkidSteerGeometry rover;
  double imu_rate = 250.0, wheel_rate = 10.0, gps_rate = 10.0;
  double max_acceleration = 0.5;                                  // m/s^2
  double latitude = 0.6919, longitude = -1.3957, height = 310.0;  // start (Point Marion, PA)
  double heading = 0.0;                                           // rad, clockwise from north
  // IMU errors and GPS noise. Noise: the ADIS16495 datasheet (seed 002
  // section 5.1). Biases: turn-on values the filter must estimate, 25 (gyro)
  // and 100 (accelerometer) times the datasheet's in-run stability.
  double gyro_arw = 2.9e-5;    // rad/sqrt(s)   (0.1 deg/sqrt(h))
  double accel_vrw = 1.33e-4;  // m/s/sqrt(s)   (0.008 m/s/sqrt(h))
  double gyro_bias = 2e-4;     // rad/s, per axis, sign drawn from the seed (41 deg/h)
  double accel_bias = 0.003;   // m/s^2, per axis, sign drawn from the seed (0.3 mg)
  double gps_sigma = 0.01;     // m
  unsigned seed = 1;
  // Hidden effects, recorded only in the truth/ metadata: true wheel radius
  // of each side against the nominal one, effective track of skid-steer
  // turning (wheels must skid: wider than the geometric track), and an
  // offset added to the wheel stream's time stamps.
  double left_radius_scale = 1.0, right_radius_scale = 1.0;
  double turning_track_factor = 1.0;
  double wheel_time_offset = 0.0;  // s
  bool slip = true;                // false: firm ground, every segment's slip is 0
};

// The default test drive: 5 s at rest, then straight runs and turns at
// 0.5 m/s with 3 s stops every 20 s, and slip episodes of every class.
SkidSteerScenario default_slip_scenario(unsigned seed);

// Loops with turns in place (issue 14): 5 s at rest, a quarter turn in place,
// then two laps of a square of about 18 m sides at 0.8 m/s (about 140 m, 4 min), each side
// ended by a stop and a quarter turn in place; starting towards the south-east
// (not north); GPS noise of 3 m; firm ground (slip 0) on half the sides, 4 %
// steady slip on the others, and episodes of 12, 30, 55 and 85 %.
SkidSteerScenario loop_slip_scenario(unsigned seed);

// Sets a hidden effect by name: left-radius-scale, right-radius-scale,
// radius-scale (both sides), turning-track-factor, wheel-time-offset, or
// slip (0 or 1). Throws DataError for an unknown name.
void set_effect(SkidSteerScenario& scenario, const std::string& name, double value);

// Streams: imu, wheels, gps, truth/motion (IMU rate: east, north, yaw,
// forward_speed), truth/slip (wheel rate: slip_ratio, slip_class).
log::Log simulate_skid_steer(const SkidSteerScenario& scenario);

}  // namespace roverlab::simulation

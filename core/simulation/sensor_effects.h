#pragma once
// The sensors of a planar rocker-bogie run (Table 5.1, seed 003) as plain
// series, and its sensor effects (RockerBogieEffects: gyro and accelerometer
// bias, force offset and scale, encoder dropout, IMU time offset) applied to
// them. The simulator applies them after its noise; the rover discrepancy
// study applies the same function to a noise-free simulation when it fits a
// sensor cause, so the effect it fits is the effect the simulator injects.

#include <array>
#include <cstddef>
#include <vector>

#include "core/simulation/rocker_bogie.h"

namespace roverlab::simulation {

// Sensor channels in Table 5.1 order: joints bogie_angle, wheel_angle_1..3;
// imu pitch_rate, specific_force_x, specific_force_z; velocimeter
// forward_speed; forces load_1..3, perpendicular_1..3.
struct SensorChannel {
  const char* stream;
  const char* name;
  const char* unit;
  const char* description;
  bool integrated = false;  // an angle integrated from a rate (wheel encoders): compared as increments
};
constexpr std::size_t kSensorChannels = 14;
const std::array<SensorChannel, kSensorChannels>& sensor_channels();

struct SensorSeries {
  std::vector<double> time;      // s, the control steps
  std::vector<double> imu_time;  // s, the imu stream's stamps (time plus any offset)
  std::array<std::vector<double>, kSensorChannels> values;
};

// Applies the sensor effects of `effects` to `series` (imu_time is set from time).
void apply_sensor_effects(const RockerBogieEffects& effects, SensorSeries& series);

}  // namespace roverlab::simulation

#include "core/simulation/sensor_effects.h"

namespace roverlab::simulation {

const std::array<SensorChannel, kSensorChannels>& sensor_channels() {
  static const std::array<SensorChannel, kSensorChannels> channels = {{
      {"joints", "bogie_angle", "rad", "16-bit absolute encoder"},
      {"joints", "wheel_angle_1", "rad", "motor encoder", true},
      {"joints", "wheel_angle_2", "rad", "motor encoder", true},
      {"joints", "wheel_angle_3", "rad", "motor encoder", true},
      {"imu", "pitch_rate", "rad/s", "clockwise positive"},
      {"imu", "specific_force_x", "m/s^2", "rover axes: x forward"},
      {"imu", "specific_force_z", "m/s^2", "rover axes: z up"},
      {"velocimeter", "forward_speed", "m/s", "rover x axis"},
      {"forces", "load_1", "N", "along the carrying link's z axis"},
      {"forces", "load_2", "N", "along the carrying link's z axis"},
      {"forces", "load_3", "N", "along the carrying link's z axis"},
      {"forces", "perpendicular_1", "N", "along the link's x axis"},
      {"forces", "perpendicular_2", "N", "along the link's x axis"},
      {"forces", "perpendicular_3", "N", "along the link's x axis"},
  }};
  return channels;
}

void apply_sensor_effects(const RockerBogieEffects& fx, SensorSeries& s) {
  if (fx.encoder_dropout_start >= 0) {  // the wheel encoders hold their last reading for 2 s
    for (std::size_t c = 1; c <= 3; ++c) {
      std::vector<double>& v = s.values[c];
      for (std::size_t k = 1; k < v.size() && k < s.time.size(); ++k) {
        if (s.time[k] >= fx.encoder_dropout_start && s.time[k] < fx.encoder_dropout_start + 2.0) v[k] = v[k - 1];
      }
    }
  }
  for (double& x : s.values[4]) x += fx.gyro_bias;
  for (std::size_t c = 5; c <= 6; ++c) {
    for (double& x : s.values[c]) x += fx.accel_bias;
  }
  for (std::size_t c = 8; c < kSensorChannels; ++c) {
    for (double& x : s.values[c]) x = fx.force_scale * x + fx.force_offset;
  }
  s.imu_time = s.time;
  for (double& x : s.imu_time) x += fx.imu_time_offset;
}

}  // namespace roverlab::simulation

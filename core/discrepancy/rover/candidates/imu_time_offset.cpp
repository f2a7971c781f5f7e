#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_imu_time_offset_rover_candidate() {
  return fixed_rover_candidate("IMU time offset", "the IMU time stamps are offset from the other sensors' time stamps",
                               false, {{"imu-time-offset", "s", 0.0, -1.0, 1.0, 0.005}});
}

}  // namespace roverlab::analysis

#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_accel_bias_rover_candidate() {
  return fixed_rover_candidate("accelerometer bias", "both accelerometer axes read a constant bias", false,
                               {{"accel-bias", "m/s^2", 0.0, -5.0, 5.0, 1e-4}});
}

}  // namespace roverlab::analysis

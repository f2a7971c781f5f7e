#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_gyro_bias_rover_candidate() {
  return fixed_rover_candidate("gyro bias", "the pitch-rate gyro reads a constant bias", false,
                               {{"gyro-bias", "rad/s", 0.0, -0.5, 0.5, 1e-4}});
}

}  // namespace roverlab::analysis

#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_force_offset_rover_candidate() {
  return fixed_rover_candidate("force offset", "every wheel force-sensor axis reads a constant offset", false,
                               {{"force-offset", "N", 0.0, -500.0, 500.0, 0.01}});
}

}  // namespace roverlab::analysis

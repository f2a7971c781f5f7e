#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

std::unique_ptr<RoverCandidate> make_wheel_radius_rover_candidate() {
  return fixed_rover_candidate(
      "wheel radius",
      "the wheels roll on another radius than the nominal one (controller and encoders assume the nominal)", true,
      // The search spans the effect's allowed range (a true 0.8 ended on the old bound of 0.8).
      {{"wheel-radius-scale", "1", 1.0, 0.5, 2.0, 0.002}});
}

}  // namespace roverlab::analysis

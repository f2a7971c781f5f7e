#include "core/discrepancy/rover/candidates.h"

namespace roverlab::analysis {

// Ishigami et al. 2007 (J. Field Robotics 24(3)): a wheel at a slip angle
// shares the soil's shear strength with its lateral force, so it pulls less
// and its resistive torque falls. One planar side sees only the magnitude,
// and sees it as ~beta^2: the screen starts at the best of an 8-deg grid
// from 0.5 deg (at 0 the response's slope is 0).
std::unique_ptr<RoverCandidate> make_slip_angle_rover_candidate() {
  return fixed_rover_candidate(
      "slip-angle",
      "the wheels run at a slip angle (a steering manoeuvre, or crabbing across a side slope) and lose drawbar pull "
      "to the lateral force",
      true, {{"slip-angle", "deg", 15.0, 0.5, 60.0, 0.2, true, 0, 8.0, true}});
}

}  // namespace roverlab::analysis

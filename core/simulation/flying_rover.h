#pragma once
// The hypothetical "flying rover" scenarios of seed 000 sections 6.3 and 6.4
// (a level body flying forward at constant speed while bogies and steering
// move), with sensors at the noise of Table 6.1 and the reference computed
// from the kinematics, plus a third scenario of RoverLab's: the bogie and
// steering motion of the left wheels crossing a bump while all wheels steer.

#include <functional>
#include <string>
#include <vector>

#include "core/kinematics/rover_model.h"
#include "core/log/log.h"

namespace roverlab::simulation {

struct FlyingRoverScenario {
  std::string name;
  double duration = 30.0;  // s
  double rate = 1000.0;    // Hz, every sensor
  double speed = 0.03;     // m/s, forward
  double gravity = 9.80665;
  // Joint angles and rates (RoverModel::joints order) at time t.
  std::function<void(double t, std::vector<double>& q, std::vector<double>& qdot)> joints;
  unsigned seed = 1;
  bool noise = true;
};

// fl-bogie-rotation (section 6.3): the front-left bogie turns at 0.06 rad/s
// from 5 s to 15 s; rear-bogie-rotation (section 6.4): the rear bogie does;
// bump-crossing: see above. Throws DataError for another name or a rover
// without the joints the scenario moves.
FlyingRoverScenario flying_rover_scenario(const std::string& name, const kinematics::RoverModel& rover);
std::vector<std::string> flying_rover_scenarios();

// Streams: imu (angular_rate_*, specific_force_*, body axes of the rover
// description), joints (each joint's angle and <joint>_rate), wheels
// (rate_<wheel>), truth/body (velocity_*, roll, pitch, yaw) and truth/wheels
// (slip_, contact_angle_, side_slip_<wheel>).
log::Log simulate_flying_rover(const kinematics::RoverModel& rover, const FlyingRoverScenario& scenario);

}  // namespace roverlab::simulation

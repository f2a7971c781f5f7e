#pragma once
// The hypothetical "flying rover" scenarios of seed 000 sections 6.3 and 6.4
// (a level body flying forward at constant speed while bogies and steering
// move), with sensors at the noise of Table 6.1 and the reference computed
// from the kinematics, plus a third scenario of RoverLab's: the bogie and
// steering motion of the left wheels crossing a bump while all wheels steer.

#include <cmath>
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
  // A steering manoeuvre (issue 33, RoverLab's, not in the seed): the body
  // turns about a centre turn_radius to its left (negative: right; infinite:
  // straight) at yaw rate speed / turn_radius, and every steering joint is
  // turned, on top of the scenario's own steering, to its wheel's travel
  // direction in that turn less slip_angle: a wheel the scenario does not
  // move otherwise slides at slip_angle (seed 000 section 5.2's beta,
  // positive when the velocity points left of the wheel plane). Straight
  // with a slip angle is a crab across a side slope: the wheels point
  // uphill and slide down at slip_angle. Each wheel turns at the rate that
  // rolls it without slip there (at the joints' angles at t = 0).
  double turn_radius = INFINITY;  // m, |R| >= 1 (the centre outside the wheels)
  double slip_angle = 0.0;        // rad, |beta| <= 45 deg
  // 0: the slip angle from the start; else it ramps in linearly over
  // kSlipAngleRamp from this time (the steering joints turn, their rates measured).
  double slip_angle_from = 0.0;                  // s
  static constexpr double kSlipAngleRamp = 1.0;  // s
};

// fl-bogie-rotation (section 6.3): the front-left bogie turns at 0.06 rad/s
// from 5 s to 15 s; rear-bogie-rotation (section 6.4): the rear bogie does;
// bump-crossing: see above. Throws DataError for another name or a rover
// without the joints the scenario moves.
FlyingRoverScenario flying_rover_scenario(const std::string& name, const kinematics::RoverModel& rover);
// The names flying_rover_scenario() knows: the one list `roverlab scenario`
// registers its commands from and campaign files check their scenarios against.
std::vector<std::string> flying_rover_scenarios();

// Checks turn_radius, slip_angle and slip_angle_from; throws DataError naming the bad one.
void check_steering_manoeuvre(const FlyingRoverScenario& scenario);

// Streams: imu (angular_rate_*, specific_force_*, body axes of the rover
// description; a turn adds its yaw rate and centripetal force), joints (each joint's angle and <joint>_rate), wheels
// (rate_<wheel>), truth/body (velocity_*, roll, pitch, yaw) and truth/wheels
// (slip_, contact_angle_, side_slip_<wheel>).
log::Log simulate_flying_rover(const kinematics::RoverModel& rover, const FlyingRoverScenario& scenario);

}  // namespace roverlab::simulation

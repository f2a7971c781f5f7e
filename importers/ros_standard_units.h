#pragma once
// Units of the standard ROS messages (REP 103: SI units, angles in rad): the
// unit of a decoded channel of geometry_msgs Wrench, Twist, Pose, Vector3
// (and their Stamped forms), sensor_msgs JointState, Imu, NavSatFix,
// nav_msgs Odometry and tf2_msgs TFMessage, by its field path
// (ros_msg_decoder.h names them). A Vector3 is a bare vector: no unit.

#include <optional>
#include <string>
#include <string_view>

namespace roverlab::io::ros {

struct StandardUnit {
  std::string unit;     // canonical SI unit (core/log/units.h)
  double factor = 1.0;  // SI value = decoded value * factor (NavSatFix degrees -> rad)
};

// "geometry_msgs/WrenchStamped" (or ".../msg/WrenchStamped"), "wrench.force.z"
// -> N. nullopt for other types and fields (covariances, quaternion parts).
std::optional<StandardUnit> standard_unit(std::string_view type, std::string_view channel);

}  // namespace roverlab::io::ros

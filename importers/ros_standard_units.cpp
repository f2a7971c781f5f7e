#include "importers/ros_standard_units.h"

#include <cmath>
#include <vector>

namespace roverlab::io::ros {

namespace {

struct Rule {
  const char* type;     // without "/msg/"
  const char* pattern;  // field path; '*' matches one or more characters
  const char* unit;
  double factor;
};

// REP 103 units of each standard message's fields.
const std::vector<Rule>& rules() {
  static const std::vector<Rule> table = {
      {"geometry_msgs/Wrench", "force.*", "N", 1.0},
      {"geometry_msgs/Wrench", "torque.*", "N*m", 1.0},
      {"geometry_msgs/WrenchStamped", "wrench.force.*", "N", 1.0},
      {"geometry_msgs/WrenchStamped", "wrench.torque.*", "N*m", 1.0},
      {"geometry_msgs/Twist", "linear.*", "m/s", 1.0},
      {"geometry_msgs/Twist", "angular.*", "rad/s", 1.0},
      {"geometry_msgs/TwistStamped", "twist.linear.*", "m/s", 1.0},
      {"geometry_msgs/TwistStamped", "twist.angular.*", "rad/s", 1.0},
      {"geometry_msgs/Pose", "position.*", "m", 1.0},
      {"geometry_msgs/Pose", "orientation.roll", "rad", 1.0},
      {"geometry_msgs/Pose", "orientation.pitch", "rad", 1.0},
      {"geometry_msgs/Pose", "orientation.yaw", "rad", 1.0},
      {"geometry_msgs/PoseStamped", "pose.position.*", "m", 1.0},
      {"geometry_msgs/PoseStamped", "pose.orientation.roll", "rad", 1.0},
      {"geometry_msgs/PoseStamped", "pose.orientation.pitch", "rad", 1.0},
      {"geometry_msgs/PoseStamped", "pose.orientation.yaw", "rad", 1.0},
      {"sensor_msgs/JointState", "position.*", "rad", 1.0},
      {"sensor_msgs/JointState", "velocity.*", "rad/s", 1.0},
      {"sensor_msgs/JointState", "effort.*", "N*m", 1.0},
      {"sensor_msgs/Imu", "orientation.roll", "rad", 1.0},
      {"sensor_msgs/Imu", "orientation.pitch", "rad", 1.0},
      {"sensor_msgs/Imu", "orientation.yaw", "rad", 1.0},
      {"sensor_msgs/Imu", "angular_velocity.*", "rad/s", 1.0},
      {"sensor_msgs/Imu", "linear_acceleration.*", "m/s^2", 1.0},
      {"sensor_msgs/NavSatFix", "latitude", "rad", M_PI / 180.0},
      {"sensor_msgs/NavSatFix", "longitude", "rad", M_PI / 180.0},
      {"sensor_msgs/NavSatFix", "altitude", "m", 1.0},
      {"sensor_msgs/NavSatFix", "position_covariance.*", "m^2", 1.0},
      {"nav_msgs/Odometry", "pose.pose.position.*", "m", 1.0},
      {"nav_msgs/Odometry", "pose.pose.orientation.roll", "rad", 1.0},
      {"nav_msgs/Odometry", "pose.pose.orientation.pitch", "rad", 1.0},
      {"nav_msgs/Odometry", "pose.pose.orientation.yaw", "rad", 1.0},
      {"nav_msgs/Odometry", "twist.twist.linear.*", "m/s", 1.0},
      {"nav_msgs/Odometry", "twist.twist.angular.*", "rad/s", 1.0},
      {"tf2_msgs/TFMessage", "transforms.*.transform.translation.*", "m", 1.0},
      {"tf2_msgs/TFMessage", "transforms.*.transform.rotation.roll", "rad", 1.0},
      {"tf2_msgs/TFMessage", "transforms.*.transform.rotation.pitch", "rad", 1.0},
      {"tf2_msgs/TFMessage", "transforms.*.transform.rotation.yaw", "rad", 1.0},
      {"tf2_msgs/TFMessage", "transforms.*.header.stamp", "s", 1.0},
  };
  return table;
}

// Glob match: '*' stands for one or more characters.
bool matches(std::string_view pattern, std::string_view text) {
  if (pattern.empty()) return text.empty();
  if (pattern[0] != '*') return !text.empty() && text[0] == pattern[0] && matches(pattern.substr(1), text.substr(1));
  for (std::size_t n = 1; n <= text.size(); ++n) {
    if (matches(pattern.substr(1), text.substr(n))) return true;
  }
  return false;
}

// "geometry_msgs/msg/Wrench" (ROS 2) -> "geometry_msgs/Wrench".
std::string ros1_type(std::string_view type) {
  std::string t(type);
  const auto at = t.find("/msg/");
  if (at != std::string::npos) t.erase(at, 4);
  return t;
}

}  // namespace

std::optional<StandardUnit> standard_unit(std::string_view type, std::string_view channel) {
  const std::string t = ros1_type(type);
  for (const Rule& r : rules()) {
    if (t == r.type && matches(r.pattern, channel)) return StandardUnit{r.unit, r.factor};
  }
  return std::nullopt;
}

}  // namespace roverlab::io::ros

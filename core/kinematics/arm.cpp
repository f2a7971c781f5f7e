#include "core/kinematics/arm.h"

#include <cmath>

#include "core/common/error.h"
#include "core/kinematics/rover_model.h"

namespace roverlab::kinematics {

std::vector<std::string> ArmModel::joints() const {
  std::vector<std::string> out;
  out.reserve(links.size());
  for (const auto& l : links) out.push_back(l.joint);
  return out;
}

Eigen::Isometry3d arm_flange_pose(const ArmModel& arm, const std::vector<double>& q) {
  if (q.size() != arm.links.size()) {
    throw DataError("arm " + arm.name + ": " + std::to_string(q.size()) + " joint angles for " +
                    std::to_string(arm.links.size()) + " joints");
  }
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (std::size_t i = 0; i < q.size(); ++i) {
    const ArmLink& l = arm.links[i];
    t = t * dh_transform(l.theta + q[i], l.d, l.a, l.alpha);  // Eq. 2.8, seed 000
  }
  Eigen::Isometry3d pose;
  pose.matrix() = t;
  return pose;
}

double arm_tool_height(const ArmModel& arm, const std::vector<double>& q) {
  return (arm_flange_pose(arm, q) * arm.tool).z();
}

}  // namespace roverlab::kinematics

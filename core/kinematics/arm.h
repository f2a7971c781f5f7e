#pragma once
// Serial manipulators from Denavit-Hartenberg tables (resources/arms/*.json):
// the pose of the tool (a plate, a probe) from the joint angles, for lab rigs
// where an arm pushes a plate into soil. Classic DH (Eq. 2.8 of seed 000,
// Craig's distal convention): T_i = Rz(theta_i + q_i) Tz(d_i) Tx(a_i) Rx(alpha_i).

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace roverlab::kinematics {

struct ArmLink {
  std::string joint;  // the revolute joint turning this link (its angle adds to theta)
  double theta = 0, d = 0, a = 0, alpha = 0;
};

struct ArmModel {
  std::string name, description;
  std::vector<ArmLink> links;                      // base to flange, one per joint
  Eigen::Vector3d tool = Eigen::Vector3d::Zero();  // tool point in the flange frame, m
  std::vector<std::string> joints() const;
};

// The flange-to-base transform at joint angles q (rad, one per link).
// Throws DataError when q has the wrong size.
Eigen::Isometry3d arm_flange_pose(const ArmModel& arm, const std::vector<double>& q);

// The tool point's height (base z) at joint angles q, m.
double arm_tool_height(const ArmModel& arm, const std::vector<double>& q);

}  // namespace roverlab::kinematics

#include "core/kinematics/rover_model.h"

#include <algorithm>

#include "core/common/error.h"

namespace roverlab::kinematics {

int RoverModel::joint_index(const std::string& n) const {
  const auto it = std::find(joints.begin(), joints.end(), n);
  return it == joints.end() ? -1 : static_cast<int>(it - joints.begin());
}

void RoverModel::build_chains(const std::vector<std::string>& drive_frames) {
  if (drive_frames.size() != wheels.size()) throw DataError("one drive frame per wheel is needed");
  for (DhLink& l : links) {
    l.cos_alpha = std::cos(l.alpha);
    l.sin_alpha = std::sin(l.alpha);
    l.cos_theta = std::cos(l.theta);
    l.sin_theta = std::sin(l.theta);
  }
  for (std::size_t w = 0; w < wheels.size(); ++w) {
    WheelChain& c = wheels[w];
    c.links.clear();
    c.bogie_joint = c.steer_joint = -1;
    std::string frame = drive_frames[w];
    while (frame != "g") {
      int found = -1;
      for (std::size_t i = 0; i < links.size(); ++i) {
        if (links[i].to == frame) found = static_cast<int>(i);
      }
      if (found < 0) throw DataError("frame '" + frame + "' of wheel " + c.name + " has no link from a parent frame");
      if (c.links.size() > links.size()) throw DataError("the links of wheel " + c.name + " form a loop");
      c.links.insert(c.links.begin(), found);
      frame = links[static_cast<std::size_t>(found)].from;
    }
    // The first joint along the chain is the bogie's, the second the steering's.
    for (int li : c.links) {
      const int j = links[static_cast<std::size_t>(li)].joint;
      if (j < 0) continue;
      if (c.bogie_joint < 0) {
        c.bogie_joint = j;
      } else if (c.steer_joint < 0) {
        c.steer_joint = j;
      } else {
        throw DataError("wheel " + c.name + ": more than two joints on its chain");
      }
    }
  }
}

Eigen::MatrixXd rover_jacobian(const RoverModel& m, const std::vector<double>& q, const std::vector<double>& gamma,
                               const std::vector<double>& beta, WheelFrame frame) {
  const int nq = static_cast<int>(m.joints.size());
  const int nw = static_cast<int>(m.wheels.size());
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(3 * nw, 6 + nq);
  for (int w = 0; w < nw; ++w) {
    const double g = gamma.empty() ? 0.0 : gamma[static_cast<std::size_t>(w)];
    const double b = beta.empty() ? 0.0 : beta[static_cast<std::size_t>(w)];
    const WheelPose<double> p = wheel_pose<double>(m, w, q.data(), g, b, frame);
    const Eigen::Matrix3d Rt = p.R.transpose();
    J.block<3, 3>(3 * w, 0) = Rt;  // vJ
    Eigen::Matrix3d rx;
    rx << 0, -p.r.z(), p.r.y(), p.r.z(), 0, -p.r.x(), -p.r.y(), p.r.x(), 0;
    J.block<3, 3>(3 * w, 3) = -Rt * rx;  // omega J = R [-r x]
    const WheelChain& c = m.wheels[static_cast<std::size_t>(w)];
    if (c.bogie_joint >= 0) J.block<3, 1>(3 * w, 6 + c.bogie_joint) = Rt * p.dr_dbogie;
    if (c.steer_joint >= 0) J.block<3, 1>(3 * w, 6 + c.steer_joint) = Rt * p.dr_dsteer;
  }
  return J;
}

WheelAngles wheel_angles(const Eigen::Vector3d& v) {
  WheelAngles a;
  a.speed = v.norm();
  if (std::abs(v.x()) < 1e-12) return a;  // singular (section 5.1): undefined, reported 0
  a.contact = std::atan(-v.y() / v.x());
  const double vcx = std::cos(a.contact) * v.x() - std::sin(a.contact) * v.y();
  a.speed_in_plane = vcx;
  a.side_slip = std::abs(vcx) < 1e-12 ? 0.0 : std::atan(v.z() / vcx);
  return a;
}

}  // namespace roverlab::kinematics

#pragma once
// Rover kinematics from Denavit-Hartenberg descriptions (seed 000, Vijayan
// 2018, chapters 2, 4 and 5): DH transforms (Eq. 2.8), the pose of each
// wheel's drive frame, optionally rotated into its contact frame (contact
// angle gamma) and side-slip frame (side-slip angle beta) as in Table 5.2, the
// wheel Jacobian (Eq. 4.8 and Table 5.1) and the rover Jacobian (Eq. 4.10).
// Templated on the scalar so that filters differentiate them with ceres::Jet.

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace roverlab::kinematics {

struct DhLink {
  std::string from, to;
  double theta = 0, d = 0, a = 0, alpha = 0;  // theta is the offset when the link has a joint
  int joint = -1;                             // index into RoverModel::joints, -1: fixed link
  // cos/sin of alpha and (for a fixed link) of theta, cached by RoverModel::build_chains.
  double cos_alpha = 1, sin_alpha = 0, cos_theta = 1, sin_theta = 0;
};

struct WheelChain {
  std::string name;                        // FL ML RL RR MR FR (seed 000's order)
  std::vector<int> links;                  // from the body frame g to the wheel's drive frame
  int bogie_joint = -1, steer_joint = -1;  // joints on the chain (-1: none)
};

// Sensor noise covariances (seed 000 Table 6.1 for ExoMars BB2).
struct SensorNoise {
  std::vector<double> steer_angle, steer_rate, wheel_rate;  // per wheel
  std::vector<double> bogie_angle, bogie_rate;              // per bogie joint
  Eigen::Vector3d gyro = Eigen::Vector3d::Constant(1e-6), accelerometer = Eigen::Vector3d::Constant(1e-3);
};

struct RoverModel {
  std::string name, description;
  double wheel_radius = 0.1;
  std::vector<std::string> joints;  // joint variables, e.g. bogie_FL .. steer_FR
  std::vector<DhLink> links;
  std::vector<WheelChain> wheels;
  SensorNoise noise;
  int joint_index(const std::string& name) const;  // -1 when absent
  // Resolves every wheel's chain from its drive frame back to "g" and caches
  // the links' constant cosines and sines. Throws DataError for a frame
  // without a parent or a loop.
  void build_chains(const std::vector<std::string>& drive_frames);
};

// Which frame the wheel velocity is expressed in: drive (smooth terrain,
// chapter 4), contact (model C) or side slip (model C+SS).
enum class WheelFrame { drive, contact, side_slip };

template <class T>
using Vec3 = Eigen::Matrix<T, 3, 1>;
template <class T>
using Mat3 = Eigen::Matrix<T, 3, 3>;
template <class T>
using Mat4 = Eigen::Matrix<T, 4, 4>;

// Eq. 2.8: the transform of frame i in frame i-1.
template <class T>
Mat4<T> dh_transform(const T& theta, double d, double a, double alpha) {
  using std::cos;
  using std::sin;
  const T ct = cos(theta), st = sin(theta);
  const double ca = std::cos(alpha), sa = std::sin(alpha);
  Mat4<T> m;
  m << ct, -st * ca, st * sa, T(a) * ct, st, ct * ca, -ct * sa, T(a) * st, T(0), T(sa), T(ca), T(d), T(0), T(0), T(0),
      T(1);
  return m;
}

// X <- X * dh_transform(theta, d, a, alpha) without the full 4x4 product,
// from the cosines and sines of theta and alpha: the DH matrix's last row is
// (0 0 0 1) and d, a, alpha are constants, so only the cos/sin of theta
// multiply X in the scalar type (what matters for ceres::Jet).
template <class T>
void append_dh(Mat4<T>& X, const T& ct, const T& st, double d, double a, double ca, double sa) {
  for (int r = 0; r < 3; ++r) {
    const T x0 = X(r, 0), x1 = X(r, 1), x2 = X(r, 2);
    const T u = x0 * ct + x1 * st, v = x1 * ct - x0 * st;
    X(r, 0) = u;
    X(r, 1) = v * ca + x2 * sa;
    X(r, 2) = x2 * ca - v * sa;
    X(r, 3) = X(r, 3) + u * a + x2 * d;
  }
}

// The same from theta and alpha.
template <class T>
void append_dh(Mat4<T>& X, const T& theta, double d, double a, double alpha) {
  using std::cos;
  using std::sin;
  append_dh<T>(X, T(cos(theta)), T(sin(theta)), d, a, std::cos(alpha), std::sin(alpha));
}

// A wheel's final frame in the body frame g: rotation R (frame -> g),
// origin r, and dr/dq for its two joints (bogie, steering; revolute, so
// z_{i-1} x (r - o_{i-1}) as in any geometric Jacobian).
template <class T>
struct WheelPose {
  Mat3<T> R;
  Vec3<T> r;
  Vec3<T> dr_dbogie = Vec3<T>::Zero(), dr_dsteer = Vec3<T>::Zero();
};

// q: all joint angles (RoverModel::joints order).
template <class T>
WheelPose<T> wheel_pose(const RoverModel& m, int wheel, const T* q, const T& gamma, const T& beta, WheelFrame frame) {
  const WheelChain& w = m.wheels[static_cast<std::size_t>(wheel)];
  Mat4<T> X = Mat4<T>::Identity();
  struct JointAt {
    int joint;
    Vec3<T> z, o;
  };
  JointAt joints[4];
  int nj = 0;
  for (int li : w.links) {
    const DhLink& l = m.links[static_cast<std::size_t>(li)];
    T theta(l.theta);
    if (l.joint >= 0) {
      theta += q[l.joint];
      if (nj < 4) joints[nj++] = {l.joint, X.template block<3, 1>(0, 2), X.template block<3, 1>(0, 3)};
    }
    append_dh<T>(X, theta, l.d, l.a, l.alpha);  // Eq. 2.8
  }
  // Table 5.2: d -> c rotates by -gamma about the axle (alpha = pi/2), c -> ss by beta.
  if (frame != WheelFrame::drive) append_dh<T>(X, -gamma, 0.0, 0.0, M_PI / 2);
  if (frame == WheelFrame::side_slip) append_dh<T>(X, beta, 0.0, 0.0, 0.0);
  WheelPose<T> p;
  p.R = X.template block<3, 3>(0, 0);
  p.r = X.template block<3, 1>(0, 3);
  for (int k = 0; k < nj; ++k) {
    const Vec3<T> col = joints[k].z.cross(p.r - joints[k].o);
    if (joints[k].joint == w.bogie_joint) p.dr_dbogie = col;
    if (joints[k].joint == w.steer_joint) p.dr_dsteer = col;
  }
  return p;
}

// Eq. 4.8 / Table 5.1: the wheel's velocity in its final frame,
// R^T (v + omega x r + dr/dq qdot), from the body velocity v and rate omega
// (both in g) and the joint rates qdot.
template <class T>
Vec3<T> wheel_velocity(const RoverModel& m, int wheel, const T* q, const T* qdot, const Vec3<T>& v,
                       const Vec3<T>& omega, const T& gamma, const T& beta, WheelFrame frame) {
  const WheelPose<T> p = wheel_pose<T>(m, wheel, q, gamma, beta, frame);
  const WheelChain& w = m.wheels[static_cast<std::size_t>(wheel)];
  Vec3<T> u = v + omega.cross(p.r);
  if (w.bogie_joint >= 0) u += p.dr_dbogie * qdot[w.bogie_joint];
  if (w.steer_joint >= 0) u += p.dr_dsteer * qdot[w.steer_joint];
  return p.R.transpose() * u;
}

// Eq. 4.10: the rover Jacobian, one 3-row block per wheel, columns
// [v (3), omega (3), qdot (joints)], at joint angles q and angles gamma, beta
// (per wheel; ignored for the drive frame).
Eigen::MatrixXd rover_jacobian(const RoverModel& m, const std::vector<double>& q, const std::vector<double>& gamma,
                               const std::vector<double>& beta, WheelFrame frame);

// Contact and side-slip angles of a wheel velocity in the drive frame
// (seed 000 sections 5.1 and 5.2): gamma = atan(-v.y_d / v.x_d) and
// beta = atan(v.y_c / v.x_c) with v_c the velocity in the contact frame.
struct WheelAngles {
  double contact = 0, side_slip = 0;
  double speed_in_plane = 0;  // v . x_c, what slip is defined against
  double speed = 0;           // |v|
};
WheelAngles wheel_angles(const Eigen::Vector3d& v_drive);

}  // namespace roverlab::kinematics

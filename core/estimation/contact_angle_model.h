#pragma once
// The process and measurement models of seed 000's contact-angle estimator
// (Vijayan 2018, Eq. 4.13-4.20, Table 5.1), shared by the filters in
// contact_angle.cpp and by the tests. The measurement of one wheel is
// linearised two ways: by ceres::Jet (the reference) and by hand (the fast
// path, tested equal to the Jet one).

#include <Eigen/Core>

#include "core/kinematics/rover_model.h"

namespace roverlab::estimation::contact {

inline constexpr int kMaxJoints = 16;

// Inputs of one step.
struct Inputs {
  Eigen::Vector3d gyro = Eigen::Vector3d::Zero(), accel = Eigen::Vector3d::Zero();
  double q[kMaxJoints] = {}, qdot[kMaxJoints] = {};
  double wheel_rate[6] = {};
};

// Cosines and sines of the Euler angles (psi, theta, phi).
template <class T>
struct AttitudeTrig {
  T cps, sps, cth, sth, cph, sph;
};
template <class T>
AttitudeTrig<T> attitude_trig(const T* att) {
  using std::cos;
  using std::sin;
  return {cos(att[0]), sin(att[0]), cos(att[1]), sin(att[1]), cos(att[2]), sin(att[2])};
}

// Eq. 4.14 and 4.13 (discretised as Eq. 4.17): attitude (psi, theta, phi)
// and body velocity at the next step; n_* are the process noises and the
// gyro / accelerometer noises (true = measured - noise). tr holds the
// cosines and sines of att.
template <class T>
void strapdown(const T* att, const AttitudeTrig<T>& tr, const T* v, const T* n_att, const T* n_v, const T* n_f,
               const T* n_w, const Inputs& in, const Eigen::Vector3d& g_i, double ts, T* att_next, T* v_next) {
  const T w[3] = {T(in.gyro.x()) - n_w[0], T(in.gyro.y()) - n_w[1], T(in.gyro.z()) - n_w[2]};
  const T& cth = tr.cth;
  const T& sth = tr.sth;
  const T& cph = tr.cph;
  const T& sph = tr.sph;
  const T& cps = tr.cps;
  const T& sps = tr.sps;
  // Eq. 4.14.
  const T d_psi = (sph * w[1] + cph * w[2]) / cth;
  const T d_th = cph * w[1] - sph * w[2];
  const T d_ph = w[0] + (sth * sph * w[1] + sth * cph * w[2]) / cth;
  att_next[0] = att[0] + d_psi * ts + n_att[0];
  att_next[1] = att[1] + d_th * ts + n_att[1];
  att_next[2] = att[2] + d_ph * ts + n_att[2];
  // R_g^i = Rz(psi) Ry(theta) Rx(phi); gravity in g is R_g^i^T g^i.
  const T R[3][3] = {{cps * cth, cps * sth * sph - sps * cph, cps * sth * cph + sps * sph},
                     {sps * cth, sps * sth * sph + cps * cph, sps * sth * cph - cps * sph},
                     {-sth, cth * sph, cth * cph}};
  T g_g[3];
  for (int k = 0; k < 3; ++k) g_g[k] = R[0][k] * g_i.x() + R[1][k] * g_i.y() + R[2][k] * g_i.z();
  // Eq. 4.13: v' = -w x v + f - g.
  const T wxv[3] = {w[1] * v[2] - w[2] * v[1], w[2] * v[0] - w[0] * v[2], w[0] * v[1] - w[1] * v[0]};
  for (int k = 0; k < 3; ++k) {
    const T dv = -wxv[k] + (T(in.accel[k]) - n_f[k]) - g_g[k];
    v_next[k] = v[k] + dv * ts + n_v[k];
  }
}

template <class T>
void strapdown(const T* att, const T* v, const T* n_att, const T* n_v, const T* n_f, const T* n_w, const Inputs& in,
               const Eigen::Vector3d& g_i, double ts, T* att_next, T* v_next) {
  strapdown<T>(att, attitude_trig<T>(att), v, n_att, n_v, n_f, n_w, in, g_i, ts, att_next, v_next);
}

// One wheel's three measurements (Eq. 4.20 / Table 5.1): wheel rate and the
// lateral and normal velocity in the final frame. q_b, q_s, qd_b, qd_s are
// the wheel's bogie and steering angles and rates (noise already removed).
template <class T>
void wheel_measurement(const kinematics::RoverModel& m, int wheel, kinematics::WheelFrame frame, const T* v,
                       const T& slip, const T& gamma, const T& beta, const T* n_w, const T& q_b, const T& q_s,
                       const T& qd_b, const T& qd_s, const Inputs& in, T out[3]) {
  const std::size_t nq = m.joints.size();
  T q[kMaxJoints], qd[kMaxJoints];
  for (std::size_t j = 0; j < nq; ++j) {
    q[j] = T(in.q[j]);
    qd[j] = T(in.qdot[j]);
  }
  const auto& c = m.wheels[static_cast<std::size_t>(wheel)];
  if (c.bogie_joint >= 0) {
    q[c.bogie_joint] = q_b;
    qd[c.bogie_joint] = qd_b;
  }
  if (c.steer_joint >= 0) {
    q[c.steer_joint] = q_s;
    qd[c.steer_joint] = qd_s;
  }
  const kinematics::Vec3<T> vel(v[0], v[1], v[2]);
  const kinematics::Vec3<T> w(T(in.gyro.x()) - n_w[0], T(in.gyro.y()) - n_w[1], T(in.gyro.z()) - n_w[2]);
  const kinematics::Vec3<T> u = kinematics::wheel_velocity<T>(m, wheel, q, qd, vel, w, gamma, beta, frame);
  using std::cos;
  const T scale = frame == kinematics::WheelFrame::side_slip ? cos(beta) : T(1.0);
  out[0] = scale * u.x() / ((T(1.0) - slip) * m.wheel_radius);
  out[1] = u.y();
  out[2] = u.z();
}

// The drive frame of a wheel at given joint angles, with what the velocity
// and its derivatives need: the chain's joint axes z and origins o (first the
// bogie's, then the steering's) and the geometric Jacobian columns J = z x (r - o).
struct WheelGeometry {
  Eigen::Matrix3d Rd = Eigen::Matrix3d::Identity();
  Eigen::Vector3d r = Eigen::Vector3d::Zero();
  Eigen::Vector3d z[2], o[2], J[2];
  int joint[2] = {-1, -1};
  int nj = 0;
};
WheelGeometry wheel_geometry(const kinematics::RoverModel& m, int wheel, const double* q);

// Table 5.2: the drive -> contact (-gamma about the axle, then pi/2 about x)
// or side-slip (beta more about z) rotation.
Eigen::Matrix3d final_rotation(kinematics::WheelFrame frame, double gamma, double beta);
// The same from the cosines and sines of gamma and beta.
Eigen::Matrix3d final_rotation(kinematics::WheelFrame frame, double cg, double sg, double cb, double sb);

// wheel_measurement in double from a wheel's geometry, final rotation C and
// cos(beta): the same three values (tested equal).
inline Eigen::Vector3d wheel_measurement(const WheelGeometry& g, const Eigen::Matrix3d& C, kinematics::WheelFrame frame,
                                         double wheel_radius, const double* v, double slip, double cos_beta,
                                         const Eigen::Vector3d& omega, const double* qdot) {
  Eigen::Vector3d w = Eigen::Vector3d(v[0], v[1], v[2]) + omega.cross(g.r);  // Eq. 4.8
  for (int k = 0; k < g.nj; ++k) w += g.J[k] * qdot[g.joint[k]];
  const Eigen::Vector3d u = C.transpose() * (g.Rd.transpose() * w);
  const double sc = frame == kinematics::WheelFrame::side_slip ? cos_beta : 1.0;
  return Eigen::Vector3d(sc * u.x() / ((1.0 - slip) * wheel_radius), u.y(), u.z());  // Eq. 4.20 / Table 5.1
}

// One wheel's measurement and its derivatives at zero noise, columns:
// velocity (3), slip, contact angle, side-slip angle, gyro noise (3), bogie
// angle, steering angle, bogie rate, steering rate (the joint columns are
// derivatives with respect to the joint values, not their noises).
struct WheelLinearization {
  Eigen::Vector3d value;
  Eigen::Matrix<double, 3, 13> d;
};

// By ceres::Jet through wheel_measurement (the reference).
WheelLinearization linearize_wheel_autodiff(const kinematics::RoverModel& m, int wheel, kinematics::WheelFrame frame,
                                            const double* v, double slip, double gamma, double beta, const Inputs& in);

// By hand: the wheel velocity's derivatives from the geometric Jacobian of
// the DH chain (dJ_a/dq_k = z_min(a,k) x J_max(a,k), dR/dq_k = [z_k]x R)
// and the closed-form contact and side-slip rotations.
WheelLinearization linearize_wheel(const kinematics::RoverModel& m, int wheel, kinematics::WheelFrame frame,
                                   const double* v, double slip, double gamma, double beta, const Inputs& in);

}  // namespace roverlab::estimation::contact

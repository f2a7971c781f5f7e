#pragma once
// The process and measurement models of seed 000's contact-angle estimator
// (Vijayan 2018, Eq. 4.13-4.20, Table 5.1), shared by the filters in
// contact_angle.cpp and by the tests. The measurement of one wheel is
// linearised two ways: by ceres::Jet (the reference) and by hand (the fast
// path, tested equal to the Jet one). ContactProcessModel and
// WheelMeasurementModel package them for the filters: the generic EKF and
// UKF of nonlinear_filter.h and the structured fast EKF consume the same two
// model types.

#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "core/filters/nonlinear_filter.h"
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
struct WheelGeometry {  // NOLINT(bugprone-reserved-identifier): Eigen's aligned-new macro, not our names
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

// Sizes of the state, process noise, measurement and measurement noise.
// State: attitude (psi, theta, phi), body velocity, six slips, then na
// angles (contact angles, then side-slip angles): the indices below name it.
struct ContactLayout {
  static constexpr int kAttitude = 0;        // psi, theta, phi (Eq. 4.13, seed 000)
  static constexpr int kVelocity = 3;        // body velocity (Eq. 4.14)
  static constexpr int kSlip = 6;            // six slips (Eq. 4.15)
  static constexpr int kContactAngle = 12;   // six contact angles (Eq. 5.3-5.4)
  static constexpr int kSideSlipAngle = 18;  // six side-slip angles (Eq. 5.5-5.6)
  static constexpr int kWheels = 6;
  // Wheel w's p-th private state: its slip (p = 0), contact angle (1) and
  // side-slip angle (2).
  static constexpr int wheel_state(int p, int w) { return kSlip + kWheels * p + w; }
  static constexpr int slip(int w) { return kSlip + w; }
  static constexpr int contact_angle(int w) { return kContactAngle + w; }
  static constexpr int side_slip_angle(int w) { return kSideSlipAngle + w; }
  int na = 0;  // angle states per wheel set: 0, 6 or 12
  int nw = 6, nq = 9;
  int nx() const { return 12 + na; }
  int np() const { return nx() + 6; }  // n_att, n_v, n_s, n_gamma, n_beta, n_f, n_w
  int ny() const { return 3 * nw; }
  int nm() const { return 3 + nw + 2 * nq + 2 * nw; }  // n_w(gyro), n_wheel, n_q, n_qdot, n_vy, n_vz
};

// The process model: strapdown attitude and velocity (Eq. 4.13-4.14), damped
// slip (Eq. 4.15) and random-walk or damped angles (Eq. 5.3-5.6). Process
// noise order: n_att, n_v, n_s, n_gamma, n_beta (additive), then n_f, n_w.
class ContactProcessModel {
 public:
  ContactProcessModel() = default;
  // slip_decay and angle_decay in 1/s (0: random walk).
  ContactProcessModel(ContactLayout layout, const Eigen::Vector3d& g_i, double slip_decay, double angle_decay);
  const ContactLayout& layout() const { return layout_; }
  // The factors slip and angles keep over a step of ts seconds.
  double slip_keep(double ts) const { return 1.0 - slip_decay_ * ts; }
  double angle_keep(double ts) const { return 1.0 - angle_decay_ * ts; }
  // x' = f(x, n) in double (the UKF's sigma points).
  void evaluate(const Eigen::VectorXd& x, const Eigen::VectorXd& n, const Inputs& in, double ts,
                Eigen::VectorXd& out) const;
  // f(x, 0) and its Jacobians by ceres::Jet (the generic EKF).
  Linearized linearize(const Eigen::VectorXd& x, const Inputs& in, double ts) const;
  // The fast EKF's part: attitude and velocity (att_v[0..5]) advanced in
  // place at zero noise, with their Jacobians with respect to themselves (A)
  // and to n_f, n_w (B); n_att and n_v enter with identity. Defined with the
  // fast EKF (contact_angle_fast_ekf.h), as are the other fast-path members.
  void strapdown_step(double* att_v, const Inputs& in, double ts, Eigen::Matrix<double, 6, 6>& A,
                      Eigen::Matrix<double, 6, 6>& B) const;

 private:
  ContactLayout layout_;
  Eigen::Vector3d g_i_ = Eigen::Vector3d::Zero();
  double slip_decay_ = 0, angle_decay_ = 0;
  // The attitude whose cosines and sines are in trig_ (sigma points mostly share it).
  mutable double trig_att_[3] = {NAN, NAN, NAN};
  mutable AttitudeTrig<double> trig_{};
};

// The measurement model: each wheel's rate and zero lateral and normal
// velocity (Eq. 4.20, Table 5.1), measurement order: the six rates, the six
// lateral, the six normal velocities. Noise order (generic EKF, r vectors):
// n_w (gyro 3), n_wheel (6), n_q, n_qdot, n_vy (6), n_vz (6); the UKF's puts
// the additive noises last (ukf_noise_order).
class WheelMeasurementModel {  // NOLINT(bugprone-reserved-identifier): as WheelGeometry
 public:
  WheelMeasurementModel() = default;
  WheelMeasurementModel(const kinematics::RoverModel& m, kinematics::WheelFrame frame, ContactLayout layout);
  const ContactLayout& layout() const { return layout_; }

  // The fast EKF: one wheel linearised by hand at state x.
  WheelLinearization linearize_wheel(int wheel, const double* x, const Inputs& in) const;
  // S += M R M^T for R = diag(r) on S's lower 3 x 3 blocks (wheel w1 >= w2;
  // the fast EKF's factorisation reads only those): wheel-rate, lateral and
  // normal noises on their own rows; the gyro noise couples every wheel, a
  // joint's noise the wheels it carries.
  void add_noise_covariance(const WheelLinearization* lin, const Eigen::VectorXd& r,
                            Eigen::Matrix<double, 18, 18>& S) const;

  // The generic EKF: h(x, 0) and its Jacobians, each wheel by ceres::Jet.
  Linearized linearize(const Eigen::VectorXd& x, const Inputs& in) const;

  // The UKF: r reordered as n_w, n_q, n_qdot, then n_wheel, n_vy, n_vz.
  Eigen::VectorXd ukf_noise_order(const Eigen::VectorXd& r) const;
  // This step's inputs: each wheel's geometry at the measured joint angles.
  void set_inputs(const Inputs& in);
  // y = h(x, n) at a sigma point (UKF noise order).
  void evaluate(const Eigen::VectorXd& x, const Eigen::VectorXd& n, Eigen::VectorXd& y);
  // The same at a sigma point that differs from the centre only in the
  // listed entries, given the centre's y0: wheels they do not reach keep the
  // centre's rows.
  void evaluate_incremental(const Eigen::VectorXd& x, const Eigen::VectorXd& n,
                            const std::vector<Eigen::Index>& changed_x, const std::vector<Eigen::Index>& changed_n,
                            const Eigen::VectorXd& y0, Eigen::VectorXd& y);

 private:
  // A wheel's final rotation at (gamma, beta) with their cosines and sines,
  // and T = (R_d C)^T, g to the final frame at the measured joint angles.
  struct RotationMemo {
    double gamma = NAN, beta = NAN, cg = 1.0, sg = 0.0, cb = 1.0, sb = 0.0;
    Eigen::Matrix3d C, T;
  };
  const RotationMemo& rotation(int wheel, double gamma, double beta);
  void evaluate_wheel(int wheel, const Eigen::VectorXd& x, const Eigen::VectorXd& n, Eigen::VectorXd& y);

  const kinematics::RoverModel* m_ = nullptr;
  kinematics::WheelFrame frame_ = kinematics::WheelFrame::contact;
  ContactLayout layout_;
  std::vector<std::vector<int>> wheels_of_joint_;
  Inputs in_;
  WheelGeometry geometry_[6];          // at the measured joint angles
  Eigen::Vector3d joint_velocity_[6];  // sum_k J_k qdot_k there, at the measured joint rates
  RotationMemo memo_[6][2];            // kept while gamma and beta repeat
};

}  // namespace roverlab::estimation::contact

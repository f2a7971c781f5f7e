#include "core/estimation/ins_slip/models.h"

#include "core/estimation/ins_slip/ins_slip.h"

namespace roverlab::estimation {

InsErrorMatrix InsErrorProcess::noise_covariance(double dt) const {
  // Eq. 14's diagonal terms, to first order in dt.
  InsErrorMatrix Q = InsErrorMatrix::Zero();
  Q.block<3, 3>(0, 0).diagonal().setConstant(noise_.gyro_arw * noise_.gyro_arw * dt);
  Q.block<3, 3>(3, 3).diagonal().setConstant(noise_.accel_vrw * noise_.accel_vrw * dt);
  Q.block<3, 3>(9, 9).diagonal().setConstant(noise_.accel_bias_walk * noise_.accel_bias_walk * dt);
  Q.block<3, 3>(12, 12).diagonal().setConstant(noise_.gyro_bias_walk * noise_.gyro_bias_walk * dt);
  return Q;
}

InsMeasurement ZeroVelocityUpdate::at(const InsState& s) const {
  InsMeasurement m;  // Eq. 17-18
  m.H = Eigen::MatrixXd::Zero(3, 15);
  m.H.block<3, 3>(0, 3).setIdentity();
  m.R = Eigen::MatrixXd::Identity(3, 3) * sigma * sigma;
  m.y = -s.v_n;
  return m;
}

InsMeasurement ZeroAngularRateUpdate::at(const InsState& s, const Eigen::Vector3d& mean_rate) const {
  InsMeasurement m;  // Eq. 19-20
  m.H = Eigen::MatrixXd::Zero(3, 15);
  m.H.block<3, 3>(0, 12) = -Eigen::Matrix3d::Identity();
  const Eigen::Vector3d w_meas = mean_rate - s.gyro_bias;
  m.R = Eigen::MatrixXd::Identity(3, 3) * sigma * sigma;
  m.y = -w_meas;
  return m;
}

InsMeasurement NonHolonomicUpdate::at(const InsState& s, const Eigen::Matrix3d& C_nb, const Eigen::Vector3d& w) const {
  InsMeasurement m;  // Eq. 21-23
  const Eigen::Vector3d v_wheel = C_cb * (C_nb * s.v_n - skew(w) * lever_arm);
  m.H = Eigen::MatrixXd::Zero(2, 15);
  m.H.block<2, 3>(0, 0) = (C_cb * C_nb * skew(s.v_n)).bottomRows<2>();  // attitude term, dropped in Eq. 22
  m.H.block<2, 3>(0, 3) = (C_cb * C_nb).bottomRows<2>();
  m.R = Eigen::MatrixXd::Zero(2, 2);
  m.R(0, 0) = lateral_sigma * lateral_sigma;
  m.R(1, 1) = vertical_sigma * vertical_sigma;
  m.y = -v_wheel.tail<2>();
  return m;
}

InsMeasurement WheelSpeedUpdate::at(const InsState& s, const Eigen::Matrix3d& C_nb, double wheel_speed) const {
  InsMeasurement m;
  m.H = Eigen::MatrixXd::Zero(1, 15);
  m.H.block<1, 3>(0, 0) = (C_cb * C_nb * skew(s.v_n)).topRows<1>();
  m.H.block<1, 3>(0, 3) = (C_cb * C_nb).topRows<1>();
  m.y = Eigen::VectorXd(1);
  m.y(0) = wheel_speed - (C_cb * C_nb * s.v_n).x();
  m.R = Eigen::MatrixXd::Identity(1, 1) * sigma * sigma;
  m.gate = gate;
  return m;
}

}  // namespace roverlab::estimation

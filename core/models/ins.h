#pragma once
// Strapdown INS in a local-level (north-east-down) frame with curvilinear
// position, after seed 002 section 4.1 (Groves 2013 notation), and the
// 15-state error model of section 4.2.

#include <Eigen/Dense>

namespace roverlab::estimation {

struct InsOptions {
  bool earth_rotation = false;  // omega_ie terms of Eq. 2-3 (off for a rover)
  bool transport_rate = false;  // omega_en terms of Eq. 2-3 (off for a rover)
};

struct InsState {
  Eigen::Matrix3d C_bn = Eigen::Matrix3d::Identity();    // body -> NED
  Eigen::Vector3d v_n = Eigen::Vector3d::Zero();         // velocity, NED, m/s
  double latitude = 0.0, longitude = 0.0, height = 0.0;  // rad, rad, m
  Eigen::Vector3d accel_bias = Eigen::Vector3d::Zero();  // m/s^2
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero();   // rad/s
};

// WGS-84 radii of curvature: meridian R_N and transverse R_E.
double meridian_radius(double latitude);
double transverse_radius(double latitude);
// Somigliana gravity with the free-air correction, down component, m/s^2.
double gravity_down(double latitude, double height);

Eigen::Matrix3d skew(const Eigen::Vector3d& v);
// Roll, pitch, yaw (rad) of a body->NED rotation (Eq. 25) and back.
Eigen::Vector3d euler_from_dcm(const Eigen::Matrix3d& C_bn);
Eigen::Matrix3d dcm_from_euler(double roll, double pitch, double yaw);

// One mechanisation step with bias-corrected IMU samples f_b (specific force,
// m/s^2) and w_b (angular rate, rad/s) over dt seconds (Eq. 2-6).
void mechanize(InsState& s, const Eigen::Vector3d& f_b, const Eigen::Vector3d& w_b, double dt,
               const InsOptions& options);

// Error-state system matrix F (Eq. 9) for the state order
// (attitude, velocity, position (lat, lon, h), accel bias, gyro bias), with
// errors defined as truth - estimate and C_true = (I + [dpsi x]) C_est.
Eigen::Matrix<double, 15, 15> error_system_matrix(const InsState& s, const Eigen::Vector3d& f_b,
                                                  const InsOptions& options);

// Applies an error-state correction to the state (Eq. 24-27) and keeps C_bn
// orthonormal.
void correct(InsState& s, const Eigen::Matrix<double, 15, 1>& dx);

}  // namespace roverlab::estimation

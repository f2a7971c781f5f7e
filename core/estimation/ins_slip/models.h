#pragma once
// The models of the INS slip estimator (seed 002), apart from the filter that
// runs them: the 15-state error process of the strapdown INS and the
// pseudo-measurements (ZUPT, ZARU, NHC) and wheel-speed update, each as H, R
// and the innovation y about the current nominal state.

#include <Eigen/Dense>
#include <cmath>

#include "core/models/ins.h"

namespace roverlab::estimation {

struct ImuNoise;

using InsErrorVector = Eigen::Matrix<double, 15, 1>;
using InsErrorMatrix = Eigen::Matrix<double, 15, 15>;

// Error-state process: attitude, velocity, position (lat, lon, h), accel
// bias, gyro bias.
class InsErrorProcess {
 public:
  InsErrorProcess(const ImuNoise& noise, const InsOptions& ins) : noise_(noise), ins_(ins) {}
  // F at the state before a mechanisation step with bias-corrected force f (Eq. 9).
  InsErrorMatrix system_matrix(const InsState& s, const Eigen::Vector3d& f) const {
    return error_system_matrix(s, f, ins_);
  }
  // Eq. 11: first-order transition over dt.
  static InsErrorMatrix transition(const InsErrorMatrix& F, double dt) { return InsErrorMatrix::Identity() + F * dt; }
  // Noise assembly: a first-order Q (Eq. 14's diagonal terms).
  InsErrorMatrix noise_covariance(double dt) const;

 private:
  const ImuNoise& noise_;
  const InsOptions& ins_;
};

// One linearised measurement: y = H dx + v, v ~ N(0, R); rejected when its
// normalised innovation squared exceeds `gate`.
struct InsMeasurement {
  Eigen::MatrixXd H, R;
  Eigen::VectorXd y;
  double gate = HUGE_VAL;
};

// Eq. 17-18: the velocity is zero.
struct ZeroVelocityUpdate {
  double sigma;  // m/s
  InsMeasurement at(const InsState& s) const;
};

// Eq. 19-20: the angular rate is zero; `mean_rate` is the raw rate averaged
// over the update interval.
struct ZeroAngularRateUpdate {
  double sigma;  // rad/s
  InsMeasurement at(const InsState& s, const Eigen::Vector3d& mean_rate) const;
};

// Eq. 21-23: no lateral or vertical velocity at the wheels. C_nb is the
// nav-to-body rotation at the start of the update epoch, w the bias-corrected
// angular rate.
struct NonHolonomicUpdate {
  Eigen::Vector3d lever_arm;                           // body frame, IMU to wheel-axle centre, m
  double lateral_sigma, vertical_sigma;                // m/s
  Eigen::Matrix3d C_cb = Eigen::Matrix3d::Identity();  // IMU body to chassis axes (mounting)
  InsMeasurement at(const InsState& s, const Eigen::Matrix3d& C_nb, const Eigen::Vector3d& w) const;
};

// Forward speed from the wheels (seed 002 section 5.1), gated so that slipping
// wheels are not used. C_nb as for NonHolonomicUpdate.
struct WheelSpeedUpdate {
  double sigma;                                        // m/s
  double gate;                                         // chi-square(1) quantile
  Eigen::Matrix3d C_cb = Eigen::Matrix3d::Identity();  // IMU body to chassis axes (mounting)
  InsMeasurement at(const InsState& s, const Eigen::Matrix3d& C_nb, double wheel_speed) const;
};

}  // namespace roverlab::estimation

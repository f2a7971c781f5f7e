#pragma once
// The models of seed 003's net-traction estimators (Setterfield 2011,
// sections 5.4-5.6) for the planar rocker-bogie of core/simulation: the
// general estimator's process and measurement models (Estimator 1, 22
// states), the measurements built from the sensors for it, and the wheel
// force estimators' measurement model (Estimators 2 and 3, 9 states) with the
// contact-angle and single-axis force measurements built from Estimator 1's
// estimates (Figure 5.1). The filters are the generic UKF
// (nonlinear_filter.h).
//
// Conventions are the simulator's: angles clockwise positive in the world
// X (forward) - Z (up) plane; the configuration is (x0, z0, pitch, bogie,
// wheel 1..3); wheel 1 rides on the rocker, wheels 2 and 3 on the bogie (the
// seed numbers the bogie wheels 1 and 2); contact angle gamma = atan(dz/dx)
// of the path under the wheel (positive uphill).

#include <array>
#include <cmath>
#include <functional>

#include <Eigen/Core>

#include "core/simulation/rocker_bogie.h"
#include "core/simulation/rocker_bogie_dynamics.h"

namespace roverlab::estimation::net_traction {

// Eq. 5.18: Estimator 1's state, in the seed's order.
namespace general {
constexpr int kWheelRate = 0;           // qdot_2..4 (3), rad/s
constexpr int kResistiveTorque = 3;     // tau_R1..3 (3), N m
constexpr int kPitch = 6;               // theta_0y, rad
constexpr int kBogie = 7;               // q_1, rad
constexpr int kPitchRate = 8;           // rad/s
constexpr int kBogieRate = 9;           // rad/s
constexpr int kPitchAcceleration = 10;  // rad/s^2
constexpr int kBogieAcceleration = 11;  // rad/s^2
constexpr int kAccelerationX = 12;      // xddot_0, world, m/s^2
constexpr int kAccelerationZ = 13;      // zddot_0, world, m/s^2
constexpr int kMomentBody = 14;         // M_0fw, N m
constexpr int kMomentBogie = 15;        // M_1fw, N m
constexpr int kForceX = 16;             // F_xfw, N
constexpr int kForceZ = 17;             // F_zfw, N
constexpr int kForwardSpeed = 18;       // xdot_0^R, m/s
constexpr int kSlip = 19;               // i_1..3 (3)
constexpr int kStates = 22;
// Eq. 5.37: wheel rates (3), pitch, bogie, specific force x and z, forward speed, slips (3).
constexpr int kMeasurements = 11;
// Eq. 5.44 and 5.47: the measurements h_1 copies from a state (-1: computed).
constexpr std::array<int, kMeasurements> kCopiedStates = {
    kWheelRate, kWheelRate + 1, kWheelRate + 2, kPitch, kBogie, -1, -1, kForwardSpeed, kSlip, kSlip + 1, kSlip + 2};
}  // namespace general

// Eq. 5.48: Estimators 2 and 3: contact angles (3), normal loads (3), drawbar pulls (3).
namespace wheel_force {
constexpr int kContactAngle = 0, kNormalLoad = 3, kDrawbarPull = 6, kStates = 9;
// Eq. 5.53: contact angles (3), loads along the links (3), loads across them (3).
constexpr int kMeasurements = 9;
}  // namespace wheel_force

// The fixed-size state and measurement vectors of the three filters.
using GeneralState = Eigen::Matrix<double, general::kStates, 1>;
using GeneralMeasurement = Eigen::Matrix<double, general::kMeasurements, 1>;
using WheelForceState = Eigen::Matrix<double, wheel_force::kStates, 1>;
using WheelForceMeasurement = Eigen::Matrix<double, wheel_force::kMeasurements, 1>;

// What the estimators take from the rover: its geometry (data, from the
// rover description) and Table 4.1's masses, inertias and damping.
struct RoverConstants {
  simulation::PlanarRockerBogieGeometry geometry;
  simulation::RockerBogieParameters parameters;
  double total_mass() const;
};

// The terms of Eq. 4.48 at the configuration (pitch, bogie angle) of Eq.
// 5.19: inertia H (Eq. 4.29) and gravity dV/dPhi, in closed form (two
// sin/cos pairs; a test holds them equal to the simulator's
// Jacobian-product inertia, which is ten times slower).
struct ConfigurationTerms {
  simulation::rocker_bogie::Mat inertia = simulation::rocker_bogie::Mat::Zero();
  simulation::rocker_bogie::Vec gravity = simulation::rocker_bogie::Vec::Zero();  // dV/dPhi
  double sin_pitch = 0, cos_pitch = 1;
};
ConfigurationTerms configuration_terms(const RoverConstants& rover, double pitch, double bogie);

// Eq. 5.20 (and 5.41): the generalised velocity with zdot_0^R = 0.
simulation::rocker_bogie::Vec generalised_velocity(double forward_speed, double pitch, double pitch_rate,
                                                   double bogie_rate, const Eigen::Vector3d& wheel_rates);

// Eq. 2.23 as the simulator evaluates it: slip (or skid) of a wheel rolling
// at rim speed `roll` (the absolute wheel rate times the radius) whose
// centre moves at `speed`.
double slip_ratio(double roll, double speed);

// Eq. 5.21-5.36: Estimator 1's process model f_1 over one estimator step
// T_e with the wheel torques u (Eq. 5.22) held.
class GeneralProcessModel {
 public:
  GeneralProcessModel() = default;
  GeneralProcessModel(const RoverConstants& rover, double step);
  void set_torques(const Eigen::Vector3d& torques) { torques_ = torques; }
  // Eq. 5.24: the wheels' angular accelerations at state x.
  Eigen::Vector3d wheel_accelerations(const Eigen::Ref<const Eigen::VectorXd>& x) const;
  // For Eigen::VectorXd and GeneralState.
  template <class State>
  void operator()(const State& x, State& out) const;

 private:
  // The configuration terms at (pitch, bogie): most sigma points share the
  // centre's (the state's Cholesky factor is lower triangular and the angles
  // are states 7 and 8), so the last few are kept.
  const ConfigurationTerms& terms(double pitch, double bogie) const;

  RoverConstants rover_;
  double step_ = 0.02;
  Eigen::Vector3d torques_ = Eigen::Vector3d::Zero();
  static constexpr int kCached = 4;
  mutable std::array<ConfigurationTerms, kCached> cache_{};
  mutable std::array<Eigen::Vector2d, kCached> cache_key_{};
  mutable int cache_size_ = 0, cache_next_ = 0;
};

// Eq. 5.43-5.47: Estimator 1's measurement model h_1.
class GeneralMeasurementModel {
 public:
  explicit GeneralMeasurementModel(double gravity = 9.81) : gravity_(gravity) {}
  // For Eigen::VectorXd and GeneralState / GeneralMeasurement.
  template <class State, class Measurement>
  void operator()(const State& x, Measurement& out) const;

 private:
  double gravity_;
  // The last pitch's sine and cosine: half the sigma points share the
  // centre's propagated pitch.
  mutable double pitch_ = NAN, sin_ = 0, cos_ = 1;
};

// One sample of the sensor vector z (Eq. 5.17) and the commanded torques.
struct SensorSample {
  double bogie = 0, pitch_rate = 0, forward_speed = 0, specific_force_x = 0, specific_force_z = 0;
  Eigen::Vector3d wheel_angle = Eigen::Vector3d::Zero(), load = Eigen::Vector3d::Zero(),
                  perpendicular = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
};

// Eq. 5.37-5.42: Estimator 1's measurement vector from two consecutive
// sensor samples T_e apart. The slips are NaN where a wheel neither rolls
// nor moves (no slip to measure). With `rates` (pitch rate, bogie rate:
// Estimator 1's last estimate) the wheel-centre velocities of Eq. 5.41 use
// them in place of the gyro and the differenced bogie angle, as Estimators 2
// and 3 use estimates for the contact angles (Eq. 5.55): the gyro's noise
// (0.56 deg/s) would otherwise dominate the slips.
GeneralMeasurement general_measurement(const RoverConstants& rover, const SensorSample& now, const SensorSample& before,
                                       double step, const Eigen::Vector2d* rates = nullptr);

// The angle of the link carrying each wheel's force sensor (epsilon of
// Figure 5.9, clockwise): the body for wheel 1, the bogie for wheels 2 and 3.
Eigen::Vector3d sensor_angles(double pitch, double bogie);

// Eq. 5.57-5.59 (h_2 = h_3, Eq. 5.67): contact angles and the loads the
// sensors see along and across their links. The link angles come from
// Estimator 1's estimate.
class ForceMeasurementModel {
 public:
  void set_sensor_angles(const Eigen::Vector3d& angles) { angles_ = angles; }
  // For Eigen::VectorXd and WheelForceState / WheelForceMeasurement.
  template <class State, class Measurement>
  void operator()(const State& x, Measurement& out) const;

 private:
  Eigen::Vector3d angles_ = Eigen::Vector3d::Zero();
  // Each wheel's last angle gamma + epsilon with its sine and cosine: a
  // sigma point moves wheel i's contact angle only along the first i + 1
  // directions of the state's (lower triangular) factor.
  mutable std::array<double, 3> angle_{NAN, NAN, NAN}, sin_{}, cos_{};
};

// Eq. 5.55-5.56: contact angles measured from Estimator 1's configuration
// and generalised velocity (the direction of each wheel centre's velocity).
Eigen::Vector3d contact_angle_measurement(const RoverConstants& rover,
                                          const Eigen::Ref<const Eigen::VectorXd>& general_state);

// Eq. 5.63-5.66: the loads across the links that single-axis sensors do not
// see, from Estimator 1's net bogie moment and horizontal force and the
// sensed loads along the links. Wheels 2 and 3 (one bogie, one line of
// action) share their sum in proportion to their loads.
Eigen::Vector3d perpendicular_from_net_forces(const RoverConstants& rover,
                                              const Eigen::Ref<const Eigen::VectorXd>& general_state,
                                              const Eigen::Vector3d& loads);

// A drawbar-pull surface DP(W, s) (N) whose shape splits the bogie's
// perpendicular load (below); only differences of DP/W between wheels 2 and
// 3 matter.
using DrawbarPullShape = std::function<double(double load, double slip)>;

// Eq. 5.63-5.66 with Eq. 5.66's split refined by a drawbar-pull shape.
// Eq. 5.66 is exact when the two bogie wheels have the same contact angle
// and the same DP/W; this keeps the first assumption (their angle a is the
// mean of the measured contact angles, Eq. 5.56, plus the bogie's) and
// drops the second: with mu = DP/W, F_perp = F_L (mu - tan a) / (1 + mu tan
// a), mu_i = shape(W_i, s_i) / W_i + delta (W_i from Eq. 5.66's split, s_i
// Estimator 1's slips) and one common delta solved so that F_perp2 +
// F_perp3 is Eq. 5.64's sum. Only the shape's difference of DP/W between
// the two wheels matters. Falls back to Eq. 5.66 where a contact angle is
// not measured, |mu| would reach 1, or the solve fails.
Eigen::Vector3d perpendicular_from_net_forces(const RoverConstants& rover,
                                              const Eigen::Ref<const Eigen::VectorXd>& general_state,
                                              const Eigen::Vector3d& loads, const Eigen::Vector3d& contact_angles,
                                              const DrawbarPullShape& shape);

}  // namespace roverlab::estimation::net_traction

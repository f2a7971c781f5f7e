#pragma once
// The planar rocker-bogie's model, apart from the simulator that runs it
// (seed 003 chapter 4): the kinematics and the inertia of Eq. 4.19-4.29, the
// wheel-soil traction before and after the effects' start, and the
// right-hand side of Eq. 4.49-4.50 as a named type that Boost.Odeint
// integrates. Internal to core/simulation: rocker_bogie.h is the public side.

#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "core/simulation/rocker_bogie.h"
#include "core/terramechanics/model.h"
#include "core/terramechanics/traction_surface.h"

namespace roverlab::simulation::rocker_bogie {

constexpr int N = 7;  // x0, z0, pitch, bogie, wheel 1..3
using Vec = Eigen::Matrix<double, N, 1>;
using Mat = Eigen::Matrix<double, N, N>;
using Jac = Eigen::Matrix<double, 2, N>;
using Vec2 = Eigen::Vector2d;
using State = std::vector<double>;  // [qdot; q], as Odeint integrates it

// Clockwise rotation in the x-z plane.
Vec2 rotate(double angle, const Vec2& v);

// Positions and velocity Jacobians of the bodies at configuration q (Eq. 4.19-4.28).
struct Kinematics {
  Vec2 body, bogie_com, wheel[3];
  Jac J_body, J_bogie, J_wheel[3];
  Eigen::Matrix<double, 1, N> W_body, W_bogie, W_wheel[3];  // angular-velocity Jacobians
};
Kinematics kinematics(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p, const Vec& q);

// Eq. 4.29, with the drivetrain's reflected inertia on each wheel joint.
Mat inertia(const Kinematics& k, const RockerBogieParameters& p);
// The velocity Jacobians' time derivatives along qd (the angular-velocity
// Jacobians and the body's translation are constant).
struct JacobianRates {
  Jac bogie, wheel[3];
};
JacobianRates jacobian_rates(const PlanarRockerBogieGeometry& g, const Kinematics& k, const Vec& q, const Vec& qd);

// Hdot qd (Eq. 4.49) from the Jacobians and their rates.
Vec inertia_rate_times(const Kinematics& k, const JacobianRates& rates, const RockerBogieParameters& p, const Vec& qd);

// One wheel's traction: Wong-Reece, or its order-5 polynomial surrogate
// (seed 003 Appendix A) fitted once.
struct WheelTraction {
  // resistance: the compaction resistance inside drawbar_pull (>= 0).
  double drawbar_pull = 0, resistive_torque = 0, sinkage = 0, resistance = 0;
};
class TractionModel {
 public:
  // The nominal wheel, or with the run's effects (soil strength, slip
  // sinkage, grousers, true radius, slip angle). Throws DataError when the polynomial
  // surrogate cannot be fitted (the soil cannot carry the wheel loads).
  TractionModel(const PlanarRockerBogieGeometry& g, const RockerBogieRun& run, bool with_effects);
  double radius() const { return wheel_.radius; }
  // Traction at normal load W and slip s (the surrogate's sinkage only when
  // asked for); counts in `unsupported` the loads the soil cannot carry
  // (Wong-Reece only: traction 0, sinkage NaN).
  // (The surrogate's compaction resistance only when asked for, as its sinkage.)
  WheelTraction evaluate(double W, double s, bool with_sinkage, std::size_t& unsupported,
                         bool with_resistance = true) const;
  // The largest load (N, 1 N steps up to `limit`) the soil carries at every
  // slip with the wheel's entry angle below 90 deg (Wong-Reece, Eq. 2.24).
  double largest_carried_load(double limit) const;

 private:
  void fit_surrogate();
  // Wong-Reece, or at the run's slip angle the Ishigami 2007 model's longitudinal part.
  terramechanics::Traction wheel_soil(double W, double s) const;

  const terramechanics::Soil* soil_;
  TractionSource source_;
  terramechanics::Wheel wheel_;
  terramechanics::ModelOptions options_;
  double slip_angle_ = 0.0;  // rad
  terramechanics::PolynomialSurface dp_, tau_, sinkage_, resistance_;
};

// What one evaluation of the dynamics found at each wheel, for the truth
// streams and the sensors.
struct DynamicsReport {
  Eigen::Vector3d slip, dp, tau, gamma, lambda, rate, sinkage;
  Vec qdd;
};

// Derivative of the state [qdot; q] (Eq. 4.49-4.50) with the wheel torques
// and normal loads held over a control step.
class Dynamics {
 public:
  Dynamics(const PlanarRockerBogieGeometry& g, const RockerBogieParameters& p, const RockerBogieRun& run);
  // The inputs held over the next control step: wheel torques (N m) and the
  // Lagrange multipliers of the last evaluation (the normal loads, Eq. 4.38).
  void hold(const Eigen::Vector3d& torque, const Eigen::Vector3d& normal);
  // qdd at (q, qd); fills `report` when given.
  void accelerations(const Vec& q, const Vec& qd, Vec& qdd, DynamicsReport* report);
  std::size_t unsupported() const { return unsupported_; }

 private:
  // One wheel's path constraint row (Eq. 4.33) and its traction and drive
  // torque added to the generalised forces (Eq. 4.40-4.47).
  struct Constraints {
    Eigen::Matrix<double, 3, N> Psi_q;
    Eigen::Vector3d Psi, Psidot_qd;
  };
  void wheel(int i, const Kinematics& k, const JacobianRates& rates, const Vec& qd, Vec& tau_a, Constraints& c,
             DynamicsReport* report);
  double changed_share(double x) const;  // 0: nominal model, 1: with the effects
  WheelTraction traction_at(double share, double W, double s, bool with_sinkage, bool with_resistance);

  const PlanarRockerBogieGeometry& g_;
  const RockerBogieParameters& p_;
  const RockerBogieRun& run_;
  const TractionModel nominal_, changed_;  // before and after the effects' start
  Eigen::Vector3d torque_ = Eigen::Vector3d::Zero(), normal_ = Eigen::Vector3d::Constant(-1.0);
  std::size_t unsupported_ = 0;
};

// The system Odeint integrates: copied by value, so it only points at the dynamics.
struct OdeSystem {
  Dynamics* dynamics;
  void operator()(const State& x, State& dx, double /*t*/) const;
};

// q and qdot out of the state [qdot; q].
void split_state(const State& x, Vec& q, Vec& qd);

}  // namespace roverlab::simulation::rocker_bogie

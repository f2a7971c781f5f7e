#pragma once
// The run of the planar rocker-bogie simulation (seed 003 chapter 4) in named
// steps: place the rover on the path, then at each 50 Hz control step
// evaluate the dynamics, run the wheel-speed controller, read the sensors
// (Table 5.1 noise, then the effects), record the truth, and integrate the
// dynamics (rocker_bogie_dynamics.h) to the next step; at the end, write
// the streams. simulate_rocker_bogie (rocker_bogie.h) is its entry point.

#include <boost/numeric/odeint.hpp>

#include <cstddef>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "core/simulation/rocker_bogie.h"
#include "core/simulation/rocker_bogie_dynamics.h"
#include "core/simulation/sensor_effects.h"

namespace roverlab::simulation {

class RockerBogieSimulator {
 public:
  // Fits the traction models; throws DataError when the soil cannot carry the wheels.
  RockerBogieSimulator(const PlanarRockerBogieGeometry& geometry, const RockerBogieParameters& parameters,
                       const RockerBogieRun& run);
  // Runs once. Throws DataError when the simulation diverges.
  RockerBogieResult run();

 private:
  using Vec = rocker_bogie::Vec;
  // Adaptive Dormand-Prince; kept over the run (it carries its last derivative, first-same-as-last).
  using Stepper =
      boost::numeric::odeint::controlled_runge_kutta<boost::numeric::odeint::runge_kutta_dopri5<rocker_bogie::State>>;

  void place_on_path();
  void control_step(std::size_t k);
  void integrate_step(double time);
  void check_constraints(const rocker_bogie::Kinematics& kin);
  void controller(const Vec& qd);
  double noise(double sigma);
  void read_sensors(std::size_t k, const Vec& q, const Vec& qd, const rocker_bogie::DynamicsReport& out);
  void read_force_sensors(std::size_t k, const Vec& q, const rocker_bogie::DynamicsReport& out);
  void record_truth(std::size_t k, const Vec& q, const rocker_bogie::Kinematics& kin,
                    const rocker_bogie::DynamicsReport& out);
  void write_metadata();
  void write_sensor_streams();
  void write_truth_streams();

  const PlanarRockerBogieGeometry& g_;
  const RockerBogieParameters& p_;
  const RockerBogieRun& run_;
  rocker_bogie::Dynamics dynamics_;
  double dt_;                  // s, the control step
  std::size_t steps_;          // control steps over the run
  rocker_bogie::State state_;  // [qdot; q]
  Stepper stepper_;
  double step_size_ = 1e-3;  // s, Odeint's adaptive step, carried between control steps
  // Wheel-speed PI: torques (N m) held over a step and the rate errors' integrals.
  Eigen::Vector3d torque_ = Eigen::Vector3d::Zero(), normal_ = Eigen::Vector3d::Constant(-1.0),
                  integral_ = Eigen::Vector3d::Zero();
  std::mt19937 rng_;
  std::normal_distribution<double> unit_{0.0, 1.0};
  // Recorded at each control step: time; truth (x, z, pitch, bogie, then
  // per wheel slip, normal load, drawbar pull, resistive torque, contact
  // angle, rate, torque, sinkage); geometry (bogie pivot x z, wheel centres
  // x z); sensors (Table 5.1: bogie angle, 3 wheel angles, pitch rate, 2
  // specific forces, forward speed, 3 loads, 3 perpendicular loads).
  std::vector<double> t_;
  std::vector<std::vector<double>> rec_, geo_;
  SensorSeries sensors_;
  RockerBogieResult result_;
};

}  // namespace roverlab::simulation

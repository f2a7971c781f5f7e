#pragma once
// Planar dynamics of one side of a rocker-bogie rover (seed 003, Setterfield
// 2011, chapter 4): the lumped body and rocker, the bogie and three wheels
// (configuration Eq. 4.19 reduced to the plane: x0, z0, pitch, bogie angle,
// three wheel angles), inertia from the velocity Jacobians (Eq. 4.20-4.29),
// wheel centres held on a path by constraints with Baumgarte stabilisation
// (Eq. 4.15-4.18, 4.33), normal loads from the Lagrange multipliers (Eq.
// 4.38), drawbar pulls and resistive torques from the terramechanics model
// through the wheel Jacobians (Eq. 4.40-4.47), the system of Eq. 4.49,
// integrated with Boost.Odeint (adaptive Dormand-Prince) between 50 Hz PI
// wheel-speed control steps (section 4.2.4).
//
// Angles are clockwise positive in the world X (forward) - Z (up) plane, as
// in the seed; the wheels roll forward with positive rates.

#include <functional>
#include <string>

#include <Eigen/Core>

#include "core/log/log.h"
#include "core/terramechanics/model.h"

namespace roverlab::simulation {

// Table 4.1 (one side of Kapvik).
struct RockerBogieParameters {
  double body_mass = 12.49, bogie_mass = 1.562, wheel_mass = 0.3174;  // kg
  double body_inertia = 0.5045, bogie_inertia = 0.05248;              // kg m^2
  double wheel_inertia = 0.003584, wheel_gear_inertia = 1.082;        // kg m^2 (gear: referred to the wheel)
  double wheel_damping = 2.28855;                                     // N m s
  Eigen::Vector2d bogie_com{0.0, -0.07322};                           // c_11, m (x, z)
  double baumgarte_alpha = 500, baumgarte_beta = 500;
  double desired_speed = 0.02;  // m/s
  double kp = 25, ki = 0.5;     // wheel-speed PI (Table 4.1)
  double kd = 12.5;          // Table 4.1; not applied: it makes the 50 Hz loop unstable (docs/validation/simulation.md)
  double control_rate = 50;  // Hz
  double gravity = 9.81;
};

// Link vectors in the body frame at rest on level ground (x forward, z up),
// from the rocker pivot, which is taken as the body's centre of mass.
struct PlanarRockerBogieGeometry {
  double wheel_radius = 0.075, wheel_width = 0.07;
  Eigen::Vector2d rocker_to_wheel1{0.350, -0.175}, rocker_to_bogie{-0.175, -0.100};
  Eigen::Vector2d bogie_to_wheel2{0.175, -0.075}, bogie_to_wheel3{-0.175, -0.075};
};

// The path of the wheel centres z_wc(x) with its first two derivatives.
struct WheelCentrePath {
  std::string name;
  std::function<double(double)> z, dz, ddz;
};
// Eq. 4.51: z = A cos(pi/2 x - 1.6) + 0.01 x with the seed's A = 0.12 m
// (crests of 11.2 deg), or gentler hills of amplitude A.
WheelCentrePath rolling_path(double amplitude = 0.12);
WheelCentrePath flat_path(double height = 0);
WheelCentrePath slope_path(double degrees);  // constant grade through x = 0
// A raised-cosine bump of `height` and `length` starting at x0 on flat ground.
WheelCentrePath bump_path(double height, double x0, double length);

enum class TractionSource { wong_reece, polynomial };

// Effects a run can switch on (seed 003's sensors and terrain, issue 5). A
// physical effect starts where the front wheel passes effect_start_x; the
// log records the effects only in its truth/ metadata.
struct RockerBogieEffects {
  double soil_strength = 1.0;         // factor on c, tan(phi), kc, kphi (a soil change)
  double slip_sinkage_n1 = 0.0;       // n = n0 + n1 |s|
  double grouser_height = 0.0;        // m (24 grousers)
  double wheel_radius_scale = 1.0;    // true radius / nominal (control and encoders assume nominal)
  double slip_angle_deg = 0.0;        // every wheel's slip angle |beta| (steering or crabbing; Ishigami 2007)
  double effect_start_x = -1e9;       // m
  double gyro_bias = 0.0;             // rad/s on the pitch rate
  double accel_bias = 0.0;            // m/s^2 on both accelerometer axes
  double force_offset = 0.0;          // N on every force-sensor axis
  double force_scale = 1.0;           // force-sensor scale factor
  double encoder_dropout_start = -1;  // s: the wheel encoders hold their value for 2 s from here (< 0: none)
  double imu_time_offset = 0.0;       // s added to the imu stream's time stamps
};
// Sets an effect by name (the table of core/simulation/effects.h: its name,
// range and member). Throws DataError naming the effect and its range.
void set_effect(RockerBogieEffects& effects, const std::string& name, double value);

struct RockerBogieRun {
  double duration = 200.0;  // s
  WheelCentrePath path = rolling_path();
  double start_x = 0.0;  // wheel 1's x at t = 0
  terramechanics::Soil soil;
  TractionSource traction = TractionSource::polynomial;
  RockerBogieEffects effects;
  bool sensor_noise = true;  // Table 5.1
  unsigned seed = 1;
  std::function<void(double)> progress;  // fraction done
  // A soil (with the effects) that cannot carry a wheel's share of the rover
  // at full slip is refused (DataError). The rover study's trials turn this
  // off: a trial far out (slip-sinkage n1 0.66) is a poor model there, not
  // the study's end.
  bool refuse_unsupported_soil = true;
};

struct RockerBogieResult {
  // Sensors at the control rate with Table 5.1's noise: joints (bogie_angle,
  // wheel_angle_1..3), imu (pitch_rate, specific_force_x/z in rover axes),
  // velocimeter (forward_speed), forces (load_1..3 along the link's z axis,
  // perpendicular_1..3 along its x axis), commands (wheel_torque_1..3); truth
  // streams truth/pose and truth/wheels.
  log::Log log;
  double max_constraint_error = 0;  // m, largest |Psi| over the run
  std::size_t unsupported = 0;      // traction evaluations where the soil could not carry the load
};

// Empty when the run drove at least a quarter of what its speed command asks
// for; otherwise a sentence saying it did not, with the wheels' mean slip
// (a scenario whose soil cannot carry the rover up its path is a stuck rover,
// and every check and study of its log describes one).
std::string stuck_note(const log::Log& simulated, double desired_speed, double duration);

// Throws DataError when the rover cannot be placed on the path.
RockerBogieResult simulate_rocker_bogie(const PlanarRockerBogieGeometry& geometry,
                                        const RockerBogieParameters& parameters, const RockerBogieRun& run);

}  // namespace roverlab::simulation

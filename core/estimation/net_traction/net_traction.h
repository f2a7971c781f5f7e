#pragma once
// Net-traction estimation of seed 003 (Setterfield 2011, sections 5.2-5.6):
// Estimator 1 (the general estimator, 22 states) and beside it Estimator 2
// (two-axis force sensors) and/or Estimator 3 (single-axis force sensors),
// three UKFs over one planar rocker-bogie log. Estimator 1 gives each
// wheel's resistive torque and slip; Estimators 2 and 3 its contact angle,
// normal load and drawbar pull, their measurements built from the force
// sensors and Estimator 1's estimate (Figure 5.1).

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/estimation/net_traction/models.h"
#include "core/filters/fixed_unscented_filter.h"
#include "core/log/log.h"

namespace roverlab::estimation {

enum class ForceSensors { two_axis, single_axis };
ForceSensors parse_force_sensors(const std::string& name);  // two-axis | single-axis; throws DataError
std::string force_sensors_name(ForceSensors sensors);

struct NetTractionOptions {
  // Which wheel-force estimator feeds the streams; default: two-axis when
  // the log carries the perpendicular loads, else single-axis.
  std::optional<ForceSensors> force_sensors;
  // With two-axis sensors, also run Estimator 3 (ignoring the perpendicular
  // loads) for comparison.
  bool compare_single_axis = true;
  // Estimator 3's split of the bogie's perpendicular load between wheels 2
  // and 3: empty, Eq. 5.66 (in proportion to their sensed loads); else by
  // this drawbar-pull shape (net_traction::perpendicular_from_net_forces).
  net_traction::DrawbarPullShape bogie_split_shape;
  std::function<void(double)> progress;  // fraction done; may throw to cancel
  // Issue 17: an update whose normalised innovation squared exceeds the
  // chi-square quantile of this probability (degrees of freedom: the
  // measurements available at that step) is rejected and the filter keeps
  // its prediction; >= 1: no gate.
  double gate_probability = 1.0 - 1e-9;
};

// One filter's estimates: one row per sample, its state and 1-sigma.
struct FilterTrack {
  Eigen::MatrixXd state, sigma;
  bool empty() const { return state.rows() == 0; }
};

struct NetTractionResult {  // NOLINT(bugprone-exception-escape): std::map's move in LogMetadata
  std::vector<double> time;
  FilterTrack general, two_axis, single_axis;  // Estimators 1, 2, 3 (2 or 3 empty when not run)
  Eigen::MatrixXd wheel_acceleration;          // Eq. 5.24 at each sample (N x 3), rad/s^2
  // Each wheel centre's x along the path (N x 3, m), dead-reckoned from
  // Estimator 1 with the front wheel (wheel 1) at x = 0 at the first sample.
  Eigen::MatrixXd wheel_x;
  ForceSensors force_sensors = ForceSensors::two_axis;  // the estimator the streams come from
  std::size_t standstill_samples = 0;                   // samples with no slip measured (the rover stood)
  std::array<std::size_t, 3> rejected_updates{};        // by the NIS gate, Estimators 1, 2, 3
  double filter_seconds = 0;                            // wall time of the filter pass
  std::vector<std::string> warnings;                    // flat-lined sensor channels, one sentence each
  // estimate/net_traction/wheels and estimate/net_traction/body.
  log::Log estimates;
  const FilterTrack& wheel_forces() const { return force_sensors == ForceSensors::two_axis ? two_axis : single_axis; }
};

// What a log lacks for the estimators (empty when they can run): the
// joints, imu, velocimeter, forces and commands streams and their channels.
std::string net_traction_missing(const log::Log& log);
bool has_two_axis_force_sensors(const log::Log& log);

// Runs the three filters in named steps over the joints stream's time base.
class NetTractionEstimator {
 public:
  // Throws DataError for missing streams or channels, fewer than 10 samples,
  // or two-axis estimation asked of a log without perpendicular loads.
  NetTractionEstimator(const log::Log& log, const net_traction::RoverConstants& rover,
                       const NetTractionOptions& options);
  NetTractionResult run();

 private:
  void read_sensors();
  void assemble_noise();
  void initial_state();
  void filter_pass();
  void general_step(std::size_t k);
  using GeneralFilter = FixedUnscentedFilter<net_traction::general::kStates, net_traction::general::kMeasurements>;
  using WheelForceFilter =
      FixedUnscentedFilter<net_traction::wheel_force::kStates, net_traction::wheel_force::kMeasurements>;
  void wheel_force_step(std::size_t k, WheelForceFilter& filter, bool two_axis, FilterTrack& track);
  void path_positions();
  double gate(int which, std::size_t k, int dof);
  void count_rejection(int which, std::size_t k, bool rejected);
  void write_streams();

  const log::Log& log_;
  net_traction::RoverConstants rover_;
  NetTractionOptions o_;
  bool two_axis_ = true, run_single_axis_ = true;
  double step_ = 0.02;
  std::vector<net_traction::SensorSample> samples_;
  net_traction::GeneralProcessModel process_;
  net_traction::GeneralMeasurementModel measurement_;
  net_traction::ForceMeasurementModel force_measurement_;
  // Fixed-size filters (the generic UKF's algebra at compile-time sizes).
  GeneralFilter general_;
  WheelForceFilter two_axis_filter_, single_axis_filter_;
  // Process noise variances per step and measurement noise variances
  // (before gating) of Estimator 1 and of Estimators 2 and 3.
  net_traction::GeneralState q1_;
  net_traction::GeneralMeasurement r1_;
  net_traction::WheelForceState q2_;
  net_traction::WheelForceMeasurement r2_, r3_;
  std::array<double, 12> gates_{};                            // NIS gate by degrees of freedom (0: not yet computed)
  std::array<std::size_t, 3> rejected_in_a_row_{};            // by Estimator 1, 2, 3
  std::array<std::size_t, 3> open_until_{};                   // the gate is open before this sample
  Eigen::Vector3d contact_angles_ = Eigen::Vector3d::Zero();  // this sample's, from Estimator 1
  NetTractionResult result_;
};

// RMS error per wheel of each estimated quantity against the log's
// truth/wheels stream, after the first settle_seconds (the filters'
// convergence). Empty (has_truth false) without truth.
struct NetTractionErrors {
  bool has_truth = false;
  std::size_t samples = 0;
  Eigen::Vector3d normal_load = Eigen::Vector3d::Zero(), drawbar_pull = Eigen::Vector3d::Zero(),
                  resistive_torque = Eigen::Vector3d::Zero(), slip = Eigen::Vector3d::Zero(),
                  contact_angle = Eigen::Vector3d::Zero();
};
NetTractionErrors tracking_errors(const log::Log& log, const NetTractionResult& result, const FilterTrack& wheel_forces,
                                  double settle_seconds = 5.0);

NetTractionResult run_net_traction(const log::Log& log, const net_traction::RoverConstants& rover,
                                   const NetTractionOptions& options);

}  // namespace roverlab::estimation

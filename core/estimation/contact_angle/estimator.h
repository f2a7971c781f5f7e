#pragma once
// The contact-angle estimator of seed 000 as named steps over members: set-up
// (channels, levelling, noise assembly, joint-rate fusion, initial state),
// the filter pass (fast EKF, generic EKF or UKF over the same
// ContactProcessModel and WheelMeasurementModel) and the output streams.
// It does not read truth: run_contact_angle scores its streams through
// core/estimation/contact_angle/estimate_errors.h.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/estimation/contact_angle/contact_angle.h"
#include "core/estimation/contact_angle/fast_ekf.h"
#include "core/estimation/contact_angle/model.h"
#include "core/estimation/contact_angle/ukf.h"
#include "core/filters/nonlinear_filter.h"
#include "core/kinematics/rover_model.h"
#include "core/log/log.h"

namespace roverlab::estimation {

// An estimate channel and the state it holds (the state order of
// ContactAngleResult::variance: yaw, pitch, roll, velocity x y z, slips,
// contact angles, side-slip angles), in the order the estimator writes them;
// the angles' channels only for the `angle_states` the model has (0, 6, 12).
struct StateChannel {
  const char* stream;  // estimate/contact/body or estimate/contact/wheels
  std::string name;
  const char* unit;
  int state;
};
std::vector<StateChannel> state_channels(const kinematics::RoverModel& rover, int angle_states);

class ContactAngleEstimator {
 public:
  // Reads the log's imu, joints and wheels streams (throws DataError naming
  // what is missing) and sets up the models and noises. The log and rover
  // must outlive the estimator.
  ContactAngleEstimator(const log::Log& log, const kinematics::RoverModel& rover, const ContactAngleOptions& options);
  ContactAngleEstimator(const ContactAngleEstimator&) = delete;  // the UKF's h refers to this object
  ContactAngleEstimator& operator=(const ContactAngleEstimator&) = delete;

  // The filter pass and the output streams; has_truth stays false and rms
  // empty (the estimator does not read truth).
  ContactAngleResult run();

 private:
  // Set-up.
  void read_channels();
  void level();
  Eigen::Vector3d mean_force(std::size_t from) const;
  void assemble_process_noise();
  void assemble_measurement_noise();
  void fuse_joint_rates();
  void initial_state();
  contact::Inputs inputs_at(std::size_t i) const;
  bool at_standstill(const contact::Inputs& in) const;
  bool measurements_finite(const contact::Inputs& in) const;
  const Eigen::VectorXd& process_noise(std::size_t i);
  void state_bounds();
  // The filter pass, one step per IMU sample; each leaves the state in x_.
  // `update` false: prediction only (standstill, a bridged IMU sample, a
  // missing joint or wheel sample). Updates pass the health monitor's gate.
  void filter_step(std::size_t i, const contact::Inputs& in, double ts, bool update);
  // The fixed-size steps (and companion_predict): steps/steps.h, compiled for NA = 0, 6 and
  // 12 in steps/na*.cpp.
  template <int NA>
  void fast_ekf_step(FastEkf<NA>& fe, std::size_t i, const contact::Inputs& in, double ts, bool update);
  void generic_ekf_step(std::size_t i, const contact::Inputs& in, double ts, bool update);
  void ukf_step(std::size_t i, const contact::Inputs& in, double ts, bool update);
  template <int NA>
  void fixed_ukf_step(ContactAngleUkf<NA>& u, std::size_t i, const contact::Inputs& in, double ts, bool update);
  bool fast_ukf() const { return o_.filter == FilterKind::ukf && !o_.reference_ukf; }
  // Health: the checks after a step, and the reset (docs/validation/contact-angle.md).
  void check_health(std::size_t i);
  void reset_filter(std::size_t i);
  Eigen::MatrixXd covariance() const;
  Eigen::VectorXd covariance_diagonal() const;
  // Outputs.
  double max_cross_correlation() const;
  void write_streams(log::Log& estimates) const;
  // RTS smoother (ContactAngleOptions::smoother): what the forward pass
  // stores per step, and the backward pass over it into out_.
  template <int NA>
  void companion_predict(const FastEkf<NA>& fe, std::size_t i, const contact::Inputs& in, double ts);
  void record_prediction(std::size_t i, const double* x);
  void record_filtered(std::size_t i, const double* x, bool segment_start);
  void smooth(std::size_t steps);

  const log::Log& log_;
  const kinematics::RoverModel& m_;
  ContactAngleOptions o_;
  const log::Stream* imu_ = nullptr;
  const log::Stream* joints_ = nullptr;
  const log::Stream* wheels_ = nullptr;
  std::vector<const std::vector<double>*> imu_ch_, q_ch_, qd_ch_, w_ch_;
  std::vector<std::string> warnings_;  // flat-lined sensor channels
  ScreenedImu imu_screened_;           // the IMU channels the filter reads
  FilterHealthMonitor health_;
  Eigen::VectorXd lower_, upper_;  // physical bounds of the states (NaN: none)
  std::vector<std::string> state_names_;
  std::size_t measurements_missing_ = 0;
  InnovationStats innovations_;
  // RTS smoother storage, per step: filtered and predicted state, the gain
  // C_k (single precision) and segment starts (the first step and each
  // filter reset); the companion filters (full P, no reset) give the gains.
  bool smooth_ = false;
  std::vector<double> sm_xf_, sm_xp_;
  std::vector<char> sm_start_;
  std::vector<float> sm_c_;  // the RTS gain C_k (nx x nx) from the companion's full covariance
  FastEkf<0> full0_;
  FastEkf<6> full6_;
  FastEkf<12> full12_;
  template <int NA>
  FastEkf<NA>& companion() {
    if constexpr (NA == 0) return full0_;
    else if constexpr (NA == 6) return full6_;
    else return full12_;
  }
  bool stopped_ = false;
  std::vector<std::vector<double>> fused_rate_;  // joint rates fused with the angles' slope (empty: measured)
  contact::ContactLayout layout_;
  kinematics::WheelFrame frame_ = kinematics::WheelFrame::contact;
  // Levelling: initial pitch and roll and the gravity vector g^i.
  double pitch0_ = 0, roll0_ = 0;
  Eigen::Vector3d g_i_ = Eigen::Vector3d::Zero();
  // Noise variances: process (ContactLayout order), measurement (generic
  // order, and the UKF's), joint angle and rate variances.
  Eigen::VectorXd qdiag_, rdiag_, q_bridged_;
  Eigen::MatrixXd Q_, R_ukf_;
  std::vector<double> q_var_, qd_var_;
  contact::ContactProcessModel process_;
  contact::WheelMeasurementModel measurement_;
  // Filters and the state they leave after each step.
  Eigen::VectorXd x0_, p0_, x_, y_meas_;
  ExtendedKalmanFilter ekf_;
  UnscentedKalmanFilter ukf_;  // the reference UKF; the fixed-size ones per model:
  ContactAngleUkf<0> ukf0_;
  ContactAngleUkf<6> ukf6_;
  ContactAngleUkf<12> ukf12_;
  FastEkf<0> fast0_;
  FastEkf<6> fast6_;
  FastEkf<12> fast12_;
  // Per state, its estimate at every IMU sample; 0 at standstill samples
  // and where the filter diverged (diverged_ 1).
  std::vector<std::vector<double>> out_;
  std::vector<double> valid_, diverged_;
};

}  // namespace roverlab::estimation

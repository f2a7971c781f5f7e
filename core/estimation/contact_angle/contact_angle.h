#pragma once
// The contact-angle, side-slip, slip and velocity estimator of seed 000
// (Vijayan 2018, chapters 4-6) for a rover described by DH parameters: state
// Euler angles, body velocity, wheel slips and (model C) contact angles,
// (model C+SS) side-slip angles; strapdown process model (Eq. 4.13-4.14),
// damped slip (Eq. 4.15), random-walk or damped angles (Eq. 5.3-5.6);
// measurement: wheel rates and zero lateral / normal wheel velocity in the
// drive, contact or side-slip frame (Eq. 4.20, Table 5.1). EKF (Jacobians by
// ceres::Jet) or UKF. The estimator itself is ContactAngleEstimator
// (contact_angle_estimator.h), its models contact_angle_model.h; the errors
// against truth come from core/estimation/contact_angle/estimate_errors.h.

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "core/filters/filter_health.h"
#include "core/kinematics/rover_model.h"
#include "core/log/log.h"

namespace roverlab::estimation {

enum class ContactModel { smooth, contact, contact_side_slip };
enum class FilterKind { ekf, ukf };
enum class AngleModel { random_walk, damped };
enum class SmootherMethod { two_filter, rts };

ContactModel parse_contact_model(const std::string& s);      // smooth | c | c+ss
FilterKind parse_filter_kind(const std::string& s);          // ekf | ukf
AngleModel parse_angle_model(const std::string& s);          // random-walk | damped
SmootherMethod parse_smoother_method(const std::string& s);  // two-filter | rts

struct ContactAngleOptions {
  ContactModel model = ContactModel::contact;
  FilterKind filter = FilterKind::ekf;
  AngleModel angle_model = AngleModel::random_walk;
  bool reset_cross_covariance = false;  // the seed's workaround (section 6.3)
  // The generic EKF with ceres::Jet Jacobians and dense algebra instead of
  // the structured fast one (the reference the fast one is tested against).
  bool reference_ekf = false;
  // The plain augmented UKF: every sigma point through f and h, without the
  // closed forms for additive noises and the incremental h (the reference).
  bool reference_ukf = false;
  // The fast EKF sums each update's tr(H K) into InnovationStats (model selection).
  bool effective_dof = false;
  // Offline fixed-interval smoother (issue 15; not in seed 000): the
  // estimates streams hold the smoothed states, ContactAngleResult::filter_rms
  // the forward filter's errors. two_filter (contact_angle_two_filter.h): the
  // filter forward and over the log reversed in time, fused by their
  // variances; any filter. rts: Rauch-Tung-Striebel over the fast EKF with
  // the cross-covariance reset (DataError otherwise), its gains from a
  // companion EKF at the same linearisation points without the reset.
  bool smoother = false;
  SmootherMethod smoother_method = SmootherMethod::two_filter;
  // Keep the diagonal of the filter's covariance at every sample
  // (ContactAngleResult::variance): the two-filter smoother's weights.
  bool record_variance = false;
  // Initial standard deviations of the slips and of the contact and side-slip
  // angles about 0 (flat ground, no slip: how the seed's runs start). The
  // two-filter smoother's backward pass starts where the log ends, on ground
  // of unknown slope: it uses wide ones (contact_angle_two_filter.cpp).
  double initial_slip_sigma = 0.01;              // (1e-4 as a variance)
  double initial_angle_sigma = std::sqrt(1e-3);  // rad
  double angle_damping = 1e-3;                   // 1/s, A_gamma = A_beta (section 6.2)
  double slip_damping = 1e-3;                    // 1/s, A of Eq. 4.15
  // Process noise variances per step (section 6.2: 1e-5, slip 1e-6).
  double attitude_variance = 1e-5, velocity_variance = 1e-5, slip_variance = 1e-6, angle_variance = 1e-5;
  double lateral_variance = 1e-5;  // n_vy, n_vz
  // Standstill (section 4.1's and 5.1's singularities): every wheel slower
  // than this and the body turning slower than standstill_gyro_rate; the slip
  // and angle states are then held and marked invalid.
  double standstill_wheel_rate = 1e-3;  // rad/s
  double standstill_gyro_rate = 0.05;   // rad/s
  // Offline extension (not in the seed): joint rates fused with the slope of
  // a least-squares line through the joint angles over this centred window
  // (s); 0 uses the measured rates alone as the seed does.
  double joint_rate_window = 0.0;
  // Robustness (issue 17): IMU screening and gap bridging, the NIS gate of
  // the wheel update and the filter's health checks; physical bounds of the
  // states (docs/validation/contact-angle.md, "Outliers, gaps, divergence").
  ImuScreenOptions imu_screen;
  HealthOptions health;
  double max_speed = 10.0;               // m/s, |body velocity| per axis
  double max_angle = M_PI / 2;           // rad: |pitch|, |roll|, |contact angle|, |side-slip angle|
  double max_slip = 10.0;                // |slip state|
  std::function<void(double)> progress;  // fraction done
};

struct StateErrors {
  std::vector<double> velocity;                        // x y z, m/s
  std::vector<double> slip, contact_angle, side_slip;  // per wheel (rad for the angles)
  std::size_t samples = 0;                             // moving samples compared
};

// The measurement updates' innovations, the evidence for a model (model
// selection, contact_model_selection.h): the NIS y^T S^-1 y summed with its
// degrees of freedom, and the Gaussian log-likelihood of the innovations
// (the prediction-error decomposition) summed over the updates.
struct InnovationStats {
  std::size_t updates = 0;    // offered to the gate (accepted or rejected)
  double nis_sum = 0;         // sum of y^T S^-1 y
  double dof = 0;             // sum of the measurement dimensions
  double log_likelihood = 0;  // sum of -(y^T S^-1 y + ln det S + m ln 2 pi) / 2
  double effective_dof = 0;   // sum of tr(H K) (fast EKF with ContactAngleOptions::effective_dof)
  void add(double nis, double log_det_s, int m, double dof_used = 0) {
    ++updates;
    effective_dof += dof_used;
    nis_sum += nis;
    dof += m;
    log_likelihood -= 0.5 * (nis + log_det_s + m * std::log(2.0 * M_PI));
  }
};

struct ContactAngleResult {
  log::Log estimates;  // estimate/contact/body, estimate/contact/wheels
  bool has_truth = false;
  StateErrors rms;  // against truth/body and truth/wheels, moving samples only (smoothed with the smoother)
  bool smoothed = false;
  log::Log filter_estimates;  // with the smoother: the forward filter's streams
  StateErrors filter_rms;     // with the smoother: the forward filter's errors
  double seconds = 0;         // of log processed
  std::size_t standstill_samples = 0;
  double max_cross_correlation = 0;  // largest |P_ij| / sqrt(P_ii P_jj), i != j, at the end
  HealthReport health;         // outliers, gaps, gated updates, divergences (both passes of the two-filter smoother)
  HealthReport filter_health;  // with the smoother: the forward filter's alone (its model's evidence)
  InnovationStats innovations;
  std::vector<std::string> warnings;  // flat-lined sensor channels, one sentence each
  // With ContactAngleOptions::record_variance: per state (yaw, pitch, roll,
  // velocity x y z, slips, contact angles, side-slip angles), per IMU
  // sample, the diagonal of the filter's P after the step.
  std::vector<std::vector<double>> variance;
};

// Needs streams imu (angular_rate_*, specific_force_* in the rover's body
// axes), joints (one channel per joint and <joint>_rate), wheels
// (rate_<wheel>); truth/body and truth/wheels are used for the errors when
// present. Throws DataError naming what is missing. ContactAngleEstimator's
// run, scored by analysis::contact_angle_errors.
ContactAngleResult run_contact_angle(const log::Log& log, const kinematics::RoverModel& rover,
                                     const ContactAngleOptions& options = {});

// Scores a finished run against the log's truth as run_contact_angle does:
// rms (and filter_rms when smoothed), has_truth.
void score_contact_angle(const log::Log& log, ContactAngleResult& result);

}  // namespace roverlab::estimation

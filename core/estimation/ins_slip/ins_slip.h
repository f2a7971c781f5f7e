#pragma once
// Proprioceptive slip detection of seed 002 (Kilic, Gu, Gross 2022): an
// error-state EKF over a strapdown INS with zero-velocity (ZUPT),
// zero-angular-rate (ZARU) and non-holonomic (NHC) pseudo-measurements,
// optional wheel-odometry aiding, and the slip ratio of INS speed against
// wheel speed. The estimator's steps are InsSlipEstimator
// (ins_slip_estimator.h), its models ins_slip_models.h, one filter pass
// ins_slip_filter.h; run_ins_slip runs it and scores the result.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/estimation/ins_slip/metrics.h"
#include "core/filters/filter_health.h"
#include "core/log/log.h"
#include "core/models/ins.h"
#include "core/models/skid_steer_odometry.h"
#include "core/models/slip.h"

namespace roverlab::estimation {

struct ImuNoise {
  double gyro_arw = 2.9e-4;          // rad/sqrt(s): angular random walk (datasheet 0.1 deg/sqrt(h), x10 for vibration)
  double accel_vrw = 1.3e-3;         // m/s/sqrt(s): velocity random walk (0.008 m/s/sqrt(h), x10 for vibration)
  double gyro_bias_walk = 1e-6;      // rad/s/sqrt(s)
  double accel_bias_walk = 1e-5;     // m/s^2/sqrt(s)
  double initial_gyro_bias = 2e-3;   // rad/s, 1 sigma
  double initial_accel_bias = 0.05;  // m/s^2, 1 sigma
  double initial_attitude = 0.01;    // rad, roll and pitch after levelling
  double initial_heading = 0.02;     // rad
};

struct StandstillOptions {
  double window = 0.5;           // s, centred window for the IMU statistics
  double gyro_std_max = 0.005;   // rad/s, std of |w|
  double accel_std_max = 0.05;   // m/s^2, std of |f|
  double wheel_rate_max = 0.05;  // rad/s, |left| and |right| wheel rates
};

struct InsSlipOptions {
  bool zupt = true, zaru = true, nhc = true;
  // Forward speed from the wheels as an update of the localisation filter
  // (seed 002 section 5.1). Slip is then judged by a second pass without it.
  bool odometry_aiding = true;
  // Offline: a Rauch-Tung-Striebel pass that carries each update (a stop's
  // ZUPT above all) back over the drive before it.
  bool smooth = true;
  InsOptions ins;
  ImuNoise noise;
  StandstillOptions standstill;
  SkidSteerGeometry rover;
  Eigen::Vector3d nhc_lever_arm = Eigen::Vector3d::Zero();  // body frame, IMU to wheel-axle centre, m
  double update_interval = 0.1;                             // s between pseudo-measurement updates
  double zupt_sigma = 0.01;                                 // m/s
  double zaru_sigma = 2e-4;                                 // rad/s, on the mean rate over the update interval
  double nhc_lateral_sigma = 0.05;                          // m/s
  // Vertical wheel velocity is further from zero than lateral on rough ground
  // (bumps, and the IMU's mounting pitch: 2 deg at 0.7 m/s is 0.025 m/s);
  // see docs/validation/ins-slip.md for the sensitivity on the Pathfinder log.
  double nhc_vertical_sigma = 0.2;  // m/s
  // IMU axes relative to the chassis (roll, pitch, yaw, rad): the NHC and
  // the wheel speed hold in chassis axes. Zero: IMU aligned with the chassis.
  Eigen::Vector3d imu_mounting = Eigen::Vector3d::Zero();
  double odometry_sigma = 0.05;  // m/s
  double odometry_gate = 6.63;   // chi-square(1) 99 %: wheel speeds this far off (slip) are not used
  // Initial heading and position: the rigid rotation and translation that best
  // align a first pass's track with the GPS fixes over this much GPS track,
  // or longer, until the GPS fix noise alone leaves the heading known to
  // alignment_heading_sigma (or the track ends).
  double alignment_distance = 20.0;       // m
  double alignment_heading_sigma = 0.01;  // rad (0.57 deg)
  std::optional<double> initial_heading;  // rad clockwise from north; overrides the alignment
  // |s| at or below which a sample counts as no slip (seed 002 section 3.1:
  // "s ~ 0"). Unset: 0.02 against slip truth or without a reference; 0
  // against GPS, where Eq. 30's third case (standstill) is the only "none": a
  // GPS speed cannot resolve |s| <= 0.02 while moving, and seed 002 Table 2's
  // no-slip counts are its runs' standstill samples
  // (docs/validation/ins-slip.md, "Slip classes on real data").
  std::optional<double> no_slip;
  // m/s: moving slower than this (wheels and body), or turning in place (one
  // side's wheels turning backwards), slip is undefined (NaN, not scored);
  // at standstill it is 0 (Eq. 1's third case).
  double min_slip_speed = 0.1;
  // Robustness (issue 17): IMU screening and gap bridging, the NIS gate of
  // the ZUPT, ZARU and NHC updates, health checks with the physical bounds
  // below (docs/validation/ins-slip.md, "Outliers, gaps, divergence").
  ImuScreenOptions imu_screen;
  HealthOptions health;
  double max_speed = 10.0;               // m/s, each velocity component
  double max_tilt = 1.4;                 // rad, |roll| and |pitch|
  double max_accel_bias = 1.0;           // m/s^2
  double max_gyro_bias = 0.1;            // rad/s
  std::function<void(double)> progress;  // fraction done, called now and then
};

// Scores against the reference (core/estimation/ins_slip/metrics.h), kept under
// their old names here.
using analysis::AxisErrors;
using analysis::InsSlipMetrics;
using analysis::OdometryMetrics;

// How the initial heading was obtained and how well it is known.
struct InitialHeading {
  enum class Method { given, aligned, assumed_north } method = Method::assumed_north;
  double heading = 0;          // rad clockwise from north
  double sigma = NAN;          // rad, 1 sigma (aligned: from the fit's residuals)
  double east = 0, north = 0;  // m, initial position
  double stretch = 0;          // m of GPS track aligned over
  std::size_t fixes = 0;       // GPS fixes used
  double residual_rms = NAN;   // m, of the aligned first pass against those fixes
};
std::string describe(const InitialHeading& h);

// What the IMU's vibration leaves the unaided slip detector: the vertical
// specific force integrated while driving wanders like a random walk that a
// ground vehicle's bounded height cannot have (an IMU error, measured without
// GPS); scaled by the forward-to-vertical vibration ratio it predicts the
// forward speed error of the detector between the stops (ZUPTs) that bound
// a drive. See docs/validation/ins-slip.md, "Slip classes on real data".
struct ImuVibration {
  double vertical_walk = NAN;       // m/s/sqrt(s): vertical velocity random walk while moving
  double forward_walk = NAN;        // m/s/sqrt(s): vertical_walk x forward / vertical vibration (at most 1)
  double modelled_walk = NAN;       // m/s/sqrt(s): the filter's ImuNoise::accel_vrw
  double forward_vibration = NAN;   // m/s^2 RMS, body x, above 5 Hz, while moving
  double vertical_vibration = NAN;  // m/s^2 RMS, body z
  double longest_drive = 0;         // s, the longest stretch between standstills
  double speed_error = NAN;         // m/s: expected RMS forward speed error of the detector over it
  double median_speed = NAN;        // m/s: the wheels' median speed while moving
  double slip_resolution = NAN;     // speed_error / median_speed: the |s| the detector cannot resolve
};

struct InsSlipResult {
  log::Log estimates;  // streams estimate/ins/..., estimate/odometry/pose
  InsSlipMetrics metrics;
  OdometryMetrics odometry;  // plain wheel odometry, same initial pose
  HealthReport health;       // IMU screening and both filter passes
  InitialHeading heading;
  // The GPS reference as smoothed (reference_track.h): fix noise, process
  // noise, fixes the gate rejected; fix_sigma NaN without GPS.
  double gps_fix_sigma = NAN, gps_accel_psd = NAN;
  std::size_t gps_outliers = 0;
  double no_slip = NAN;  // the |s| band of the "none" class used (InsSlipOptions::no_slip)
  ImuVibration vibration;
};

// Channel names the estimator reads (RoverLab's conventions; see
// resources/mappings/wvu_pathfinder.json).
struct InsSlipChannels {
  std::string imu = "imu";
  std::string wheels = "wheels";
  std::string gps = "gps";
  std::string truth_slip = "truth/slip";  // slip_ratio: used as the reference when present (simulated logs)
};

// Runs InsSlipEstimator over a log with streams imu (specific_force_x..z,
// angular_rate_x..z, body axes forward-right-down), wheels (angle_FL, angle_FR,
// angle_RL, angle_RR, rad, forward positive) and optionally gps (east, north,
// up from the first fix; latitude, longitude, height). Throws DataError when
// a stream or channel is missing or the log is too short. The metrics are
// analysis::score_ins_slip and analysis::score_wheel_odometry of the streams.
InsSlipResult run_ins_slip(const log::Log& log, const InsSlipOptions& options, const InsSlipChannels& channels = {});

}  // namespace roverlab::estimation

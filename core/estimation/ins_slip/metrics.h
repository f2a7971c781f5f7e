#pragma once
// Scoring of the INS slip estimator (seed 002) against its reference: the
// position and velocity errors against GPS (Table 1), the heading drift, the
// slip-class confusion against the reference slip (Table 2), and plain wheel
// odometry on the same track. Reads the estimator's output streams and the
// input log; the estimator itself never sees these scores.

#include <cmath>
#include <string>

#include "core/log/log.h"
#include "core/models/slip.h"

namespace roverlab::analysis {

struct AxisErrors {
  double east = 0, north = 0, up = 0;
};

struct InsSlipMetrics {
  bool has_reference = false;
  double final_position_error = 0;  // horizontal, m, at the last GPS sample
  double final_position_error_3d = 0;
  double position_rmse = 0;       // horizontal, m
  AxisErrors position_rmse_axes;  // as in seed 002 Table 1
  double velocity_rmse = 0;       // horizontal, m/s, against the smoothed GPS velocity (reference_track.h)
  double heading_drift = 0;       // rad, heading minus GPS course over the last 5 s of driving
  double distance = 0;            // m along the GPS track
  // After the best rigid alignment (rotation and translation) of the track
  // onto GPS over the first alignment_distance metres, applied to the whole
  // track: a heading error at the start cannot hide a good estimator.
  double aligned_position_rmse = NAN;            // horizontal, m
  double aligned_final_position_error = NAN;     // horizontal, m
  double alignment_rotation = NAN;               // rad, clockwise, the rotation that alignment needed
  estimation::ConfusionMatrix confusion;         // estimated vs reference slip classes
  estimation::ConfusionMatrix confusion_moving;  // the same without the standstill samples
  double standstill_fraction = 0;
  double duration = 0;  // s of IMU data processed
};

struct OdometryMetrics {
  double final_position_error = 0;  // horizontal, m
  double position_rmse = 0;
  double aligned_position_rmse = NAN;  // as InsSlipMetrics
};

// Where the references are in the input log.
struct InsReferenceStreams {
  std::string gps = "gps";
  std::string truth_slip = "truth/slip";  // slip_ratio: the slip reference when present (simulated logs)
  double alignment_distance = 20.0;       // m of GPS track the aligned errors are aligned over
};

// Scores the streams estimate/ins/{pose,velocity,standstill,slip} in
// `estimates` against the input log's GPS (and its slip truth, when present).
InsSlipMetrics score_ins_slip(const log::Log& input, const log::Log& estimates,
                              const InsReferenceStreams& reference = {});

// Scores estimate/odometry/pose against GPS at the GPS samples within the
// span of estimate/ins/pose (the same samples as the INS's scores).
OdometryMetrics score_wheel_odometry(const log::Log& input, const log::Log& estimates,
                                     const InsReferenceStreams& reference = {});

}  // namespace roverlab::analysis

#pragma once
// What skid-steer wheel odometry gets wrong against a reference track (GPS or
// truth), why, and what a corrected model gains on data it was not fitted to.
//
// The drive is split by distance: the first part fits each candidate
// correction (Ceres, least squares on the east/north track error), the rest
// tests it, with dead reckoning restarted from the reference pose at the
// split so that the test part measures only the model. Candidates: wheel
// radius scale, per-side scale, skid-steer turning (effective track), slip
// episodes (piecewise-constant slip), time offset between wheel and
// reference streams.

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/study.h"
#include "core/log/log.h"
#include "core/models/skid_steer_odometry.h"

namespace roverlab::analysis {

struct OdometryStudyOptions {
  estimation::SkidSteerGeometry rover;
  double fit_fraction = 0.5;      // share of the driven distance used for fitting
  double heading_distance = 5.0;  // m of reference track that set the initial heading
  double slip_window = 5.0;       // s, length of a slip-episode window
  double min_gain = 0.2;          // a cause must cut the held-out RMSE by at least this share
  double min_improvement = 0.05;  // m, and by at least this much (about the reference's accuracy)
  std::string wheels = "wheels", reference = "gps";
};

struct OdometryParameter {
  std::string name;
  double value = 0, sigma = 0;  // sigma from the fit's covariance (NaN when unavailable or at its bound)
  bool at_bound = false;        // within 1 % of a bound of its search (near_bound): no sigma, no cause
};

struct OdometryCandidate {
  std::string name;   // "radius scale", "per-side scale", "turning track", "slip episodes", "time offset"
  std::string cause;  // what it would mean physically
  std::vector<OdometryParameter> parameters;  // slip episodes: summarised (count, median, max)
  int parameter_count = 0;
  double fit_rmse = 0;                // m, on the fit part
  double bic = 0, delta_bic = 0;      // against the baseline, on the fit part
  double held_out_rmse = 0;           // m, on the test part
  double held_out_final = 0;          // m, at the end of the test part
  bool significant = false;           // delta BIC < -10 and held-out gain >= min_gain and >= min_improvement,
                                      // and no parameter at its bound
  std::vector<double> fitted;         // the parameters as the candidate's model takes them
  std::vector<std::string> at_bound;  // the fitted parameters within 1 % of a bound of their search
  // In the forward selection: this step's share of the chain's held-out gain
  // (the held-out RMSE it cut against the step before, over the whole chain's
  // cut), and whether it is named (StepRole).
  double gain_share = NAN;
  StepRole role = StepRole::cause;
};

// The horizontal track error at each reference sample of both parts, with
// the nominal geometry (before) and the named cause (after; NaN when none is
// named), each part dead-reckoned from its own start as the study scores it;
// the slip there, 1 - reference speed / wheel speed (NaN where the wheels
// roll slower than 0.05 m/s or the slip is outside [-1, 1]).
struct OdometryResiduals {
  std::vector<double> time, before, after, slip;  // s, m, m, 1
  double rms_before = 0, rms_after = NAN;         // m, over the held-out part
};

struct OdometryDiscrepancyReport {
  double distance = 0, fit_distance = 0, split_time = 0;  // m, m, s
  std::size_t fit_samples = 0, test_samples = 0;          // reference samples
  // Baseline (nominal geometry) on both parts.
  double baseline_fit_rmse = 0, baseline_held_out_rmse = 0, baseline_held_out_final = 0;
  double baseline_bic = 0;
  // What the baseline gets wrong on the fit part: distance ratio and heading error.
  double distance_ratio = 0;                          // odometry distance / reference distance
  double heading_error_end = 0;                       // rad, odometry heading minus reference course at the split
  double along_track_rmse = 0, cross_track_rmse = 0;  // m
  std::vector<OdometryCandidate> candidates;
  int best = -1;  // index of the named cause, -1 when none is significant
  // Forward selection (several causes): the named cause first, then each
  // step the chain so far plus one more candidate, all refitted together; of
  // the steps that lower BIC by more than 10 against the chain before and the
  // held-out RMSE by at least min_improvement, the lowest BIC is kept. Empty
  // when no cause is named.
  std::vector<OdometryCandidate> selection;
  // The further step with the lowest held-out RMSE, tried and not kept
  // (absent when every candidate is in or no cause is named).
  std::optional<OdometryCandidate> rejected_step;
  OdometryResiduals residuals;
  std::string what_is_wrong, verdict;
};

// Throws DataError when the wheels or reference stream is missing, the drive
// is shorter than 5 m, or either part has fewer than 10 reference samples.
OdometryDiscrepancyReport study_odometry(const log::Log& log, const OdometryStudyOptions& options = {});

}  // namespace roverlab::analysis

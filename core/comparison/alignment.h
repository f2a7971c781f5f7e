#pragma once
// Putting a run onto a baseline run's clock: by a time offset (given, or
// found by cross-correlating channels), by an event (the start of motion),
// or by the distance travelled.

#include <cmath>
#include <string>
#include <vector>

#include "core/log/log.h"

namespace roverlab::comparison {

enum class AlignBy { time, motion, distance };

struct AlignmentOptions {
  AlignBy by = AlignBy::time;
  bool find_offset = false;
  double offset_s = 0;               // the other run's clock minus the baseline's (when given)
  std::vector<std::string> sync;     // "stream/channel" cross-correlated; empty: the fastest shared stream
  double max_offset_s = 30;          // search range of the cross-correlation
  double motion_threshold_m = 0.05;  // the run has started once it is this far from its first position
};

// How the other run's times follow from the baseline's.
struct Alignment {
  AlignBy by = AlignBy::time;
  double offset_s = 0;        // time and motion: t_other = t_base + offset_s
  std::string how;            // in words: "given", "cross-correlation of imu (6 channels)", ...
  double correlation = NAN;   // the cross-correlation's peak (mean over channels), NaN when not used
  double base_event_s = NAN;  // motion: when each run started moving
  double other_event_s = NAN;
  std::string position_source;  // motion and distance: the stream the positions came from
  // distance: both runs' cumulative distance at their position stream's times
  std::vector<double> base_time, base_distance, other_time, other_distance;

  // The other run's times for baseline times (ascending); NaN where the
  // other run has not travelled that far (distance).
  std::vector<double> other_times(const std::vector<double>& base_times) const;
};

// Where a run went: the first of truth/motion (east, north), truth/pose (x, z),
// gps, estimate/ins/pose, estimate/odometry/pose (east, north), odometry (x, y)
// the log has; `stream` is empty when it has none.
struct PositionTrack {
  std::string stream, x, y;
};
PositionTrack position_track(const log::Log& log);

// Throws DataError naming what is missing (no shared channel to correlate,
// no position stream, a run that never moves).
Alignment align_runs(const log::Log& base, const log::Log& other, const AlignmentOptions& options);

// The time offset (other minus base) maximising the mean normalised
// cross-correlation of the channels, within +-max_offset_s: coarse on a
// ~10 Hz grid, then on the stream's own rate, then a parabola through the
// peak's neighbours for a fraction of a sample. `correlation` gets the peak.
double find_time_offset(const log::Stream& base, const log::Stream& other, const std::vector<std::string>& channels,
                        double max_offset_s, double* correlation = nullptr);

}  // namespace roverlab::comparison

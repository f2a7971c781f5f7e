#pragma once
// What a log's run was, for the first lines of a report: the rover, how long
// it ran, how far it went (along the best pose source the log has) and where
// (the first GPS fix, else the local frame).

#include <string>
#include <vector>

#include "core/log/log.h"

namespace roverlab::analysis {

// A stream that places the rover: two position channels (a, b), or a
// velocity stream ("velocity_x", b null) whose speed is integrated.
struct PoseSource {
  const char* stream;
  const char* a;
  const char* b;
  const char* method;  // in words, for the report
};

struct RunOverview {
  std::string rover;   // the log's rover id; empty when it names none
  double start_s = 0;  // first and last time of the measured streams (outside estimate/)
  double end_s = 0;
  double duration_s = 0;
  double distance_m = 0;        // path length along distance_source; NaN when the log has no pose
  std::string distance_source;  // the stream it was measured on ("gps"), empty when none
  std::string distance_method;  // in words: "simulated truth", "GPS track", "INS estimate", "wheel odometry"
  bool has_gps_fix = false;     // the start below is a GPS fix
  double start_latitude_deg = 0, start_longitude_deg = 0;
};

// The distance along the first of `sources` (best first) the log has: the
// path length, the sum of the horizontal steps between finite samples (the
// planar truth's steps in x and z); a velocity source, the trapezoidal
// integral of the speed. The estimators' pose sources are theirs to name
// (estimation/ins_slip/streams.h: kPoseSources).
RunOverview overview_of(const log::Log& log, const std::vector<PoseSource>& sources);

}  // namespace roverlab::analysis

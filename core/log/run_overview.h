#pragma once
// What a log's run was, for the first lines of a report: the rover, how long
// it ran, how far it went (along the best pose source the log has) and where
// (the first GPS fix, else the local frame).

#include <string>

#include "core/log/log.h"

namespace roverlab::analysis {

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

// The pose sources, best first: simulated truth (truth/motion east/north,
// the planar truth/pose x/z, or truth/body velocities integrated), GPS
// (east/north), the INS estimate, wheel odometry (estimate/odometry/pose
// east/north, else the logged odometry x/y). The distance is the path
// length: the sum of the horizontal steps between finite samples (the
// planar truth's steps in x and z); a velocity source, the trapezoidal
// integral of the speed.
RunOverview overview_of(const log::Log& log);

}  // namespace roverlab::analysis

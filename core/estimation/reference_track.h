#pragma once
// A reference track from a log's GPS stream (east, north, up from the first
// fix; optionally latitude, longitude, height), with velocities by central
// differences: what estimators and odometry are judged against.

#include <string>
#include <vector>

#include "core/log/log.h"

namespace roverlab::estimation {

struct ReferenceTrack {
  std::vector<double> time, east, north, up, v_east, v_north;
  bool present = false;                            // false when the stream or its east/north channels are missing
  double latitude = 0, longitude = 0, height = 0;  // first fix (rad, rad, m)
};

// Velocities are differenced over about +-0.5 s.
ReferenceTrack reference_from_gps(const log::Log& log, const std::string& stream = "gps");

// Course (rad clockwise from north) from sample `from` to the first point
// `distance` metres away; NaN when the track never gets 1 m away.
double initial_course(const ReferenceTrack& ref, double distance, std::size_t from = 0);

// Course over ground at time t from the differenced velocity; NaN when slower than min_speed.
double course_at(const ReferenceTrack& ref, double t, double min_speed = 0.1);

// Cumulative horizontal distance along the track at each sample, counted in
// segments at least `step` metres long (so that position noise does not add up).
std::vector<double> distance_along(const ReferenceTrack& ref, double step = 0.5);

}  // namespace roverlab::estimation

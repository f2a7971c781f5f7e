#pragma once
// A reference track from a log's GPS stream (east, north, up from the first
// fix; optionally latitude, longitude, height), with velocities by central
// differences: what estimators and odometry are judged against.

#include <cmath>
#include <string>
#include <vector>

#include "core/log/log.h"

namespace roverlab::estimation {

struct ReferenceTrack {
  std::vector<double> time, east, north, up, v_east, v_north;
  bool present = false;                            // false when the stream or its east/north channels are missing
  double latitude = 0, longitude = 0, height = 0;  // first fix (rad, rad, m)
  // Set by smooth_reference: which fixes its gate rejected, the fix noise
  // it estimated, the process noise it chose.
  std::vector<char> outlier;
  std::vector<double> smooth_east, smooth_north;  // smoothed positions, m
  double fix_sigma = NAN;                         // m, horizontal, per axis
  double accel_psd = NAN;                         // (m/s^2)^2/Hz of the constant-velocity model
  bool smoothed = false;
};

// The GPS velocity as an RTS-smoothed constant-velocity model over the fixes.
struct GpsSmoothing {
  double min_fix_sigma = 0.01;  // m: floor of the fix noise estimated from the second differences
  double gate = 13.82;          // chi-square(2) 99.9 %: fixes whose innovation exceeds it are rejected
  int max_rejected_in_row = 5;  // a longer run of rejections is taken as real motion: the fix is used
};

// Replaces v_east and v_north by the Rauch-Tung-Striebel smoothed velocity of
// a constant-velocity model: fix noise from the median absolute second
// difference of the positions, process noise by maximum likelihood over a
// grid, fixes rejected by the innovation gate.
void smooth_reference(ReferenceTrack& ref, const GpsSmoothing& options = {});

// Best rigid 2-D alignment (rotation about the origin, then translation) that
// maps the points (x_e, x_n) onto (y_e, y_n) in the least-squares sense:
// y ~ R(rotation) x + (east, north), rotation clockwise (a heading offset).
struct RigidAlignment {
  double rotation = 0;          // rad, clockwise: added to a heading
  double east = 0, north = 0;   // m
  double rotation_sigma = NAN;  // rad, 1 sigma from the residuals and the spread of the points
  double residual_rms = NAN;    // m
  std::size_t points = 0;
};
RigidAlignment rigid_alignment(const std::vector<double>& x_east, const std::vector<double>& x_north,
                               const std::vector<double>& y_east, const std::vector<double>& y_north);
// Applies it to one point.
void apply_alignment(const RigidAlignment& a, double& east, double& north);

// Velocities are differenced over about +-0.5 s.
ReferenceTrack reference_from_gps(const log::Log& log, const std::string& stream = "gps");

// Course (rad clockwise from north) from sample `from` to the first point
// `distance` metres away; NaN when the track never gets 1 m away.
double initial_course(const ReferenceTrack& ref, double distance, std::size_t from = 0);

// Course over ground at time t from the differenced velocity; NaN when slower than min_speed.
double course_at(const ReferenceTrack& ref, double t, double min_speed = 0.1);

// Cumulative horizontal distance along the track at each sample (the
// smoothed track when there is one), counted in segments at least `step`
// metres long (so that position noise does not add up).
std::vector<double> distance_along(const ReferenceTrack& ref, double step = 0.5);

}  // namespace roverlab::estimation

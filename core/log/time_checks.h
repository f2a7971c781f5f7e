#pragma once
// Checks of a stream's time base that estimators make before they integrate
// over it: a log can hold a legal but broken time base (one time stamp of
// 1e300 s, a joints stream recorded an hour after the IMU).

#include "core/log/stream.h"

namespace roverlab::log {

// Throws DataError naming the stream when two consecutive samples are more
// than `max_gap` seconds apart (an integrating estimator cannot bridge it).
void require_no_gap(const Stream& stream, double max_gap);

// Throws DataError naming both streams when `other` covers less than
// `min_fraction` of `reference`'s time span.
void require_overlap(const Stream& reference, const Stream& other, double min_fraction);

}  // namespace roverlab::log

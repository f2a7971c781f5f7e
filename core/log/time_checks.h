#pragma once
// Checks of a stream's time base that estimators make before they integrate
// over it: a log can hold a legal but broken time base (one time stamp of
// 1e300 s, a joints stream recorded an hour after the IMU).

#include <cstddef>
#include <string>
#include <vector>

#include "core/log/stream.h"

namespace roverlab::log {

// Throws DataError naming the stream when two consecutive samples are more
// than `max_gap` seconds apart (an integrating estimator cannot bridge it).
void require_no_gap(const Stream& stream, double max_gap);

// Throws DataError naming both streams when `other` covers less than
// `min_fraction` of `reference`'s time span.
void require_overlap(const Stream& reference, const Stream& other, double min_fraction);

// Throws DataError naming the stream when it has fewer than `min_samples`
// samples ("stream 'forces' is empty").
void require_samples(const Stream& stream, std::size_t min_samples);

// require_overlap both ways: each of the two streams covers at least
// `min_fraction` of the other's span (a stream whose time stamps were scaled
// or shifted shares no time base with the others, whichever is longer).
void require_shared_time_base(const Stream& a, const Stream& b, double min_fraction);

// Throws DataError naming the stream, channel and time of the first value
// that is not finite or whose magnitude exceeds `limit` (in the channel's SI
// unit: no sensor reads 1e300 N).
void require_finite_within(const Stream& stream, const std::string& channel, double limit);

// A sentence for `channel` when it holds one exact value over at least
// `min_fraction` of the stream's span and at least `min_seconds` (a stuck
// encoder, a disconnected sensor: no measurement of noise ever repeats
// itself for that long); empty otherwise.
std::string flat_lined(const Stream& stream, const std::string& channel, double min_fraction, double min_seconds);

}  // namespace roverlab::log

#pragma once
// Putting streams onto a common time base.

#include <string>
#include <vector>

#include "core/log/stream.h"

namespace roverlab::log {

// Times t0, t0 + 1/rate, ... up to t1 (inclusive within 1e-9 of a period).
// Throws DataError when rate <= 0 or t1 < t0 or a bound is not finite.
std::vector<double> uniform_times(double t0, double t1, double rate_hz);

// Every channel of `stream` linearly interpolated at `times` (strictly
// increasing), as a new stream called `name`. Times outside the stream's
// span give NaN: nothing is extrapolated.
Stream resample(const Stream& stream, const std::vector<double>& times, std::string name);

// `base` and `other` on base's time base, restricted to the span both cover.
// Channels of base are copied, channels of other interpolated; a channel name
// of other that base already has is prefixed "<other stream>.".
// Throws DataError when the two streams do not overlap in time.
Stream align(const Stream& base, const Stream& other, std::string name);

}  // namespace roverlab::log

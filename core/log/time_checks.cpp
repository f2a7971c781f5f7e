#include "core/log/time_checks.h"

#include <algorithm>
#include <cstdio>
#include <string>

#include "core/common/error.h"

namespace roverlab::log {

namespace {

std::string seconds(double v) {
  char b[48];
  std::snprintf(b, sizeof b, "%.6g s", v);
  return b;
}

}  // namespace

void require_no_gap(const Stream& s, double max_gap) {
  const auto& t = s.time();
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t[i] - t[i - 1] > max_gap) {
      throw DataError("stream '" + s.name() + "': a gap of " + seconds(t[i] - t[i - 1]) + " after t = " +
                      seconds(t[i - 1]) + " (more than " + seconds(max_gap) + ": a broken time stamp or a dropout)");
    }
  }
}

void require_overlap(const Stream& reference, const Stream& other, double min_fraction) {
  if (reference.size() < 2) return;
  const double span = reference.end_time() - reference.start_time();
  const double covered = other.empty() ? 0.0
                                       : std::min(reference.end_time(), other.end_time()) -
                                             std::max(reference.start_time(), other.start_time());
  if (!(covered >= min_fraction * span)) {
    throw DataError("stream '" + other.name() + "' (t = " + seconds(other.start_time()) + " .. " +
                    seconds(other.end_time()) + ") covers " +
                    std::to_string(static_cast<int>(100.0 * std::max(0.0, covered) / span)) + " % of stream '" +
                    reference.name() + "' (t = " + seconds(reference.start_time()) + " .. " +
                    seconds(reference.end_time()) + "): the streams do not share a time base");
  }
}

}  // namespace roverlab::log

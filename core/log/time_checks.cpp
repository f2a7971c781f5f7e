#include "core/log/time_checks.h"

#include <algorithm>
#include <cmath>
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
  if (other.empty()) throw DataError("stream '" + other.name() + "' is empty");
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

void require_samples(const Stream& s, std::size_t min_samples) {
  if (s.size() >= min_samples) return;
  if (s.empty()) throw DataError("stream '" + s.name() + "' is empty");
  throw DataError("stream '" + s.name() + "' has " + std::to_string(s.size()) + " sample" + (s.size() == 1 ? "" : "s") +
                  "; at least " + std::to_string(min_samples) + " are needed");
}

void require_shared_time_base(const Stream& a, const Stream& b, double min_fraction) {
  require_overlap(a, b, min_fraction);
  require_overlap(b, a, min_fraction);
}

void require_finite_within(const Stream& s, const std::string& channel, double limit) {
  const std::vector<double>& v = s.channel(channel).values;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::isfinite(v[i]) && std::abs(v[i]) <= limit) continue;
    char b[160];
    std::snprintf(b, sizeof b, ": %g at t = %.6g s (%s)", v[i], s.time()[i],
                  std::isfinite(v[i]) ? "beyond any physical reading" : "missing or not finite");
    throw DataError("stream '" + s.name() + "' channel '" + channel + "'" + b);
  }
}

std::string flat_lined(const Stream& s, const std::string& channel, double min_fraction, double min_seconds) {
  const std::vector<double>& v = s.channel(channel).values;
  const std::vector<double>& t = s.time();
  if (v.size() < 2) return "";
  std::size_t best_begin = 0, best_end = 0, begin = 0;
  for (std::size_t i = 1; i <= v.size(); ++i) {
    if (i < v.size() && v[i] == v[begin]) continue;
    if (t[i - 1] - t[begin] > t[best_end] - t[best_begin]) {
      best_begin = begin;
      best_end = i - 1;
    }
    begin = i;
  }
  const double held = t[best_end] - t[best_begin];
  if (!(held >= min_seconds && held >= min_fraction * s.duration())) return "";
  char b[200];
  std::snprintf(b, sizeof b,
                "' stays at %g for %.3g s of its %.3g s (t = %.6g .. %.6g s): a stuck or disconnected sensor?",
                v[best_begin], held, s.duration(), t[best_begin], t[best_end]);
  return "stream '" + s.name() + "' channel '" + channel + b;
}

}  // namespace roverlab::log

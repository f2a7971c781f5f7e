#include "core/log/resample.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace roverlab::log {

std::vector<double> uniform_times(double t0, double t1, double rate_hz) {
  if (!std::isfinite(t0) || !std::isfinite(t1) || !std::isfinite(rate_hz) || rate_hz <= 0.0 || t1 < t0) {
    throw DataError("uniform time base needs finite t0 <= t1 and a positive rate");
  }
  const double period = 1.0 / rate_hz;
  const auto n = static_cast<std::size_t>(std::floor((t1 - t0) / period + 1e-9)) + 1;
  std::vector<double> times(n);
  for (std::size_t k = 0; k < n; ++k) times[k] = t0 + static_cast<double>(k) * period;
  return times;
}

Stream resample(const Stream& stream, const std::vector<double>& times, std::string name) {
  Stream out(std::move(name), times);
  for (const auto& c : stream.channels()) {
    out.add_channel(c.name, c.unit, stream.interpolate(c.name, times), c.description);
  }
  return out;
}

Stream align(const Stream& base, const Stream& other, std::string name) {
  const double t0 = std::max(base.start_time(), other.start_time());
  const double t1 = std::min(base.end_time(), other.end_time());
  if (base.empty() || other.empty() || !(t0 <= t1)) {
    throw DataError("streams '" + base.name() + "' and '" + other.name() + "' do not overlap in time");
  }
  const Stream part = base.slice(t0, t1);
  Stream out(std::move(name), part.time());
  for (const auto& c : part.channels()) out.add_channel(c.name, c.unit, c.values, c.description);
  for (const auto& c : other.channels()) {
    std::string channel_name = c.name;
    if (out.find_channel(channel_name) != nullptr) {
      channel_name = other.name() + "." + c.name;
      std::replace(channel_name.begin(), channel_name.end(), '/', '.');
    }
    out.add_channel(channel_name, c.unit, other.interpolate(c.name, part.time()), c.description);
  }
  return out;
}

}  // namespace roverlab::log

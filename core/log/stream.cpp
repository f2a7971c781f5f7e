#include "core/log/stream.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <sstream>

#include "core/common/error.h"
#include "core/log/units.h"

namespace roverlab::log {
namespace {

std::string format_time(double t) {
  std::ostringstream out;
  out.precision(9);
  out << t;
  return out.str();
}

bool is_valid_segment(std::string_view s) {
  if (s.empty() || s == "." || s == "..") return false;
  return std::none_of(s.begin(), s.end(), [](char c) { return c == '/' || c == '\0' || c == '\n' || c == '\r'; });
}

}  // namespace

bool is_valid_channel_name(std::string_view name) { return is_valid_segment(name); }

bool is_valid_stream_name(std::string_view name) {
  if (name.empty()) return false;
  std::size_t begin = 0;
  while (true) {
    const std::size_t slash = name.find('/', begin);
    const std::string_view segment =
        name.substr(begin, slash == std::string_view::npos ? std::string_view::npos : slash - begin);
    if (!is_valid_segment(segment)) return false;
    if (slash == std::string_view::npos) return true;
    begin = slash + 1;
  }
}

Stream::Stream(std::string name, std::vector<double> time) : name_(std::move(name)), time_(std::move(time)) {
  if (!is_valid_stream_name(name_)) {
    throw DataError("invalid stream name '" + name_ + "'");
  }
  for (std::size_t i = 0; i < time_.size(); ++i) {
    if (!std::isfinite(time_[i])) {
      throw DataError("stream '" + name_ + "': time is not finite at sample " + std::to_string(i));
    }
    if (i > 0 && !(time_[i] > time_[i - 1])) {
      throw DataError("stream '" + name_ + "': time is not strictly increasing at sample " + std::to_string(i) +
                      " (t = " + format_time(time_[i]) + " s after " + format_time(time_[i - 1]) + " s)");
    }
  }
}

double Stream::start_time() const { return empty() ? std::nan("") : time_.front(); }
double Stream::end_time() const { return empty() ? std::nan("") : time_.back(); }
double Stream::duration() const { return size() < 2 ? 0.0 : time_.back() - time_.front(); }
double Stream::mean_rate_hz() const { return size() < 2 ? 0.0 : static_cast<double>(size() - 1) / duration(); }

namespace {
// Up to this many channels a scan beats hashing the name.
constexpr std::size_t kLinearSearchChannels = 16;
}  // namespace

Channel& Stream::add_channel(std::string name, std::string unit, std::vector<double> values, std::string description) {
  if (!is_valid_channel_name(name)) {
    throw DataError("stream '" + name_ + "': invalid channel name '" + name + "'");
  }
  if (find_channel(name) != nullptr) {
    throw DataError("stream '" + name_ + "': channel '" + name + "' appears twice");
  }
  const UnitConversion si = unit_to_si(unit);  // throws on unknown units
  if (si.si_unit != unit) {
    throw DataError("stream '" + name_ + "', channel '" + name + "': unit '" + unit + "' is not SI; convert it to '" +
                    si.si_unit + "'");
  }
  if (values.size() != time_.size()) {
    throw DataError("stream '" + name_ + "', channel '" + name + "': " + std::to_string(values.size()) +
                    " samples but the time base has " + std::to_string(time_.size()));
  }
  index_.emplace(name, channels_.size());
  channels_.push_back(Channel{std::move(name), std::move(unit), std::move(description), std::move(values)});
  return channels_.back();
}

const Channel* Stream::find_channel(std::string_view name) const {
  if (channels_.size() <= kLinearSearchChannels) {
    for (const auto& c : channels_) {
      if (c.name == name) return &c;
    }
    return nullptr;
  }
  const auto it = index_.find(std::string(name));
  return it == index_.end() ? nullptr : &channels_[it->second];
}

const Channel& Stream::channel(std::string_view name) const {
  const Channel* c = find_channel(name);
  if (c == nullptr) {
    throw DataError("stream '" + name_ + "' has no channel '" + std::string(name) + "'");
  }
  return *c;
}

std::size_t Stream::index_at_or_before(double t) const {
  if (empty() || std::isnan(t) || t < time_.front()) return npos;
  const auto it = std::upper_bound(time_.begin(), time_.end(), t);
  return static_cast<std::size_t>(it - time_.begin()) - 1;
}

std::size_t Stream::nearest_index(double t) const {
  if (empty() || std::isnan(t)) return npos;
  const std::size_t i = index_at_or_before(t);
  if (i == npos) return 0;
  if (i + 1 >= size()) return i;
  return (t - time_[i] <= time_[i + 1] - t) ? i : i + 1;
}

double interpolate_linear(const std::vector<double>& time, const std::vector<double>& values, double t) {
  if (time.empty() || std::isnan(t) || t < time.front() || t > time.back()) {
    return std::nan("");
  }
  const auto it = std::upper_bound(time.begin(), time.end(), t);
  const std::size_t hi = static_cast<std::size_t>(it - time.begin());
  if (hi >= time.size()) return values.back();  // t == last time
  const std::size_t lo = hi - 1;
  const double w = (t - time[lo]) / (time[hi] - time[lo]);
  return values[lo] + w * (values[hi] - values[lo]);
}

double Stream::value_at(std::string_view channel_name, double t) const {
  return interpolate_linear(time_, channel(channel_name).values, t);
}

std::vector<double> Stream::interpolate(std::string_view channel_name, const std::vector<double>& times) const {
  const Channel& c = channel(channel_name);
  std::vector<double> out(times.size());
  for (std::size_t k = 0; k < times.size(); ++k) out[k] = interpolate_linear(time_, c.values, times[k]);
  return out;
}

Stream Stream::slice(double t0, double t1) const {
  if (std::isnan(t0) || std::isnan(t1)) {
    throw DataError("stream '" + name_ + "': slice bounds must not be NaN");
  }
  const auto first = std::lower_bound(time_.begin(), time_.end(), t0);
  const auto last = std::upper_bound(time_.begin(), time_.end(), t1);
  const auto begin = static_cast<std::size_t>(first - time_.begin());
  const auto end = std::max(begin, static_cast<std::size_t>(last - time_.begin()));
  const auto from = static_cast<std::ptrdiff_t>(begin), to = static_cast<std::ptrdiff_t>(end);
  Stream out(name_, std::vector<double>(time_.begin() + from, time_.begin() + to));
  for (const auto& c : channels_) {
    out.index_.emplace(c.name, out.channels_.size());
    out.channels_.push_back(
        Channel{c.name, c.unit, c.description, std::vector<double>(c.values.begin() + from, c.values.begin() + to)});
  }
  return out;
}

}  // namespace roverlab::log

#pragma once
// A stream: one time base (seconds, strictly increasing, finite) and named
// channels, each one contiguous array of doubles in SI units. There is no
// object per sample (DESIGN.md, "Time series as in PlotJuggler's PlotData").

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace roverlab::log {

struct Channel {
  std::string name;
  std::string unit;  // canonical SI unit string (see units.h)
  std::string description;
  std::vector<double> values;  // one value per time sample; NaN marks a missing sample
};

class Stream {
 public:
  static constexpr std::size_t npos = std::numeric_limits<std::size_t>::max();

  // Throws DataError when the name is invalid or the time base is not finite
  // and strictly increasing.
  Stream(std::string name, std::vector<double> time);

  const std::string& name() const { return name_; }
  const std::vector<double>& time() const { return time_; }
  std::size_t size() const { return time_.size(); }
  bool empty() const { return time_.empty(); }
  double start_time() const;    // NaN when empty
  double end_time() const;      // NaN when empty
  double duration() const;      // 0 when fewer than two samples
  double mean_rate_hz() const;  // (N - 1) / duration; 0 when undefined

  // Adds a channel. Throws DataError when the name is invalid or taken, the
  // unit is unknown or not SI, or the length differs from the time base.
  Channel& add_channel(std::string name, std::string unit, std::vector<double> values, std::string description = {});

  const std::vector<Channel>& channels() const { return channels_; }
  const Channel* find_channel(std::string_view name) const;
  const Channel& channel(std::string_view name) const;  // throws DataError when absent

  // Binary search: index of the last sample with time <= t, npos when t
  // precedes the first sample (or is NaN).
  std::size_t index_at_or_before(double t) const;
  // Index of the sample closest in time to t; npos when empty or t is NaN.
  std::size_t nearest_index(double t) const;

  // Linear interpolation of a channel at time t; NaN outside [start, end].
  double value_at(std::string_view channel_name, double t) const;
  // The same at many times (ascending or not), in one pass per time.
  std::vector<double> interpolate(std::string_view channel_name, const std::vector<double>& times) const;

  // Samples with t0 <= t <= t1, all channels, under the same name.
  Stream slice(double t0, double t1) const;

 private:
  std::string name_;
  std::vector<double> time_;
  std::vector<Channel> channels_;
  // Channel index by name for wide streams (a CSV of 200k columns): adding
  // and finding stay linear overall instead of quadratic.
  std::unordered_map<std::string, std::size_t> index_;
};

// Interpolates `values` sampled at `time` (ascending) at t; NaN outside.
double interpolate_linear(const std::vector<double>& time, const std::vector<double>& values, double t);

// Name rules shared by the importers: a stream name is one or more segments
// separated by '/', e.g. "imu" or "truth/imu"; a channel name has no '/'.
bool is_valid_stream_name(std::string_view name);
bool is_valid_channel_name(std::string_view name);

}  // namespace roverlab::log

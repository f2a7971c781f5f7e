#include "core/comparison/alignment.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "core/estimation/ins_slip/streams.h"
#include "core/log/conventions.h"
#include "core/log/resample.h"

namespace roverlab::comparison {

namespace {

// A channel with its mean removed and scaled to unit variance; NaN -> 0.
std::vector<double> normalised(std::vector<double> x) {
  double sum = 0, sum_squares = 0;
  std::size_t n = 0;
  for (double v : x) {
    if (!std::isfinite(v)) continue;
    sum += v;
    sum_squares += v * v;
    ++n;
  }
  const double mean = n > 0 ? sum / static_cast<double>(n) : 0.0;
  const double var = n > 1 ? sum_squares / static_cast<double>(n) - mean * mean : 0.0;
  const double scale = var > 0 ? 1.0 / std::sqrt(var) : 0.0;
  for (double& v : x) v = std::isfinite(v) ? (v - mean) * scale : 0.0;
  return x;
}

// Means of consecutive groups of `factor` samples.
std::vector<double> decimated(const std::vector<double>& x, std::size_t factor) {
  std::vector<double> out(x.size() / factor);
  for (std::size_t i = 0; i < out.size(); ++i) {
    double sum = 0;
    for (std::size_t k = 0; k < factor; ++k) sum += x[i * factor + k];
    out[i] = sum / static_cast<double>(factor);
  }
  return out;
}

// The channels of both runs on one grid: a[k] at base time t0 + k dt, b[k]
// at t0 - lag0 dt + k dt, with b's span covering every lag in [0, 2 lag0].
struct CorrelationGrid {
  std::vector<std::vector<double>> a, b;
  double dt = 0;
  std::size_t lag0 = 0;

  // Mean over channels and overlapping samples of a[k] b[k + lag].
  double score(std::size_t lag) const {
    const std::size_t n = std::min(a.front().size(), b.front().size() > lag ? b.front().size() - lag : 0);
    if (n < a.front().size() / 4 || n == 0) return -std::numeric_limits<double>::infinity();
    double sum = 0;
    for (std::size_t c = 0; c < a.size(); ++c) {
      const double* pa = a[c].data();
      const double* pb = b[c].data() + lag;
      for (std::size_t k = 0; k < n; ++k) sum += pa[k] * pb[k];
    }
    return sum / static_cast<double>(n * a.size());
  }

  CorrelationGrid coarse(std::size_t factor) const {
    CorrelationGrid g;
    for (const auto& x : a) g.a.push_back(decimated(x, factor));
    for (const auto& x : b) g.b.push_back(decimated(x, factor));
    g.dt = dt * static_cast<double>(factor);
    g.lag0 = lag0 / factor;
    return g;
  }
};

// The lag in [lo, hi] with the highest score.
std::size_t best_lag(const CorrelationGrid& g, std::size_t lo, std::size_t hi, double* peak) {
  std::size_t best = lo;
  double best_score = -std::numeric_limits<double>::infinity();
  for (std::size_t lag = lo; lag <= hi; ++lag) {
    const double s = g.score(lag);
    if (s > best_score) {
      best_score = s;
      best = lag;
    }
  }
  *peak = best_score;
  return best;
}

CorrelationGrid correlation_grid(const log::Stream& base, const log::Stream& other,
                                 const std::vector<std::string>& channels, double max_offset_s, std::size_t factor) {
  CorrelationGrid g;
  g.dt = 1.0 / base.mean_rate_hz();
  g.lag0 = factor * static_cast<std::size_t>(std::ceil(max_offset_s / (g.dt * static_cast<double>(factor))));
  const std::vector<double> ta = log::uniform_times(base.start_time(), base.end_time(), base.mean_rate_hz());
  const double shift = static_cast<double>(g.lag0) * g.dt;
  const std::vector<double> tb =
      log::uniform_times(base.start_time() - shift, base.end_time() + shift, base.mean_rate_hz());
  for (const auto& name : channels) {
    g.a.push_back(normalised(base.interpolate(name, ta)));
    g.b.push_back(normalised(other.interpolate(name, tb)));
  }
  return g;
}

// First time the run is `threshold` away from its first finite position.
double motion_start(const log::Stream& s, const std::string& x, const std::string& y, double threshold) {
  const auto& vx = s.channel(x).values;
  const auto& vy = s.channel(y).values;
  std::size_t first = 0;
  while (first < s.size() && !(std::isfinite(vx[first]) && std::isfinite(vy[first]))) ++first;
  for (std::size_t k = first; k < s.size(); ++k) {
    if (std::hypot(vx[k] - vx[first], vy[k] - vy[first]) >= threshold) return s.time()[k];
  }
  throw DataError("stream '" + s.name() + "' never moves " + std::to_string(threshold) + " m from its start");
}

// Cumulative path length (NaN positions skipped).
std::vector<double> travelled(const log::Stream& s, const std::string& x, const std::string& y) {
  const auto& vx = s.channel(x).values;
  const auto& vy = s.channel(y).values;
  std::vector<double> out(s.size(), 0.0);
  std::size_t last = s.size();
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (k > 0) out[k] = out[k - 1];
    if (!(std::isfinite(vx[k]) && std::isfinite(vy[k]))) continue;
    if (last < s.size()) out[k] += std::hypot(vx[k] - vx[last], vy[k] - vy[last]);
    last = k;
  }
  return out;
}

// A pose source with two position channels (the log's and the estimators'
// pose sources, best first: estimation/ins_slip/streams.h); a velocity
// source (b null) places no run.
using PositionSource = analysis::PoseSource;
const auto& kPositionSources = estimation::ins_streams::kPoseSources;

bool has_position(const log::Log& lg, const PositionSource& p) {
  const log::Stream* s = lg.find_stream(p.stream);
  return p.b != nullptr && s != nullptr && s->size() >= 2 && s->find_channel(p.a) != nullptr &&
         s->find_channel(p.b) != nullptr;
}

const PositionSource& shared_position_source(const log::Log& base, const log::Log& other) {
  for (const auto& p : kPositionSources) {
    if (has_position(base, p) && has_position(other, p)) return p;
  }
  throw DataError("the runs share no position stream (truth/motion, truth/pose, gps, odometry, ...) to align by");
}

// The sync channels: given ("stream/channel", one stream), else every channel
// both runs have in the fastest stream they share (outside truth/ and estimate/).
std::pair<std::string, std::vector<std::string>> sync_channels(const log::Log& base, const log::Log& other,
                                                               const std::vector<std::string>& given) {
  std::pair<std::string, std::vector<std::string>> out;
  if (!given.empty()) {
    for (const auto& path : given) {
      const auto slash = path.rfind('/');
      if (slash == std::string::npos) throw DataError("sync channel '" + path + "' is not stream/channel");
      const std::string stream = path.substr(0, slash);
      if (!out.first.empty() && stream != out.first) throw DataError("sync channels must come from one stream");
      base.channel(path);
      other.channel(path);
      out.first = stream;
      out.second.push_back(path.substr(slash + 1));
    }
    return out;
  }
  double best_rate = 0;
  for (const auto& s : base.streams()) {
    const log::Stream* o = other.find_stream(s.name());
    if (o == nullptr || s.size() < 8 || o->size() < 8 || s.name().rfind(log::kTruthPrefix, 0) == 0 ||
        s.name().rfind(log::kEstimatePrefix, 0) == 0 || s.mean_rate_hz() <= best_rate) {
      continue;
    }
    std::vector<std::string> shared;
    for (const auto& c : s.channels()) {
      if (o->find_channel(c.name) != nullptr) shared.push_back(c.name);
    }
    if (shared.empty()) continue;
    best_rate = s.mean_rate_hz();
    out = {s.name(), shared};
  }
  if (out.second.empty()) throw DataError("the runs share no measured channel to cross-correlate");
  return out;
}

}  // namespace

double find_time_offset(const log::Stream& base, const log::Stream& other, const std::vector<std::string>& channels,
                        double max_offset_s, double* correlation) {
  if (!(base.mean_rate_hz() > 0) || other.size() < 2) throw DataError("stream '" + base.name() + "' is too short");
  const auto factor = std::max<std::size_t>(1, static_cast<std::size_t>(base.mean_rate_hz() / 10.0));
  const CorrelationGrid fine = correlation_grid(base, other, channels, max_offset_s, factor);
  double peak = 0;
  std::size_t lag = fine.lag0;
  if (factor > 1) {
    const CorrelationGrid coarse = fine.coarse(factor);
    lag = best_lag(coarse, 0, 2 * coarse.lag0, &peak) * factor;
  }
  const std::size_t lo = lag > 2 * factor ? lag - 2 * factor : 0;
  lag = best_lag(fine, lo, std::min(lag + 2 * factor, 2 * fine.lag0), &peak);
  double fraction = 0;
  if (lag > 0 && lag < 2 * fine.lag0) {
    // A parabola through the peak and its neighbours.
    const double before = fine.score(lag - 1), after = fine.score(lag + 1);
    const double curvature = before - 2 * peak + after;
    if (curvature < 0) fraction = 0.5 * (before - after) / curvature;
  }
  if (correlation != nullptr) *correlation = peak;
  return (static_cast<double>(lag) - static_cast<double>(fine.lag0) + fraction) * fine.dt;
}

PositionTrack position_track(const log::Log& log) {
  for (const auto& p : kPositionSources) {
    if (has_position(log, p)) return {p.stream, p.a, p.b};
  }
  return {};
}

std::vector<double> Alignment::other_times(const std::vector<double>& base_times) const {
  std::vector<double> out(base_times.size());
  if (by != AlignBy::distance) {
    for (std::size_t k = 0; k < out.size(); ++k) out[k] = base_times[k] + offset_s;
    return out;
  }
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double s = log::interpolate_linear(base_time, base_distance, base_times[k]);
    const auto it = std::lower_bound(other_distance.begin(), other_distance.end(), s);
    if (std::isnan(s) || it == other_distance.end()) {
      out[k] = NAN;
      continue;
    }
    const auto hi = static_cast<std::size_t>(it - other_distance.begin());
    if (hi == 0 || other_distance[hi] == other_distance[hi - 1]) {
      out[k] = other_time[hi];
      continue;
    }
    const double w = (s - other_distance[hi - 1]) / (other_distance[hi] - other_distance[hi - 1]);
    out[k] = other_time[hi - 1] + w * (other_time[hi] - other_time[hi - 1]);
  }
  return out;
}

Alignment align_runs(const log::Log& base, const log::Log& other, const AlignmentOptions& options) {
  Alignment a;
  a.by = options.by;
  if (options.by == AlignBy::time) {
    if (!options.find_offset) {
      a.offset_s = options.offset_s;
      a.how = options.offset_s == 0.0 ? "the clocks as recorded" : "the given offset";
      return a;
    }
    const auto [stream, channels] = sync_channels(base, other, options.sync);
    a.offset_s =
        find_time_offset(base.stream(stream), other.stream(stream), channels, options.max_offset_s, &a.correlation);
    a.how = "cross-correlation of " + stream + " (" + std::to_string(channels.size()) + " channels)";
    return a;
  }
  const PositionSource& p = shared_position_source(base, other);
  a.position_source = p.stream;
  const log::Stream& sb = base.stream(p.stream);
  const log::Stream& so = other.stream(p.stream);
  if (options.by == AlignBy::motion) {
    a.base_event_s = motion_start(sb, p.a, p.b, options.motion_threshold_m);
    a.other_event_s = motion_start(so, p.a, p.b, options.motion_threshold_m);
    a.offset_s = a.other_event_s - a.base_event_s;
    a.how = "start of motion on " + a.position_source;
    return a;
  }
  a.base_time = sb.time();
  a.base_distance = travelled(sb, p.a, p.b);
  a.other_time = so.time();
  a.other_distance = travelled(so, p.a, p.b);
  a.how = "distance travelled on " + a.position_source;
  return a;
}

}  // namespace roverlab::comparison

#include "core/comparison/compare.h"

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace roverlab::comparison {

namespace {

// Linear interpolation of many channels of one stream at the same times:
// the bracketing samples and weights are found once (one merge pass for
// ascending times), then each channel costs one pass. The same values as
// log::Stream::interpolate: NaN outside the stream's span.
class InterpolationPlan {
 public:
  InterpolationPlan(const std::vector<double>& time, const std::vector<double>& at) : lo_(at.size()), w_(at.size()) {
    std::size_t hint = 0;
    for (std::size_t k = 0; k < at.size(); ++k) {
      const double t = at[k];
      if (time.empty() || std::isnan(t) || t < time.front() || t > time.back()) {
        w_[k] = NAN;
        continue;
      }
      if (hint >= time.size() || time[hint] > t) hint = 0;
      while (hint + 1 < time.size() && time[hint + 1] <= t) ++hint;  // time[hint] <= t < time[hint + 1]
      lo_[k] = hint;
      w_[k] = hint + 1 < time.size() ? (t - time[hint]) / (time[hint + 1] - time[hint]) : 0.0;
    }
  }

  // How much of a white noise's variance the interpolation keeps, on average
  // over the times: (1 - w)^2 + w^2 (1 at a sample, 1/2 halfway).
  double noise_gain() const {
    double sum = 0;
    std::size_t n = 0;
    for (double w : w_) {
      if (std::isnan(w)) continue;
      sum += (1 - w) * (1 - w) + w * w;
      ++n;
    }
    return n > 0 ? sum / static_cast<double>(n) : 1.0;
  }

  void apply(const std::vector<double>& values, std::vector<double>& out) const {
    out.resize(lo_.size());
    for (std::size_t k = 0; k < lo_.size(); ++k) {
      const double w = w_[k];
      if (std::isnan(w)) {
        out[k] = NAN;
      } else {
        const double v0 = values[lo_[k]];
        out[k] = w == 0.0 ? v0 : v0 + w * (values[lo_[k] + 1] - v0);
      }
    }
  }

 private:
  std::vector<std::size_t> lo_;
  std::vector<double> w_;
};

// A difference this small against the channel's size is floating-point
// rounding (a log against itself at a sub-sample offset), never "differs".
constexpr double kRounding = 1e-9;

double rms_of(const std::vector<double>& values) {
  double sum = 0;
  std::size_t n = 0;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    sum += v * v;
    ++n;
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : 0.0;
}

std::string path_of(const log::Stream& s, const log::Channel& c) { return s.name() + "/" + c.name; }

// The median of a channel's finite values (a logged sigma); NaN when none.
double median_finite(const std::vector<double>& values) {
  std::vector<double> v;
  for (double x : values) {
    if (std::isfinite(x)) v.push_back(x);
  }
  if (v.empty()) return NAN;
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

// Compares one run with the baseline: named steps, their state in members.
class RunComparer {
 public:
  RunComparer(const log::Log& base, const log::Log& other, const CompareOptions& options)
      : base_(base), other_(other), options_(options) {}

  RunComparison run() {
    result_.false_alarm = options_.false_alarm;
    result_.alignment = align_runs(base_, other_, options_.alignment);
    list_unshared();
    for (const auto& s : base_.streams()) {
      if (const log::Stream* o = other_.find_stream(s.name())) compare_stream(s, *o);
    }
    return std::move(result_);
  }

 private:
  // Channels (and whole streams) only one run has.
  void list_unshared() {
    for (const auto& s : base_.streams()) {
      const log::Stream* o = other_.find_stream(s.name());
      for (const auto& c : s.channels()) {
        if (o == nullptr || o->find_channel(c.name) == nullptr) result_.only_in_base.push_back(path_of(s, c));
      }
    }
    for (const auto& s : other_.streams()) {
      const log::Stream* b = base_.find_stream(s.name());
      for (const auto& c : s.channels()) {
        if (b == nullptr || b->find_channel(c.name) == nullptr) result_.only_in_other.push_back(path_of(s, c));
      }
    }
  }

  // The baseline stream's own times where the other run, aligned, may have
  // values: the baseline is read as recorded (interpolating it would smooth
  // its noise), the other run is interpolated onto it.
  std::vector<double> common_times(const log::Stream& base, const log::Stream& other) const {
    double t0 = base.start_time(), t1 = base.end_time();
    if (result_.alignment.by != AlignBy::distance) {
      t0 = std::max(t0, other.start_time() - result_.alignment.offset_s);
      t1 = std::min(t1, other.end_time() - result_.alignment.offset_s);
    }
    if (base.size() < 2 || other.size() < 2 || !(t1 > t0)) return {};
    const auto& t = base.time();
    return {std::lower_bound(t.begin(), t.end(), t0), std::upper_bound(t.begin(), t.end(), t1)};
  }

  void compare_stream(const log::Stream& base, const log::Stream& other) {
    const std::vector<double> times = common_times(base, other);
    if (times.size() < 8) {
      result_.not_compared.push_back(base.name() + " (the aligned runs overlap by fewer than 8 samples)");
      return;
    }
    const InterpolationPlan at_base(base.time(), times);
    const InterpolationPlan at_other(other.time(), result_.alignment.other_times(times));
    log::Stream kept(options_.difference_prefix + "/" + base.name(), times);
    for (const auto& c : base.channels()) {
      const log::Channel* oc = other.find_channel(c.name);
      if (oc == nullptr) continue;
      if (oc->unit != c.unit) {
        result_.not_compared.push_back(path_of(base, c) + " (unit " + c.unit + " against " + oc->unit + ")");
        continue;
      }
      at_base.apply(c.values, a_);
      at_other.apply(oc->values, b_);
      ChannelComparison cc = compare_channel(base, other, c, at_base.noise_gain(), at_other.noise_gain());
      if (options_.keep_differences) kept.add_channel(c.name, c.unit, d_, "other run minus baseline");
      result_.channels.push_back(std::move(cc));
    }
    if (options_.keep_differences && !kept.channels().empty()) result_.differences.add_stream(std::move(kept));
  }

  // Each stream's noise: its logged <channel>_sigma, else estimated on its own samples.
  void noise(const log::Stream& base, const log::Stream& other, ChannelComparison& cc) const {
    const log::Channel* sb = base.find_channel(cc.channel + "_sigma");
    const log::Channel* so = other.find_channel(cc.channel + "_sigma");
    cc.logged_sigma = sb != nullptr && so != nullptr;
    cc.base_sigma = cc.logged_sigma ? median_finite(sb->values) : noise_sigma(base.channel(cc.channel).values);
    cc.other_sigma = cc.logged_sigma ? median_finite(so->values) : noise_sigma(other.channel(cc.channel).values);
  }

  // `base_gain`, `other_gain`: the share of each stream's noise variance left after interpolation.
  ChannelComparison compare_channel(const log::Stream& base, const log::Stream& other, const log::Channel& c,
                                    double base_gain, double other_gain) {
    ChannelComparison cc;
    cc.stream = base.name();
    cc.channel = c.name;
    cc.unit = c.unit;
    d_.resize(a_.size());
    double sum = 0, sum_squares = 0;
    for (std::size_t k = 0; k < a_.size(); ++k) {
      d_[k] = b_[k] - a_[k];
      if (!std::isfinite(d_[k])) continue;
      sum += d_[k];
      sum_squares += d_[k] * d_[k];
      ++cc.samples;
    }
    if (cc.samples > 0) {
      cc.bias = sum / static_cast<double>(cc.samples);
      cc.rms = std::sqrt(sum_squares / static_cast<double>(cc.samples));
    }
    noise(base, other, cc);
    const double noise_squares =
        base_gain * cc.base_sigma * cc.base_sigma + other_gain * cc.other_sigma * cc.other_sigma;
    if (std::isfinite(noise_squares)) cc.beyond_noise = std::sqrt(std::max(0.0, cc.rms * cc.rms - noise_squares));
    // Two tests, each at half the false-alarm rate (Bonferroni): the block F test sees a bias or a drift, the
    // periodogram test a periodic part that averages out within half a block (issue 45).
    cc.test = test_difference(d_, options_.false_alarm / 2, options_.blocks);
    cc.oscillation = test_oscillation(d_, options_.false_alarm / 2);
    cc.differs = (cc.test.differs || cc.oscillation.differs) && cc.rms > kRounding * rms_of(a_);  // else rounding
    return cc;
  }

  const log::Log& base_;
  const log::Log& other_;
  const CompareOptions& options_;
  RunComparison result_;
  std::vector<double> a_, b_, d_;  // one channel of each run on the common times, and their difference
};

}  // namespace

std::size_t RunComparison::differing() const {
  return static_cast<std::size_t>(
      std::count_if(channels.begin(), channels.end(), [](const ChannelComparison& c) { return c.differs; }));
}

RunComparison compare_runs(const log::Log& base, const log::Log& other, const CompareOptions& options) {
  if (!(options.false_alarm > 0.0 && options.false_alarm <= 0.5)) {
    throw DataError("false-alarm rate must be in (0, 0.5]");
  }
  if (options.blocks < 2) throw DataError("the difference test needs at least 2 blocks");
  return RunComparer(base, other, options).run();
}

}  // namespace roverlab::comparison

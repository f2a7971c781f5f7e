#include "core/filters/filter_health.h"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cstdio>
#include <iterator>

#include "core/common/error.h"

namespace roverlab::estimation {

namespace {

// Standard normal quantile by bisection on erfc (called rarely).
double normal_quantile(double p) {
  double lo = -40.0, hi = 40.0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    if (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

std::string format(const char* f, double v) {
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

// Median and 1.4826 MAD of the finite values in w (reordered).
void median_and_spread(std::vector<double>& w, double& median, double& spread) {
  const auto mid = w.begin() + static_cast<std::ptrdiff_t>(w.size() / 2);
  std::nth_element(w.begin(), mid, w.end());
  median = *mid;
  for (double& v : w) v = std::abs(v - median);
  std::nth_element(w.begin(), mid, w.end());
  spread = 1.4826 * *mid;
}

}  // namespace

double chi_square_quantile(double dof, double probability) {
  if (probability >= 1.0) return HUGE_VAL;
  if (dof == 1.0) {  // the square of a normal variable
    const double z = normal_quantile(0.5 + 0.5 * probability);
    return z * z;
  }
  if (dof == 2.0) return -2.0 * std::log1p(-probability);  // exponential with mean 2
  // Wilson-Hilferty: (X / k)^(1/3) is nearly normal, mean 1 - 2/(9k), variance 2/(9k).
  const double z = normal_quantile(probability), v = 2.0 / (9.0 * dof);
  const double c = 1.0 - v + z * std::sqrt(v);
  return dof * c * c * c;
}

namespace {

using ImuChannels = std::array<const std::vector<double>*, 6>;
enum Usable : char { missing = 0, usable = 1, out_of_range = 2, inconsistent = 3 };

// Range test per sample, then the Hampel test per channel against the
// usable samples around it.
std::vector<char> flag_samples(const ImuChannels& ch, const ImuScreenOptions& o) {
  const std::size_t n = ch[0]->size();
  std::vector<char> flags(n, usable);
  const auto range = [&o](std::size_t c) { return c < 3 ? o.max_angular_rate : o.max_specific_force; };
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t c = 0; c < 6; ++c) {
      const double v = (*ch[c])[i];
      if (!std::isfinite(v)) {
        flags[i] = missing;
      } else if (std::abs(v) > range(c) && flags[i] == usable) {
        flags[i] = out_of_range;
      }
    }
  }
  const auto h = static_cast<std::size_t>(std::max(o.half_window, 1));
  std::vector<double> w;
  w.reserve(2 * h + 1);
  for (std::size_t c = 0; c < 6; ++c) {
    const std::vector<double>& x = *ch[c];
    const double floor = c < 3 ? o.min_rate_jump : o.min_force_jump;
    for (std::size_t i = 0; i < n; ++i) {
      if (flags[i] != usable) continue;
      w.clear();
      double lo = x[i], hi = x[i];
      for (std::size_t k = i > h ? i - h : 0; k <= std::min(n - 1, i + h); ++k) {
        if (flags[k] != missing && std::abs(x[k]) <= range(c)) {
          w.push_back(x[k]);
          lo = std::min(lo, x[k]);
          hi = std::max(hi, x[k]);
        }
      }
      // The median lies within [lo, hi]: a window narrower than the floor cannot flag x[i].
      if (w.size() < 3 || hi - lo <= floor) continue;
      double median = 0, spread = 0;
      median_and_spread(w, median, spread);
      if (std::abs(x[i] - median) > o.hampel_k * spread + floor) flags[i] = inconsistent;
    }
  }
  return flags;
}

// A run of rejected or missing samples is bridged by a line from the mean of
// the half_window usable samples before it to that of those after it (the
// log is processed offline: both ends are known), each end's noise
// averaged; before the first or after the last usable sample, a constant.
void bridge_runs(const std::vector<double>& t, const ImuChannels& ch, const std::vector<char>& flags, std::size_t h,
                 ScreenedImu& s) {
  const std::size_t n = t.size();
  const auto mean_of = [&](const std::vector<std::size_t>& idx, std::size_t c) {
    double sum = 0;
    for (std::size_t k : idx) sum += (*ch[c])[k];
    return sum / static_cast<double>(idx.size());
  };
  std::vector<std::size_t> before, after;
  std::vector<double> w;
  for (std::size_t a = 0; a < n;) {
    if (flags[a] == usable) {
      ++a;
      continue;
    }
    std::size_t b = a;
    while (b < n && flags[b] != usable) ++b;  // [a, b) not usable; a - 1 usable when a > 0
    before.clear();
    after.clear();
    for (std::size_t k = a; k-- > 0 && before.size() < h;) {
      if (flags[k] == usable) before.push_back(k);
    }
    for (std::size_t k = b; k < n && after.size() < h; ++k) {
      if (flags[k] == usable) after.push_back(k);
    }
    ScreenedImu::Run run;
    run.begin = a;
    run.end = b;
    for (std::size_t c = 0; c < 6; ++c) {
      w.clear();
      for (std::size_t k : before) w.push_back((*ch[c])[k]);
      for (std::size_t k : after) w.push_back((*ch[c])[k]);
      double median = 0;
      median_and_spread(w, median, run.spread[c]);
    }
    s.runs.push_back(run);
    const double t0 = before.empty() ? t[b] : t[a - 1], t1 = after.empty() ? t0 : t[b];
    for (std::size_t c = 0; c < 6; ++c) {
      const double v0 = mean_of(before.empty() ? after : before, c), v1 = mean_of(after.empty() ? before : after, c);
      for (std::size_t i = a; i < b; ++i) {
        const double f = t1 > t0 ? (t[i] - t0) / (t1 - t0) : 0.0;
        s.values[c][i] = v0 + f * (v1 - v0);
      }
    }
    for (std::size_t i = a; i < b; ++i) {
      s.bridged[i] = 1;
      ++(flags[i] == missing ? s.missing : s.outliers);
    }
    a = b;
  }
}

// Intervals without a usable sample longer than gap_periods nominal (median)
// periods; longer than max_bridged_gap: refused.
void find_gaps(const std::string& stream, const std::vector<double>& t, const std::vector<char>& flags,
               const ImuScreenOptions& o, ScreenedImu& s) {
  const std::size_t n = t.size();
  std::vector<double> dt;
  dt.reserve(n);
  for (std::size_t i = 1; i < n; ++i) dt.push_back(t[i] - t[i - 1]);
  double period = 0;
  if (!dt.empty()) {
    std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
    period = dt[dt.size() / 2];
  }
  double last = t[0];  // the last usable sample's time (the log's start before the first)
  for (std::size_t i = 0; i <= n; ++i) {
    if (i < n && flags[i] != usable) continue;
    const double end = i < n ? t[i] : t[n - 1];
    if (end - last > o.max_bridged_gap) {
      throw DataError("stream '" + stream + "': a gap of " + format("%.6g s", end - last) +
                      " without a usable sample after t = " + format("%.6g s", last) + " (more than " +
                      format("%.6g s", o.max_bridged_gap) +
                      ", the longest bridged by prediction: a broken time stamp or a dropout)");
    }
    if (end - last > o.gap_periods * period) s.gaps.push_back({last, end});
    last = end;
  }
}

}  // namespace

// Range and Hampel tests, the bridges, the gaps.
ScreenedImu screen_imu(const std::string& stream, const std::vector<double>& t, const ImuChannels& ch,
                       const ImuScreenOptions& o) {
  const std::vector<char> flags = flag_samples(ch, o);
  if (std::find(flags.begin(), flags.end(), usable) == flags.end())
    throw DataError("stream '" + stream + "': no usable IMU sample (all missing or out of range)");
  ScreenedImu s;
  s.bridged.assign(t.size(), 0);
  for (std::size_t c = 0; c < 6; ++c) s.values[c] = *ch[c];
  bridge_runs(t, ch, flags, static_cast<std::size_t>(std::max(o.half_window, 1)), s);
  find_gaps(stream, t, flags, o, s);
  return s;
}

double ScreenedImu::added_variance(std::size_t i, int channel) const {
  if (i >= bridged.size() || bridged[i] == 0) return 0.0;
  const auto after =
      std::upper_bound(runs.begin(), runs.end(), i, [](std::size_t k, const Run& r) { return k < r.begin; });
  if (after == runs.begin()) return 0.0;
  const Run& r = *std::prev(after);
  const double k = static_cast<double>(i - r.begin + 1), spread = r.spread[static_cast<std::size_t>(channel)];
  return (2.0 * k - 1.0) * spread * spread;
}

const char* to_string(HealthStatus status) {
  switch (status) {
    case HealthStatus::ok:
      return "ok";
    case HealthStatus::degraded:
      return "degraded";
    case HealthStatus::diverged:
      return "diverged";
  }
  return "?";
}

HealthStatus HealthReport::status() const {
  if (resets > 0 || stopped) return HealthStatus::diverged;
  if (outliers_rejected > 0 || missing_samples > 0 || measurements_missing > 0 || updates_rejected > 0 || !gaps.empty())
    return HealthStatus::degraded;
  return HealthStatus::ok;
}

std::string HealthReport::message() const {
  std::vector<std::string> parts;
  const auto count = [](std::size_t k, const char* one, const char* many) {
    return std::to_string(k) + " " + (k == 1 ? one : many);
  };
  if (outliers_rejected > 0)
    parts.push_back(count(outliers_rejected, "IMU sample", "IMU samples") + " rejected as outliers");
  if (missing_samples > 0) parts.push_back(count(missing_samples, "IMU sample", "IMU samples") + " missing");
  if (measurements_missing > 0)
    parts.push_back(count(measurements_missing, "step", "steps") + " without a measurement sample (predicted only)");
  if (!gaps.empty()) {
    double longest = 0, total = 0;
    for (const TimeGap& g : gaps) {
      longest = std::max(longest, g.end - g.start);
      total += g.end - g.start;
    }
    parts.push_back(count(gaps.size(), "gap", "gaps") +
                    (gaps.size() == 1
                         ? " of " + format("%.2f s", total)
                         : " (" + format("%.2f s", total) + " in all, longest " + format("%.2f s", longest) + ")") +
                    " bridged by prediction");
  }
  if (updates_rejected > 0)
    parts.push_back(count(updates_rejected, "measurement update", "measurement updates") + " rejected by the NIS gate");
  if (resets > 0 || stopped) {
    std::string d = "diverged at t = " + format("%.2f s", divergence_time) + " (" + divergence_reason + "); " +
                    count(resets, "reset", "resets");
    if (stopped) d += ", then stopped";
    d += ", " + format("%.1f", 100.0 * invalid_fraction) + " % of samples marked invalid";
    parts.push_back(d);
  }
  if (parts.empty()) return "no sample rejected, no gap, no divergence";
  std::string m;
  for (const std::string& p : parts) m += (m.empty() ? "" : "; ") + p;
  return m;
}

void HealthReport::merge(const HealthReport& o) {
  updates_rejected += o.updates_rejected;
  updates += o.updates;
  resets += o.resets;
  stopped = stopped || o.stopped;
  invalid_fraction = std::max(invalid_fraction, o.invalid_fraction);
  if (std::isnan(divergence_time) || (!std::isnan(o.divergence_time) && o.divergence_time < divergence_time)) {
    divergence_time = o.divergence_time;
    divergence_reason = o.divergence_reason;
  }
  nis_out_of_band_fraction = std::max(nis_out_of_band_fraction, o.nis_out_of_band_fraction);
}

void HealthReport::merge_reversed(const HealthReport& b, double mirror) {
  updates_rejected += b.updates_rejected;
  updates += b.updates;
  nis_out_of_band_fraction = std::max(nis_out_of_band_fraction, b.nis_out_of_band_fraction);
  if (b.resets == 0 && !b.stopped) return;
  const double t = mirror - b.divergence_time;  // NaN stays NaN
  std::string reason = "backward pass, " + std::to_string(b.resets) + (b.resets == 1 ? " reset" : " resets");
  if (b.stopped) reason += ", then stopped (the forward filter's states kept where it has none)";
  if (resets == 0 && !stopped) {
    divergence_time = t;
    divergence_reason = reason + ": " + b.divergence_reason;
  } else {
    divergence_reason +=
        "; " + reason + (std::isnan(t) ? "" : ", from t = " + format("%.2f s", t)) + ": " + b.divergence_reason;
  }
  resets += b.resets;
}

double FilterHealthMonitor::gate(int dof) {
  const auto d = static_cast<std::size_t>(std::max(dof, 1));
  if (gates_.size() <= d) gates_.resize(d + 1, NAN);
  if (std::isnan(gates_[d])) gates_[d] = chi_square_quantile(static_cast<double>(d), o_.gate_probability);
  return gates_[d];
}

void FilterHealthMonitor::record(double t, double nis, int dof, bool gated) {
  // NIS moving average: a window's sum of NIS is chi-square with the sum of the dofs.
  if (std::isnan(window_start_)) window_start_ = t;
  if (std::isfinite(nis)) {
    window_sum_ += nis;
    window_dof_ += dof;
  }
  if (t - window_start_ >= o_.nis_window && window_dof_ > 0) {
    ++windows_;
    if (window_sum_ > chi_square_quantile(window_dof_, 0.999)) ++windows_out_;
    report_.nis_out_of_band_fraction = static_cast<double>(windows_out_) / static_cast<double>(windows_);
    window_start_ = t;
    window_sum_ = window_dof_ = 0;
  }
  if (!gated) return;
  ++report_.updates;
  if (nis <= gate(dof)) {
    rejected_since_ = NAN;
  } else {
    ++report_.updates_rejected;
    if (std::isnan(rejected_since_)) rejected_since_ = t;
  }
}

std::string FilterHealthMonitor::check(double t, const Eigen::Ref<const Eigen::MatrixXd>& P,
                                       const Eigen::Ref<const Eigen::VectorXd>& x,
                                       const Eigen::Ref<const Eigen::VectorXd>& lower,
                                       const Eigen::Ref<const Eigen::VectorXd>& upper,
                                       const std::vector<std::string>& names) {
  if (!x.allFinite()) return "state not finite";
  if (!P.diagonal().allFinite()) return "covariance not finite";  // the whole of P with the factorisation
  if (std::isnan(last_factorisation_) || !(t - last_factorisation_ < o_.factorisation_interval) ||
      t < last_factorisation_) {
    last_factorisation_ = t;
    if (!P.allFinite()) return "covariance not finite";
    if (Eigen::LLT<Eigen::MatrixXd>(P).info() != Eigen::Success) return "covariance not positive definite";
  }
  for (Eigen::Index k = 0; k < x.size(); ++k) {
    if (x(k) < lower(k) || x(k) > upper(k)) {
      const auto u = static_cast<std::size_t>(k);
      return (u < names.size() ? names[u] : "state " + std::to_string(k)) + " outside its physical bounds (" +
             format("%.3g", x(k)) + ")";
    }
  }
  if (!std::isnan(rejected_since_) && t - rejected_since_ > o_.max_rejected_time) {
    return "every update rejected by the NIS gate for " + format("%.2g s", t - rejected_since_);
  }
  return "";
}

bool FilterHealthMonitor::reset(double t, const std::string& reason) {
  if (std::isnan(report_.divergence_time)) {
    report_.divergence_time = t;
    report_.divergence_reason = reason;
  }
  rejected_since_ = NAN;
  // A divergence while recovering from the last one is the same episode.
  const bool same_episode = !std::isnan(last_reset_) && t - last_reset_ < o_.recovery_time;
  if (!same_episode && static_cast<int>(report_.resets) >= o_.max_resets) {
    report_.stopped = true;
    return false;
  }
  if (!same_episode) ++report_.resets;
  last_reset_ = t;
  return true;
}

bool FilterHealthMonitor::invalid_at(double t) const {
  return report_.stopped || (!std::isnan(last_reset_) && t - last_reset_ < o_.recovery_time);
}

}  // namespace roverlab::estimation

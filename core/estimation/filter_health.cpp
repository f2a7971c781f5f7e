#include "core/estimation/filter_health.h"

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

// Range and Hampel tests per sample, then the hold of the last usable
// sample, then the gaps between usable samples.
ScreenedImu screen_imu(const std::string& stream, const std::vector<double>& t,
                       const std::array<const std::vector<double>*, 6>& ch, const ImuScreenOptions& o) {
  const std::size_t n = t.size();
  ScreenedImu s;
  std::vector<char> usable(n, 1);
  for (std::size_t i = 0; i < n; ++i) {
    for (int c = 0; c < 6; ++c) {
      const double v = (*ch[static_cast<std::size_t>(c)])[i];
      const double range = c < 3 ? o.max_angular_rate : o.max_specific_force;
      if (!std::isfinite(v)) {
        usable[i] = 0;
      } else if (std::abs(v) > range && usable[i]) {
        usable[i] = 2;
      }
    }
  }
  const auto h = static_cast<std::size_t>(std::max(o.half_window, 1));
  std::vector<double> w;
  w.reserve(2 * h + 1);
  for (int c = 0; c < 6; ++c) {
    const std::vector<double>& x = *ch[static_cast<std::size_t>(c)];
    const double floor = c < 3 ? o.min_rate_jump : o.min_force_jump;
    for (std::size_t i = 0; i < n; ++i) {
      if (usable[i] != 1) continue;
      w.clear();
      for (std::size_t k = i > h ? i - h : 0; k <= std::min(n - 1, i + h); ++k) {
        if (usable[k] != 0 && std::isfinite(x[k]) && std::abs(x[k]) <= (c < 3 ? o.max_angular_rate : o.max_specific_force))
          w.push_back(x[k]);
      }
      if (w.size() < 3) continue;
      double median = 0, spread = 0;
      median_and_spread(w, median, spread);
      if (std::abs(x[i] - median) > o.hampel_k * spread + floor) usable[i] = 3;
    }
  }
  std::size_t first = 0;
  while (first < n && usable[first] != 1) ++first;
  if (first == n) throw DataError("stream '" + stream + "': no usable IMU sample (all missing or out of range)");
  // A run of rejected or missing samples is bridged by a line from the mean
  // of the half_window usable samples before it to that of those after it
  // (the log is processed offline: both ends are known), each end's noise
  // averaged; before the first or after the last usable sample, a constant.
  s.bridged.assign(n, 0);
  for (int c = 0; c < 6; ++c) s.values[static_cast<std::size_t>(c)] = *ch[static_cast<std::size_t>(c)];
  const auto mean_of = [&](const std::vector<std::size_t>& idx, std::size_t c) {
    double sum = 0;
    for (std::size_t k : idx) sum += (*ch[c])[k];
    return sum / static_cast<double>(idx.size());
  };
  std::vector<std::size_t> before, after;
  for (std::size_t a = 0; a < n;) {
    if (usable[a] == 1) {
      ++a;
      continue;
    }
    std::size_t b = a;
    while (b < n && usable[b] != 1) ++b;  // [a, b) unusable
    before.clear();
    after.clear();
    for (std::size_t k = a; k-- > 0 && before.size() < h;) {
      if (usable[k] == 1) before.push_back(k);
    }
    for (std::size_t k = b; k < n && after.size() < h; ++k) {
      if (usable[k] == 1) after.push_back(k);
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
    const double t0 = before.empty() ? t[b] : t[a - 1], t1 = after.empty() ? t[a - 1] : t[b];
    for (std::size_t c = 0; c < 6; ++c) {
      const double v0 = mean_of(before.empty() ? after : before, c), v1 = mean_of(after.empty() ? before : after, c);
      for (std::size_t i = a; i < b; ++i) {
        const double w = t1 > t0 ? (t[i] - t0) / (t1 - t0) : 0.0;
        s.values[c][i] = v0 + w * (v1 - v0);
      }
    }
    for (std::size_t i = a; i < b; ++i) {
      s.bridged[i] = 1;
      if (usable[i] == 0) {
        ++s.missing;
      } else {
        ++s.outliers;
      }
    }
    a = b;
  }
  // Gaps: intervals between usable samples longer than gap_periods nominal periods.
  std::vector<double> dt;
  for (std::size_t i = 1; i < n; ++i) dt.push_back(t[i] - t[i - 1]);
  double period = 0;
  if (!dt.empty()) {
    std::nth_element(dt.begin(), dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2), dt.end());
    period = dt[dt.size() / 2];
  }
  std::size_t prev = first;
  for (std::size_t i = first + 1; i <= n; ++i) {
    if (i < n && usable[i] != 1) continue;
    const double start = t[prev], end = i < n ? t[i] : t[n - 1];
    if (end - start > o.max_bridged_gap) {
      throw DataError("stream '" + stream + "': a gap of " + format("%.6g s", end - start) + " without a usable sample after t = " +
                      format("%.6g s", start) + " (more than " + format("%.6g s", o.max_bridged_gap) +
                      ", the longest bridged by prediction: a broken time stamp or a dropout)");
    }
    if (end - start > o.gap_periods * period) s.gaps.push_back({start, end});
    prev = std::min(i, n - 1);
  }
  if (first > 0) s.gaps.insert(s.gaps.begin(), TimeGap{t[0], t[first]});
  return s;
}

double ScreenedImu::added_variance(std::size_t i, int channel) const {
  if (i >= bridged.size() || bridged[i] == 0) return 0.0;
  const auto after = std::upper_bound(runs.begin(), runs.end(), i, [](std::size_t k, const Run& r) { return k < r.begin; });
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
  if (outliers_rejected > 0) parts.push_back(count(outliers_rejected, "IMU sample", "IMU samples") + " rejected as outliers");
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
                    (gaps.size() == 1 ? " of " + format("%.2f s", total)
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
  if (parts.empty()) return "healthy: no sample rejected, no gap, no divergence";
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
  if (!P.allFinite()) return "covariance not finite";
  if (Eigen::LLT<Eigen::MatrixXd>(P).info() != Eigen::Success) return "covariance not positive definite";
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

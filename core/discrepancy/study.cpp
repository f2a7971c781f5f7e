#include "core/discrepancy/study.h"

#include <cmath>
#include <cstdio>

namespace roverlab::analysis {

bool Trend::measured() const { return std::isfinite(slope); }

// Ordinary least squares, b = Sxy / Sxx, se(b) = sqrt(SSE / (n - 2) / Sxx),
// SSE summed from the residuals themselves (no Syy - b Sxy cancellation).
Trend regress(const std::vector<double>& x, const std::vector<double>& y) {
  std::size_t n = 0;
  double mx = 0, my = 0;
  const auto pair = [&](std::size_t k) { return k < y.size() && std::isfinite(x[k]) && std::isfinite(y[k]); };
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!pair(k)) continue;
    mx += x[k];
    my += y[k];
    ++n;
  }
  if (n < 3) return {NAN, NAN};
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0, sxy = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!pair(k)) continue;
    sxx += (x[k] - mx) * (x[k] - mx);
    sxy += (x[k] - mx) * (y[k] - my);
  }
  if (sxx <= 1e-12 * static_cast<double>(n) * (1.0 + mx * mx)) return {NAN, NAN};
  Trend l{sxy / sxx, NAN};
  double sse = 0;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (!pair(k)) continue;
    const double e = y[k] - my - l.slope * (x[k] - mx);
    sse += e * e;
  }
  l.t = l.slope / std::sqrt(sse / static_cast<double>(n - 2) / sxx);
  return l;
}

double rmse(const std::vector<double>& e, double per_point) {
  double s = 0;
  for (double v : e) s += v * v;
  return e.empty() ? NAN : std::sqrt(per_point * s / static_cast<double>(e.size()));
}

const char* step_role_name(StepRole role) {
  switch (role) {
    case StepRole::cause:
      return "cause";
    case StepRole::also_consistent:
      return "also consistent";
    case StepRole::at_bound:
      return "at its bound";
  }
  return "cause";
}

double gain_share(double baseline, double without, double final_error) {
  const double gain = baseline - final_error;
  return gain > 0 ? (without - final_error) / gain : NAN;
}

double without_step(double final_error, double before, double after) { return final_error + before - after; }

std::string last_link(const std::string& name) {
  const auto plus = name.rfind(" + ");
  return plus == std::string::npos ? name : name.substr(plus + 3);
}

std::string step_share_text(const std::string& name, double share) {
  char one[64];
  std::snprintf(one, sizeof one, " (%.3g %% of the held-out gain)", 100.0 * share);
  return last_link(name) + one;
}

StepRole step_role(bool at_bound, double share, double negligible, bool cuts) {
  if (at_bound) return StepRole::at_bound;
  return !(share >= negligible) || !cuts ? StepRole::also_consistent : StepRole::cause;
}

}  // namespace roverlab::analysis

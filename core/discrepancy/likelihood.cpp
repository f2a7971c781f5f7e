#include "core/discrepancy/likelihood.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace roverlab::analysis {

namespace {

// Residuals a group's first values need before they count: one for an
// integrated group (an increment needs the value before it).
std::size_t lags_needed(const ResidualGroup& g) { return g.integrated ? 1U : 0U; }

// Visits each residual of a group that has the lags it needs, with its
// (differenced) value, its predecessor's and the ordinal of its segment
// within the group: f(x, previous, segment). The first of a segment has the
// predecessor 0, so that its innovation is its whole value: an
// autocorrelation near 1 cannot make a level offset within a block free.
template <typename F>
void for_each_usable(const ResidualGroup& g, const std::vector<char>& start, std::size_t begin, const double* in,
                     std::size_t stride, F&& f) {
  const std::size_t need = lags_needed(g);
  std::size_t pos = 0, segment = 0;
  for (std::size_t i = 0; i < g.size; ++i, ++pos) {
    const std::size_t at = begin + i;
    if (i == 0 || (!start.empty() && start[at] != 0)) {
      if (i > 0) ++segment;
      pos = 0;
    }
    if (pos < need) continue;
    auto value = [&](std::size_t k) { return in[k * stride]; };
    const double x = g.integrated ? value(at) - value(at - 1) : value(at);
    double prev = 0;
    if (g.autocorrelated && pos > need) prev = g.integrated ? value(at - 1) - value(at - 2) : value(at - 1);
    f(x, prev, segment);
  }
}

}  // namespace

GroupedLikelihood::GroupedLikelihood(std::vector<ResidualGroup> groups, std::vector<char> segment_start)
    : groups_(std::move(groups)), start_(std::move(segment_start)) {
  for (const auto& g : groups_) {
    if (!(g.floor > 0) || !std::isfinite(g.floor))
      throw std::invalid_argument("likelihood group " + g.name + ": the noise floor must be finite and > 0");
    size_ += g.size;
  }
  if (!start_.empty() && start_.size() != size_)
    throw std::invalid_argument("likelihood: one segment flag per residual is needed");
}

std::size_t GroupedLikelihood::effective_count() const {
  std::size_t n = 0, begin = 0;
  std::vector<double> zeros(size_, 0.0);
  for (const auto& g : groups_) {
    for_each_usable(g, start_, begin, zeros.data(), 1, [&](double, double, std::size_t) { ++n; });
    begin += g.size;
  }
  return n;
}

LikelihoodProfile GroupedLikelihood::profile(const std::vector<double>& r) const {
  if (r.size() != size_) throw std::invalid_argument("likelihood: residual count differs from the groups'");
  LikelihoodProfile p;
  std::size_t begin = 0;
  for (const auto& g : groups_) {
    double sxx = 0, sxp = 0, spp = 0;
    std::size_t n = 0;
    for_each_usable(g, start_, begin, r.data(), 1, [&](double x, double prev, std::size_t) {
      sxx += x * x;
      sxp += x * prev;
      spp += prev * prev;
      ++n;
    });
    GroupProfile gp;
    gp.used = n;
    if (g.autocorrelated && spp > 0) gp.rho = std::clamp(sxp / spp, g.min_rho, 1.0);
    // Mean squared innovation: (sxx - 2 rho sxp + rho^2 spp) / n.
    const double ms =
        n > 0 ? std::max(sxx - 2 * gp.rho * sxp + gp.rho * gp.rho * spp, 0.0) / static_cast<double>(n) : 0;
    gp.scale = std::max(std::sqrt(ms), g.floor);
    if (n > 0) p.minus_two_log_l += static_cast<double>(n) * std::log(gp.scale * gp.scale);
    p.groups.push_back(gp);
    begin += g.size;
  }
  return p;
}

LikelihoodProfile GroupedLikelihood::fit_weights(const std::vector<double>& r) const {
  LikelihoodProfile p = profile(r);
  std::size_t begin = 0;
  for (std::size_t gi = 0; gi < groups_.size(); ++gi) {
    double s = 0;
    std::size_t n = 0;
    for_each_usable(groups_[gi], start_, begin, r.data(), 1, [&](double x, double, std::size_t) {
      s += x * x;
      ++n;
    });
    p.groups[gi].rho = 0;
    p.groups[gi].scale = std::max(n > 0 ? std::sqrt(s / static_cast<double>(n)) : 0.0, groups_[gi].floor);
    begin += groups_[gi].size;
  }
  return p;
}

void GroupedLikelihood::whiten(const LikelihoodProfile& at, const double* in, double* out, std::size_t stride) const {
  std::size_t begin = 0, j = 0;
  for (std::size_t gi = 0; gi < groups_.size(); ++gi) {
    const double rho = at.groups[gi].rho, scale = at.groups[gi].scale;
    for_each_usable(groups_[gi], start_, begin, in, stride,
                    [&](double x, double prev, std::size_t) { out[j++] = (x - rho * prev) / scale; });
    begin += groups_[gi].size;
  }
}

std::vector<std::size_t> GroupedLikelihood::segments() const {
  std::vector<std::size_t> out;
  out.reserve(effective_count());
  const std::vector<double> zeros(size_, 0.0);
  std::size_t begin = 0;
  for (const auto& g : groups_) {
    for_each_usable(g, start_, begin, zeros.data(), 1,
                    [&](double, double, std::size_t segment) { out.push_back(segment); });
    begin += g.size;
  }
  return out;
}

std::string format_delta_bic(double d) {
  if (!std::isfinite(d)) return "n/a";
  if (d <= -1e6) return "< -1e6";
  if (d >= 1e6) return "> 1e6";
  char buf[40];
  if (std::abs(d) < 100) {
    std::snprintf(buf, sizeof buf, "%.1f", d);
    return buf;
  }
  std::snprintf(buf, sizeof buf, "%.0f", std::abs(d));
  std::string digits = buf, grouped;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) grouped += ',';
    grouped += digits[i];
  }
  return (d < 0 ? "-" : "") + grouped;
}

std::string format_estimate(double value, double sigma, const std::string& unit) {
  char buf[96];
  const std::string u = unit.empty() || unit == "1" ? "" : " " + unit;
  if (std::isfinite(sigma) && sigma > 0) {
    std::snprintf(buf, sizeof buf, "%.4g +- %.2g", value, sigma);
  } else {
    std::snprintf(buf, sizeof buf, "%.4g", value);
    return buf + u + " (not determined by the data)";
  }
  return buf + u;
}

bool near_bound(double value, double lower, double upper) {
  const double range = upper - lower;
  const auto close = [&](double bound) {
    const double tolerance = std::max(std::min(0.01 * std::abs(bound), 0.01 * range), 1e-6 * range);
    return std::abs(value - bound) <= tolerance;
  };
  return close(lower) || close(upper);
}

std::string format_fitted(double value, double sigma, const std::string& unit, bool at_bound) {
  if (!at_bound) return format_estimate(value, sigma, unit);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", value);
  return buf + (unit.empty() || unit == "1" ? std::string() : " " + unit) + " (at its bound)";
}

}  // namespace roverlab::analysis

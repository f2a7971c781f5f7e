#pragma once
// The discrepancy studies' likelihood (issue 29). Residuals come in groups
// (a channel of a rover log, a measured quantity of a wheel test); each group
// has its own noise scale and its own first-order autocorrelation, and both
// are profiled out, i.e. estimated anew for every model the study evaluates:
//   -2 ln L = sum_g n_g ln(s_g^2),  s_g^2 = min_rho mean_k (e_k - rho e_{k-1})^2
// (Gaussian AR(1) likelihood, constants dropped; the first residual of a
// segment has the predecessor 0, so its innovation is its whole value). A group of an
// integrated quantity (a wheel encoder's angle) is first differenced: its
// increments are compared, not its integral. One badly explained group then
// cannot set another's scale, and autocorrelated residuals count as the
// innovations they are instead of as thousands of independent samples.
// The same object whitens residuals and Jacobian columns for a least-squares
// fit (rho and s held at a profile), so the fit's covariance is in the
// likelihood's units.

#include <cstddef>
#include <string>
#include <vector>

namespace roverlab::analysis {

struct ResidualGroup {
  std::string name;
  std::size_t size = 0;        // consecutive residuals in the vector, groups in order
  bool integrated = false;     // compare increments: difference before the AR(1) whitening
  double floor = 0;            // smallest noise scale trusted, in the residuals' units (> 0)
  bool autocorrelated = true;  // false: rho held at 0 (independent points, as in a wheel test)
  double min_rho = 0;          // the lowest autocorrelation allowed (< 0: increments of white noise, -0.5)
};

struct GroupProfile {
  double rho = 0;        // lag-1 autocorrelation of the (differenced) residuals, in [min_rho, 1]
  double scale = 1;      // innovation standard deviation, >= the group's floor
  std::size_t used = 0;  // residuals with the lags they need
};

struct LikelihoodProfile {
  std::vector<GroupProfile> groups;
  double minus_two_log_l = 0;
};

class GroupedLikelihood {
 public:
  // segment_start[i] != 0 when residual i has no predecessor (the first of a
  // block; empty: only each group's first residual).
  GroupedLikelihood(std::vector<ResidualGroup> groups, std::vector<char> segment_start = {});

  std::size_t size() const { return size_; }
  const std::vector<ResidualGroup>& groups() const { return groups_; }
  // The residuals that count (those with their lags), the n of BIC's ln n.
  std::size_t effective_count() const;

  // Each group's rho and scale at these residuals, and -2 ln L there.
  LikelihoodProfile profile(const std::vector<double>& residuals) const;
  double minus_two_log_l(const std::vector<double>& residuals) const { return profile(residuals).minus_two_log_l; }
  // Weights for fitting a model started at these residuals: each group's
  // RMS (of the increments, for an integrated group) as its scale, rho 0.
  // A fit whitened by the start's autocorrelation would be blind to what
  // makes the start autocorrelated: a level shift is differenced away.
  LikelihoodProfile fit_weights(const std::vector<double>& residuals) const;

  // Innovations divided by the profile's scales: e.g. residuals or a
  // Jacobian column (linear in its input); out has effective_count() entries.
  // `stride` reads every stride-th value (a column of a row-major matrix).
  void whiten(const LikelihoodProfile& at, const double* in, double* out, std::size_t stride = 1) const;
  // For each of whiten()'s outputs, the ordinal of its segment within its
  // group: the same ordinal in every group is the same block of time.
  std::vector<std::size_t> segments() const;

 private:
  std::vector<ResidualGroup> groups_;
  std::vector<char> start_;
  std::size_t size_ = 0;
};

// "delta BIC" in a form a person reads: one decimal below 100, whole numbers
// with thousands separators up to 1e6, and "< -1e6" / "> 1e6" beyond.
std::string format_delta_bic(double delta_bic);

// "0.832 +- 0.012", or "0.832 (not determined by the data)" when sigma is not
// finite or not positive; `unit` appended when not "1".
std::string format_estimate(double value, double sigma, const std::string& unit);

// A fitted value at a bound of its search, or within 1 % of it (1 % of the
// bound's size, at most 1 % of the range; at least 1e-6 of the range for a
// bound at 0): a fact about the search, not about the world (issue 43).
bool near_bound(double value, double lower, double upper);

// format_estimate, or "0.3 (at its bound)" with no sigma when at_bound.
std::string format_fitted(double value, double sigma, const std::string& unit, bool at_bound);

}  // namespace roverlab::analysis

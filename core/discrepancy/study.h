#pragma once

// What every discrepancy study computes the same way (single_wheel/,
// odometry/, rover/): the trend of a residual against an explanatory
// variable and the root-mean-square of residuals. One definition each, so
// that the three studies' tables mean the same thing by the same word.

#include <vector>

namespace roverlab::analysis {

// A least-squares slope of y on x with its t statistic.
struct Trend {
  double slope;  // NaN: no trend can be measured (fewer than 3 pairs, or x does not vary)
  double t;      // slope / its standard error; +-inf for residuals exactly on a sloped line, NaN on a flat one
  bool measured() const;
};

// The slope of y on x over the pairs where both are finite (a NaN marks a
// sample without a value, e.g. a slip where the wheels stand still), and
// its t statistic on n - 2 degrees of freedom. x "does not vary" when
// Sxx <= 1e-12 n (1 + mean(x)^2): rounding alone, relative to x's size.
Trend regress(const std::vector<double>& x, const std::vector<double>& y);

// sqrt(per_point * sum(e^2) / e.size()): the RMS of e, or, with per_point 2
// and e holding (east, north) pairs, the RMS horizontal error. NaN for no e.
double rmse(const std::vector<double>& e, double per_point = 1.0);

}  // namespace roverlab::analysis

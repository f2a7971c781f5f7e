#pragma once

// What every discrepancy study computes the same way (single_wheel/,
// odometry/, rover/): the trend of a residual against an explanatory
// variable (the residual diagnostics), the root-mean-square of residuals
// (held-out scoring), and what a step of the forward selection is in the
// verdict. One definition each, so that the three studies' tables mean the
// same thing by the same word.

#include <cstddef>
#include <vector>

#include "core/common/thread_pool.h"

namespace roverlab::analysis {

// A step of the odometry or single-wheel forward selection whose share of
// the held-out gain (the held-out error it cut against the step before, over
// the whole chain's cut) is under this is reported as "also consistent
// with", not as a cause. Calibrated on simulated truth (issue 43, 40 seeds
// per kind, sizes down to the edge of detection; docs/validation/
// discrepancy.md, "A cause that matters"): a hidden effect alone holds
// 100 % (398 of 398 one-effect steps), so the threshold matters for a
// second cause beside a larger one. Real second causes: 1 of 214 single-wheel
// steps under 1 % (0.41 %), 14 under 2 %; odometry 2 of 131 under 1 % or
// 2 % (0.58 %, 0.59 %). Stand-ins: 2 of 38 under 1 % (-0.47 %, 0.74 %), the
// next at 2.75 %; odometry 5 of 5 at 100 %. 2 % demoted 13 more real causes
// than 1 % and no more stand-ins. (The rover study names a step by its
// share of a channel's gain instead, kNegligibleChannelShare.)
constexpr double kNegligibleGainShare = 0.01;

// What a step of a forward selection is in the verdict.
enum class StepRole {
  cause,            // named as a cause
  also_consistent,  // its share of the held-out gain is under kNegligibleGainShare
  at_bound          // a parameter at its bound: a fact about the search, not a cause
};

// "cause", "also consistent", "at its bound" (the JSON documents' words).
const char* step_role_name(StepRole role);

// Share of the held-out gain: (without - final) / (baseline - final); NaN
// when the chain gains nothing.
double gain_share(double baseline, double without, double final_error);

// The verdict's rule for a selected step, the same in every study: a step
// with a parameter at its bound is never a cause; a step whose share of the
// gain (the whole held-out gain, or, in the rover study, a channel's) is not
// at least `negligible`, or (single wheel) that cuts no quantity's held-out
// error to 0.7 of the step before, is only consistent with the data.
StepRole step_role(bool at_bound, double share, double negligible, bool cuts = true);

// The candidate screen: candidate i fitted alone by fit(i) for i < count, in
// parallel on the shared thread pool (core/common/thread_pool.h), results
// in candidate order; each fit independent of the others, so the results
// are the same on any number of threads. Rethrows the lowest index's error.
template <class Result, class Fit>
std::vector<Result> screen_candidates(std::size_t count, const Fit& fit) {
  std::vector<Result> out(count);
  shared_thread_pool().for_each_index(count, [&](std::size_t i) { out[i] = fit(i); });
  return out;
}

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

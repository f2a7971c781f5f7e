#pragma once
// The calibration of the negligible-share threshold (issue 43,
// kNegligibleGainShare in core/discrepancy/study.h): every step a forward
// selection took on simulated truth, whether it is a hidden effect, its
// share of the held-out gain, whether it cut a quantity's held-out RMSE by
// 30 %, and the role the study gave it. The single-wheel and odometry tests
// fill it; this prints the table and the shares' distributions.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/discrepancy/study.h"

namespace roverlab::test {

struct StepShare {
  std::string run;     // what was hidden, e.g. "slip-sinkage x0.25 seed 4003"
  std::string step;    // the candidate the step added
  int effects = 0;     // hidden effects in the run
  bool truth = false;  // the step adds a hidden effect no earlier step accounts for
  double share = 0.0;  // its share of the held-out gain
  bool cuts = true;    // cut some quantity's held-out RMSE to 0.7 of the step before (single wheel)
  analysis::StepRole role = analysis::StepRole::cause;
};

// The q-quantile (0..1) of sorted values, nearest rank; NaN for none.
inline double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return NAN;
  const auto k = static_cast<std::size_t>(std::lround(q * static_cast<double>(sorted.size() - 1)));
  return sorted[std::min(k, sorted.size() - 1)];
}

inline std::vector<double> shares_of(const std::vector<StepShare>& steps, bool truth) {
  std::vector<double> out;
  for (const auto& s : steps) {
    if (s.truth == truth) out.push_back(s.share);
  }
  std::sort(out.begin(), out.end());
  return out;
}

// One line per step, then the true and spurious steps' share distributions.
inline void print_step_shares(const char* study, const std::vector<StepShare>& steps) {
  std::printf("%s: %zu selected steps\n", study, steps.size());
  std::printf("  %-62s %-22s %-5s %9s %-4s %s\n", "run", "step", "true", "share %", "cut", "role");
  for (const auto& s : steps) {
    std::printf("  %-62s %-22s %-5s %9.3g %-4s %s\n", s.run.c_str(), s.step.c_str(), s.truth ? "yes" : "no",
                100.0 * s.share, s.cuts ? "yes" : "no", analysis::step_role_name(s.role));
  }
  for (const bool truth : {true, false}) {
    const auto v = shares_of(steps, truth);
    std::printf("  %s steps: %zu; share %% min %.3g, 10th %.3g, median %.3g, 90th %.3g, max %.3g\n",
                truth ? "true" : "spurious", v.size(), v.empty() ? 0.0 : 100.0 * v.front(), 100.0 * quantile(v, 0.1),
                100.0 * quantile(v, 0.5), 100.0 * quantile(v, 0.9), v.empty() ? 0.0 : 100.0 * v.back());
  }
}

// How the steps fall about a threshold: true steps (one-effect runs, then
// runs with two) under it, spurious steps at or over it and named as causes.
struct ShareCounts {
  unsigned true_one = 0, true_one_under = 0, true_two = 0, true_two_under = 0;
  unsigned spurious = 0, spurious_over = 0, spurious_named = 0;
};

inline ShareCounts count_step_shares(const std::vector<StepShare>& steps, double threshold) {
  ShareCounts c;
  for (const auto& s : steps) {
    if (s.truth) {
      (s.effects == 1 ? c.true_one : c.true_two) += 1;
      (s.effects == 1 ? c.true_one_under : c.true_two_under) += s.share < threshold ? 1 : 0;
      continue;
    }
    ++c.spurious;
    c.spurious_over += s.share >= threshold ? 1 : 0;
    c.spurious_named += s.role == analysis::StepRole::cause ? 1 : 0;
  }
  std::printf(
      "  at %.3g %%: true steps of one-effect runs %u, under it %u; of two-effect runs %u, under it %u; "
      "spurious steps %u, at or over it %u, named as a cause %u\n",
      100.0 * threshold, c.true_one, c.true_one_under, c.true_two, c.true_two_under, c.spurious, c.spurious_over,
      c.spurious_named);
  return c;
}

}  // namespace roverlab::test

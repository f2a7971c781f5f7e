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

// The step a chain's name ends with: "slip-sinkage + grousers" -> "grousers".
inline std::string last_step(const std::string& chain) {
  const auto plus = chain.rfind(" + ");
  return plus == std::string::npos ? chain : chain.substr(plus + 3);
}

// Whether a study names exactly one cause, and that step's chain name
// matches (match(name) true).
template <class Report, class Match>
bool names_exactly(const Report& r, Match match) {
  int causes = 0;
  bool right = false;
  for (const auto& s : r.selection) {
    if (s.role != analysis::StepRole::cause) continue;
    ++causes;
    right = match(s.name);
  }
  return causes == 1 && right;
}

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

// The selection's steps of one single-wheel study (a report with selection,
// baseline_held_out_rmse and per step name, gain_share, held_out_rmse and
// role), as the calibration records them; `hidden` names the hidden effects.
template <class Report>
void record_steps(const Report& r, const std::string& run, const std::vector<std::string>& hidden,
                  std::vector<StepShare>& out) {
  const std::vector<double>* before = &r.baseline_held_out_rmse;
  std::vector<std::string> accounted;
  for (const auto& s : r.selection) {
    StepShare rec;
    rec.run = run;
    rec.step = last_step(s.name);
    rec.effects = static_cast<int>(hidden.size());
    rec.truth = std::find(hidden.begin(), hidden.end(), rec.step) != hidden.end() &&
                std::find(accounted.begin(), accounted.end(), rec.step) == accounted.end();
    accounted.push_back(rec.step);
    rec.share = s.gain_share;
    rec.cuts = false;
    for (std::size_t qi = 0; qi < s.held_out_rmse.size() && qi < before->size(); ++qi)
      rec.cuts = rec.cuts || s.held_out_rmse[qi] <= 0.7 * (*before)[qi];
    rec.role = s.role;
    out.push_back(rec);
    before = &s.held_out_rmse;
  }
}

// The table, the one-effect runs' count, the trade-off at other thresholds,
// and the counts at kNegligibleGainShare, which the calibration tests bound:
// no hidden effect the selection took in a one-effect run under it, nor more
// than 1 in 20 of the second effects of two-effect runs (measured over 40
// seeds: 1 of 214 single-wheel, 2 of 131 odometry). Stand-ins are counted,
// not bounded: most take large shares (they replace a hidden effect in the
// chain), which no share threshold can tell from a cause
// (docs/validation/discrepancy.md).
inline ShareCounts report_step_shares(const char* study, const std::vector<StepShare>& steps, unsigned one_effect_runs,
                                      unsigned named_alone) {
  print_step_shares(study, steps);
  std::printf("one-effect runs: %u, exactly their effect named: %u\n", one_effect_runs, named_alone);
  for (const double threshold : {0.005, 0.02, 0.05, 0.10}) count_step_shares(steps, threshold);
  return count_step_shares(steps, analysis::kNegligibleGainShare);
}

}  // namespace roverlab::test

#pragma once

// What every discrepancy study computes the same way (single_wheel/,
// odometry/, rover/): the trend of a residual against an explanatory
// variable (the residual diagnostics), the root-mean-square of residuals
// (held-out scoring), and what a step of the forward selection is in the
// verdict. One definition each, so that the three studies' tables mean the
// same thing by the same word.

#include <algorithm>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
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

// The forward selection every study runs (issue 42 item 2), written once:
// rounds while the chain holds fewer than max_steps candidates. A round tries
// every open candidate on top of the chain, in parallel on the shared
// thread pool (trials in candidate order, each independent of the others,
// so the round is the same on any number of threads), asks which trial is
// best, and stops unless the study's rule accepts it; the accepted trial
// joins the chain. The study (its data, model and candidates) supplies:
//   using Trial = ...;  // default-constructible
//   bool open(const std::vector<std::size_t>& chain, std::size_t i);
//       // candidate i (not in the chain) may be tried; called on the calling
//       // thread in candidate order before the trials, so it may prepare one
//   Trial trial(const std::vector<std::size_t>& chain, std::size_t i) const;
//       // candidate i on top of the chain (called concurrently)
//   int best(const std::vector<std::size_t>& open, std::vector<Trial>& trials);
//       // the best trial's candidate, -1 for none (trials[i] for i in open)
//   bool accept(const std::vector<std::size_t>& chain, std::size_t i, Trial& t);
//       // the study's stopping rule: false ends the selection
//   void join(std::vector<std::size_t>& chain, std::size_t i, Trial&& t);
//       // appends i (or more) to the chain and keeps the step
// and may supply
//   double expected_cost(std::size_t i) const;
//       // how long candidate i's trial is expected to take (any unit): the
//       // trials start longest first, so that a long one does not start last
//       // and run alone at the round's end. Only the order they start in
//       // changes, not what they compute.
template <class Study, class = void>
struct HasExpectedCost : std::false_type {};
template <class Study>
struct HasExpectedCost<Study, std::void_t<decltype(std::declval<const Study&>().expected_cost(std::size_t{}))>>
    : std::true_type {};

template <class Study>
void select_forward(Study& study, std::size_t count, std::size_t max_steps, std::vector<std::size_t>& chain) {
  using Trial = typename Study::Trial;
  while (chain.size() < max_steps) {
    std::vector<std::size_t> open;
    for (std::size_t i = 0; i < count; ++i) {
      if (std::find(chain.begin(), chain.end(), i) == chain.end() && study.open(chain, i)) open.push_back(i);
    }
    if (open.empty()) return;
    std::vector<std::size_t> start = open;  // the order the trials start in
    if constexpr (HasExpectedCost<Study>::value) {
      std::vector<double> cost(count);  // asked once per candidate, not at every comparison
      for (std::size_t i : open) cost[i] = study.expected_cost(i);
      std::stable_sort(start.begin(), start.end(), [&](std::size_t a, std::size_t b) { return cost[a] > cost[b]; });
    }
    std::vector<Trial> trials(count);
    shared_thread_pool().for_each_index(start.size(),
                                        [&](std::size_t k) { trials[start[k]] = study.trial(chain, start[k]); });
    const int best = study.best(open, trials);
    if (best < 0) return;
    const auto b = static_cast<std::size_t>(best);
    if (!study.accept(chain, b, trials[b])) return;
    study.join(chain, b, std::move(trials[b]));
  }
}

// The first of the open trials that no later one beats (better(a, b): a
// beats b), as Study::best returns it; -1 when none is open.
template <class Trial, class Better>
int best_trial(const std::vector<std::size_t>& open, const std::vector<Trial>& trials, const Better& better) {
  int best = -1;
  for (std::size_t i : open) {
    if (best < 0 || better(trials[i], trials[static_cast<std::size_t>(best)])) best = static_cast<int>(i);
  }
  return best;
}

// Weighs the steps of a forward selection, in chain order (issue 43): each
// step's share of the held-out gain, gain_share(baseline, without(step),
// final_error), where without is the held-out error of the final model
// without that step, and its role, role(step) (step_role with the study's
// rule: its share of the whole gain or of a channel's, its bounds, its cut).
// Each hook is called once a step, in chain order, without before role, and
// may fill in the step's own fields. Step has members gain_share and role.
template <class Step, class Without, class Role>
void weigh_steps(std::vector<Step>& steps, double baseline, double final_error, const Without& without,
                 const Role& role) {
  for (auto& step : steps) {
    step.gain_share = gain_share(baseline, without(step), final_error);
    step.role = role(step);
  }
}

// The held-out error of a final model without a step of a chain scored
// step by step, nothing refitted: the final error plus what the step cut
// (the error before it less the error after it).
double without_step(double final_error, double before, double after);

// The verdict's list of named steps (issue 43): the causes joined by `then`
// (", then "), the others by "; " into `also`, or, when bound_apart, those
// with a parameter at its bound into `bound`; text(step) is a step's words.
struct StepLists {
  std::string named, also, bound;
  int causes = 0;
};
template <class Step, class Text>
StepLists list_steps(const std::vector<Step>& steps, const Text& text, const char* then, bool bound_apart = false) {
  StepLists out;
  for (const auto& step : steps) {
    if (step.role == StepRole::cause) {
      out.named += (out.causes++ > 0 ? then : "") + text(step);
    } else {
      std::string& list = bound_apart && step.role == StepRole::at_bound ? out.bound : out.also;
      list += (list.empty() ? "" : "; ") + text(step);
    }
  }
  return out;
}

// The last link of a joint step's "a + b" name ("b"; the name itself when
// it has one link): the cause that step adds.
std::string last_link(const std::string& name);

// "NAME (S % of the held-out gain)", NAME the step's last_link: a step of
// the odometry or single-wheel verdict.
std::string step_share_text(const std::string& name, double share);

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

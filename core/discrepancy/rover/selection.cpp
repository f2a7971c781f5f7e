// The rover discrepancy study's forward selection and verdict.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <memory>

#include "core/common/error.h"
#include "core/common/thread_pool.h"
#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/rover/candidates.h"
#include "core/discrepancy/rover/fit.h"
#include "core/discrepancy/rover/prediction.h"
#include "core/discrepancy/rover/study.h"

namespace roverlab::analysis::rover {

namespace {

std::vector<RoverParameterFit> fits_of(const std::vector<FitParameter>& p, std::size_t from) {
  std::vector<RoverParameterFit> out;
  for (std::size_t j = from; j < p.size(); ++j) {
    const RoverCandidateParameter& sp = p[j].spec;
    // At or within 1 % of a bound: the search stopped there, so no sigma (issue 43).
    const bool at_bound = sp.fitted && near_bound(p[j].value, sp.lower, sp.upper);
    out.push_back({sp.effect, sp.unit, p[j].value, at_bound ? NAN : p[j].sigma, at_bound});
  }
  return out;
}

struct Trial {
  FitOutcome fit;
  double screened_fit = 0;  // -2 ln L the linearised fit predicts
  double delta_bic = 0;
  bool significant = false;
  bool screened = false;  // judged by its linearised fit alone
  int simulations = 0;
  bool applies = false;
  JacobianMemo jacobian;  // the screen's, carried into the fit
};

// The most candidates a round fits after screening; the best screen is always among them.
constexpr std::size_t kMaxFitsPerRound = 3;

// The candidate's own parameters (those after the chain) moved to their
// grids' best, the chain held where it is: the chain is at its optimum and a
// grid would only move it off it.
void grid_start_candidate(Predictor& pr, std::vector<FitParameter>& parameters, std::size_t chain) {
  std::vector<char> was(parameters.size());
  for (std::size_t j = 0; j < chain; ++j) {
    was[j] = parameters[j].free ? 1 : 0;
    parameters[j].free = false;
  }
  grid_start(pr, parameters);
  for (std::size_t j = 0; j < chain; ++j) parameters[j].free = was[j] != 0;
}

// -2 ln L on the fit blocks at these values; NaN where the simulator refuses them.
double score_or_nan(Predictor& pr, const std::vector<FitParameter>& parameters) {
  try {
    const std::vector<double> r = pr.residuals(effects_of(pr.scenario_effects(), parameters), Part::fit);
    return pr.likelihood(Part::fit).minus_two_log_l(r);
  } catch (const DataError&) {
    return NAN;
  }
}

// What a round's trials share: the chain, the model's score, the options.
struct RoundSetting {
  const RoverResidualFeatures& features;
  const std::vector<FitParameter>& chain;
  const Score& current;
  double ln_n = 0, min_delta_bic = 0;
  bool with_sigmas = false;
};

// Screens candidate `c` on top of the chain by one Gauss-Newton step (and
// the step simulated), on its own predictor.
void screen_trial(Predictor& pr, const RoverCandidate& c, const RoundSetting& s, Trial& t) {
  const std::vector<RoverCandidateParameter> specs = c.parameters(s.features);
  t.applies = true;
  t.fit.parameters = s.chain;
  for (auto& p : t.fit.parameters) p.free = true;
  for (const auto& sp : specs) t.fit.parameters.push_back({sp, sp.start, 0.0, true});
  const int sims = pr.simulations();
  if (std::any_of(specs.begin(), specs.end(), [](const RoverCandidateParameter& sp) { return sp.grid_screen; }))
    grid_start_candidate(pr, t.fit.parameters, s.chain.size());
  t.screened_fit = linearised_fit(pr, t.fit.parameters, s.current.weights, t.jacobian);
  // The linear model misjudges a response that curves: suite seed 428's
  // slip-sinkage of 0.45 was screened at delta BIC -3,747 from n1 = 0 and
  // never fitted, though the step landed at 0.47. The step is simulated too
  // and the better of the two counts (one simulation for a physical cause).
  t.screened_fit = std::min(t.screened_fit, score_or_nan(pr, t.fit.parameters));
  t.simulations = pr.simulations() - sims;
  t.screened = true;
  t.fit.score = s.current;
  t.fit.score.fit = t.screened_fit;
  for (auto& p : t.fit.parameters) p.sigma = NAN;  // a screen gives no sigma
  t.delta_bic = t.screened_fit - s.current.fit + static_cast<double>(specs.size()) * s.ln_n;
}

// A screened trial fitted in full, from its screen's optimum (or the best
// of a grid where a parameter has one).
void fit_trial(Predictor& pr, const RoundSetting& s, Trial& t) {
  const int sims = pr.simulations();
  const auto k = static_cast<double>(t.fit.parameters.size() - s.chain.size());
  grid_start_candidate(pr, t.fit.parameters, s.chain.size());
  t.fit = fit_parameters(pr, t.fit.parameters, s.current.weights, s.with_sigmas, &t.jacobian);
  t.simulations += pr.simulations() - sims;
  t.screened = false;
  t.delta_bic = t.fit.score.fit - s.current.fit + k * s.ln_n;
  t.significant = t.delta_bic < -s.min_delta_bic && t.fit.score.test < s.current.test;
}

// One round of forward selection (study.h, select_forward): every unused
// candidate on top of the chain, the chain's parameters free beside the
// candidate's (a cause the chain has absorbed, e.g. a force offset taken up
// by a force scale fitted alone, seeds 104 and 393, only shows when the
// chain can move back: with the chain held its screen was worse than
// nothing). The chain is at its joint optimum, so the gain is the
// candidate's: BIC counts its parameters only. Each is screened by one
// Gauss-Newton step (the skeleton's trials, each on its own fork of the
// predictor, in parallel); those whose screen could be significant are
// fitted here, best screen first, at most kMaxFitsPerRound of them,
// skipping a screen that promises under a tenth of the best fit's gain; the
// candidate with the best evidence is always fitted, never screened out.
// The fits run in parallel too when there are threads for them (a fit the
// rule then skips is dropped, its fork with it), and the forks are absorbed
// in candidate order, so the round is the same on any number of threads.
// Returns the significant trial with the lowest delta BIC, -1 for none.
int fit_round(Predictor& pr, std::vector<std::unique_ptr<Predictor>>& forks, const std::vector<std::size_t>& open,
              std::vector<Trial>& trials, const RoundSetting& s) {
  int best = -1;
  std::vector<std::size_t> order;
  for (std::size_t i : open) {
    if (trials[i].delta_bic < -s.min_delta_bic) order.push_back(i);
  }
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return trials[a].screened_fit < trials[b].screened_fit; });
  if (order.size() > kMaxFitsPerRound) order.resize(kMaxFitsPerRound);
  // Each fit on a copy of its trial and fork, adopted only when the rule fits it.
  std::vector<Trial> fitted(order.size());
  std::vector<std::unique_ptr<Predictor>> fit_forks(order.size());
  const auto fit = [&](std::size_t k) {
    fitted[k] = trials[order[k]];
    fit_forks[k] = std::make_unique<Predictor>(*forks[order[k]]);
    fit_trial(*fit_forks[k], s, fitted[k]);
  };
  std::vector<std::exception_ptr> errors(order.size());  // a fit the rule skips throws nothing
  ThreadPool& pool = shared_thread_pool();
  if (pool.threads() > 1) {
    pool.for_each_index(order.size(), [&](std::size_t k) {
      try {
        fit(k);
      } catch (...) {
        errors[k] = std::current_exception();
      }
    });
  }
  double best_gain = 0;  // the largest fall of -2 ln L a fit of this round reached
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::size_t i = order[k];
    // A screen that promises under a tenth of what the best fit so far gained
    // is not fitted (the best screen always is: it comes first).
    if (s.current.fit - trials[i].screened_fit < 0.1 * best_gain) continue;
    if (errors[k]) std::rethrow_exception(errors[k]);
    if (!fit_forks[k]) fit(k);
    trials[i] = std::move(fitted[k]);
    forks[i] = std::move(fit_forks[k]);
    const Trial& t = trials[i];
    best_gain = std::max(best_gain, s.current.fit - t.fit.score.fit);
    if (t.significant && (best < 0 || t.delta_bic < trials[static_cast<std::size_t>(best)].delta_bic))
      best = static_cast<int>(i);
  }
  for (std::size_t i : open) pr.absorb(*forks[i]);
  return best;
}

// The backward half of stepwise selection: a step whose effect, taken out of
// the final chain (set back to neutral, nothing refitted), raises -2 ln L by
// less than its BIC penalty plus min_delta_bic was absorbed by the steps
// after it (e.g. a slip-sinkage refitted to 0.0004 beside grousers): it is
// dropped and said so in the verdict. One simulation a step.
void drop_absorbed_steps(Predictor& pr, const RoverStudyOptions& o, double ln_n, RoverDiscrepancyReport& r,
                         std::vector<FitParameter>& chain, Score& current) {
  if (r.selection.size() < 2) return;
  std::size_t at = 0;
  for (std::size_t i = 0; i < r.selection.size();) {
    const std::size_t k = r.selection[i].parameters.size();
    std::vector<FitParameter> without = chain;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(at),
                  without.begin() + static_cast<std::ptrdiff_t>(at + k));
    const Score s = score(pr, effects_of(pr.scenario_effects(), without));
    if (s.fit - current.fit - static_cast<double>(k) * ln_n > o.min_delta_bic || r.selection.size() < 2) {
      at += k;
      ++i;
      continue;
    }
    r.dropped.push_back(r.selection[i].name);
    r.selection.erase(r.selection.begin() + static_cast<std::ptrdiff_t>(i));
    chain = std::move(without);
    current = s;
  }
}

// A model on the test blocks: -2 ln L, and each channel's mean square
// residual in noise sigmas (encoders as increments, as held_out_sigmas).
struct HeldOutByChannel {
  double test = 0, held_out = NAN;  // -2 ln L; RMS over all channels (Score::held_out)
  std::vector<double> mean_square;
};

HeldOutByChannel held_out_by_channel(Predictor& pr, const std::vector<FitParameter>& chain) {
  const GroupedLikelihood& l = pr.likelihood(Part::test);
  const std::vector<double> res = pr.residuals(effects_of(pr.scenario_effects(), chain), Part::test);
  HeldOutByChannel out;
  out.test = l.minus_two_log_l(res);
  const LikelihoodProfile counts = l.profile(res);
  LikelihoodProfile yardstick;
  for (const auto& g : l.groups()) yardstick.groups.push_back({0.0, g.integrated ? std::sqrt(2.0) : 1.0, 0});
  std::vector<double> w(l.effective_count());
  l.whiten(yardstick, res.data(), w.data());
  std::size_t j = 0;
  double total = 0;
  for (std::size_t c = 0; c < l.groups().size(); ++c) {
    const std::size_t n = counts.groups[c].used;
    double sq = 0;
    for (std::size_t k = 0; k < n && j + k < w.size(); ++k) sq += w[j + k] * w[j + k];
    j += n;
    total += sq;
    out.mean_square.push_back(n > 0 ? sq / static_cast<double>(n) : 0.0);
  }
  out.held_out = w.empty() ? NAN : std::sqrt(total / static_cast<double>(w.size()));
  return out;
}

// A chain's gain on a channel is material when it removes this much of the
// channel's mean square residual (in noise variances): a gyro bias of a
// quarter of the gyro's noise sigma removes 0.06 (suite seed 106).
constexpr double kMaterialChannelGain = 0.02;

// The step's largest share of a channel's held-out gain, over the channels
// the chain improves materially; NaN when it improves none so (a lone weak
// cause, such as a gyro bias of 0.002 rad/s on a 60 s run).
double largest_channel_share(const HeldOutByChannel& base, const HeldOutByChannel& final_model,
                             const HeldOutByChannel& without) {
  double largest = NAN;
  for (std::size_t c = 0; c < base.mean_square.size() && c < final_model.mean_square.size(); ++c) {
    const double gain = base.mean_square[c] - final_model.mean_square[c];
    if (gain < kMaterialChannelGain || c >= without.mean_square.size()) continue;
    const double share = (without.mean_square[c] - final_model.mean_square[c]) / gain;
    largest = std::isnan(largest) ? share : std::max(largest, share);
  }
  return largest;
}

// Each step's share of the held-out gain (issue 43): the final model with
// that step's effects set back to neutral, nothing refitted, scored on the
// test blocks against the whole chain's gain there (one simulation a step).
// gain_share is the share of the chain's gain in the held-out -2 ln L; the
// step is named when its share of some channel's held-out gain is at least
// kNegligibleGainShare: a gyro bias beside a force scale holds 0.25 % of the
// whole gain (suite seed 106) yet all of the gyro channel's, while a soil
// strength of 1.0017 that only stands in for a slip-sinkage (seed 9612)
// holds a few percent of every channel's. A step with a parameter at its
// bound is not named either.
void weigh_steps(Predictor& pr, RoverDiscrepancyReport& r, const std::vector<FitParameter>& chain) {
  const HeldOutByChannel base = held_out_by_channel(pr, {});
  const HeldOutByChannel final_model = held_out_by_channel(pr, chain);
  std::size_t at = 0;
  const auto without = [&](RoverSelectionStep& step) {
    const std::size_t k = step.parameters.size();
    std::vector<FitParameter> rest = chain;
    rest.erase(rest.begin() + static_cast<std::ptrdiff_t>(at), rest.begin() + static_cast<std::ptrdiff_t>(at + k));
    const HeldOutByChannel w = r.selection.size() == 1 ? base : held_out_by_channel(pr, rest);
    at += k;
    step.test_without = w.test;
    step.held_out_without = w.held_out;
    step.channel_share = largest_channel_share(base, final_model, w);
    return w.test;
  };
  const auto role = [](RoverSelectionStep& step) {
    // No channel gains materially: the step's share of the whole held-out
    // gain instead (a one-step chain holds all of it; docs/validation/rover-one-effect-issue43.md, A).
    if (std::isnan(step.channel_share)) step.channel_share = step.gain_share;
    const bool at_bound = std::any_of(step.parameters.begin(), step.parameters.end(),
                                      [](const RoverParameterFit& p) { return p.at_bound; });
    return step_role(at_bound, step.channel_share, kNegligibleChannelShare);
  };
  analysis::weigh_steps(r.selection, r.baseline_test, r.final_test, without, role);
}

// The forward selection's hooks (study.h, select_forward): the candidates
// used and the chain's joint fit (`chain`, its parameters; `current`, its
// score); a round is each open candidate screened on its own fork of the
// predictor (the trials), then fit_round.
struct CauseSteps {
  using Trial = rover::Trial;
  Predictor& pr;
  const std::vector<std::unique_ptr<RoverCandidate>>& candidates;
  const RoverResidualFeatures& f;
  const RoverStudyOptions& o;
  RoverDiscrepancyReport& r;
  std::vector<FitParameter>& chain;
  Score& current;
  double ln_n;
  std::vector<std::unique_ptr<Predictor>> forks;  // the round's, one per open candidate
  bool first_round = true;
  std::vector<int> screen_simulations;  // each candidate's screen in the round before (0: not yet screened)

  // Sigmas for the first round's table; the chain's once, at its end.
  RoundSetting setting() const { return {f, chain, current, ln_n, o.min_delta_bic, first_round}; }
  bool open(const std::vector<std::size_t>& /*used*/, std::size_t i) {
    if (candidates[i]->parameters(f).empty()) return false;
    forks[i] = std::make_unique<Predictor>(pr.fork());
    return true;
  }
  // A screen's simulations, as in the round before; in the first round one
  // per parameter and step, and a grid's walk for a grid_screen parameter
  // (the slip angle: 10 simulations in sequence, half a round's screens).
  double expected_cost(std::size_t i) const {
    if (screen_simulations[i] > 0) return screen_simulations[i];
    double cost = 1;
    for (const RoverCandidateParameter& p : candidates[i]->parameters(f)) {
      cost += 1;
      if (p.grid_screen && p.grid > 0) cost += (p.upper - p.lower) / p.grid;
    }
    return cost;
  }
  Trial trial(const std::vector<std::size_t>& /*used*/, std::size_t i) const {
    Trial t;
    screen_trial(*forks[i], *candidates[i], setting(), t);
    return t;
  }
  int best(const std::vector<std::size_t>& open, std::vector<Trial>& trials) {
    for (std::size_t i : open) screen_simulations[i] = trials[i].simulations;
    const int b = fit_round(pr, forks, open, trials, setting());
    forks = std::vector<std::unique_ptr<Predictor>>(candidates.size());
    if (!first_round) return b;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const Trial& t = trials[i];
      if (!t.applies) continue;
      r.candidates.push_back({candidates[i]->name(), candidates[i]->cause(), fits_of(t.fit.parameters, chain.size()),
                              t.fit.score.fit, t.delta_bic, t.fit.score.held_out, t.significant, t.simulations,
                              t.screened});
    }
    return b;
  }
  bool accept(const std::vector<std::size_t>& /*used*/, std::size_t /*i*/, const Trial& /*t*/) const {
    return true;  // fit_round names only a significant trial
  }
  void join(std::vector<std::size_t>& used, std::size_t b, Trial&& t) {
    used.push_back(b);
    first_round = false;
    // The trial fitted the whole chain with the new cause (fit_round): it is the joint refit.
    const FitOutcome& joint = t.fit;
    const std::size_t k = joint.parameters.size() - chain.size();
    const double delta_bic = joint.score.fit - current.fit + static_cast<double>(k) * ln_n;
    chain = joint.parameters;
    current = joint.score;
    r.selection.push_back(
        {candidates[b]->name(), candidates[b]->cause(), fits_of(chain, chain.size() - k), delta_bic, current.held_out});
    if (o.progress && used.size() < static_cast<std::size_t>(o.max_causes))
      o.progress(static_cast<double>(used.size()) / static_cast<double>(o.max_causes + 1));
  }
};

}  // namespace

// Forward selection (issue 13 item 4): each round fits every unused
// candidate jointly with the chain, takes the one with the lowest BIC when it
// improves BIC by more than min_delta_bic and the held-out likelihood rises;
// its joint fit is the new chain. BIC is
// -2 ln L of the study's likelihood (likelihood.h) + k ln n.
void select_causes(Predictor& pr, const RoverResidualFeatures& f, const RoverStudyOptions& o, RoverDiscrepancyReport& r,
                   std::vector<FitParameter>& chain) {
  const auto candidates = rover_candidates();
  const double ln_n = std::log(static_cast<double>(pr.likelihood(Part::fit).effective_count()));
  Score current = score(pr, pr.scenario_effects());  // the nominal model
  r.baseline_bic = current.fit;
  r.baseline_held_out = current.held_out;
  r.baseline_test = current.test;
  const std::size_t max_causes = o.max_causes > 0 ? static_cast<std::size_t>(o.max_causes) : 0;
  if (o.progress && max_causes > 0) o.progress(0.0);
  CauseSteps steps{pr,
                   candidates,
                   f,
                   o,
                   r,
                   chain,
                   current,
                   ln_n,
                   std::vector<std::unique_ptr<Predictor>>(candidates.size()),
                   true,
                   std::vector<int>(candidates.size(), 0)};
  std::vector<std::size_t> used;
  select_forward(steps, candidates.size(), max_causes, used);
  const bool refitted = r.selection.size() > 1;
  drop_absorbed_steps(pr, o, ln_n, r, chain, current);
  if (refitted) set_sigmas(pr, chain, current.fit);
  // Every step's parameters as the final joint refit left them (not as its own round did).
  std::size_t at = 0;
  for (auto& step : r.selection) {
    const std::size_t k = step.parameters.size();
    step.parameters =
        fits_of(std::vector<FitParameter>(chain.begin(), chain.begin() + static_cast<std::ptrdiff_t>(at + k)), at);
    at += k;
  }
  r.final_held_out = current.held_out;
  r.final_test = current.test;
  weigh_steps(pr, r, chain);
}

namespace {

std::string step_text(const RoverSelectionStep& s, bool with_bic) {
  std::string v = s.name + " (";
  for (std::size_t j = 0; j < s.parameters.size(); ++j) {
    const auto& p = s.parameters[j];
    v += (j > 0 ? ", " : "") + p.effect + " = " + format_fitted(p.value, p.sigma, p.unit, p.at_bound);
  }
  char buf[120];
  if (std::isfinite(s.gain_share)) {
    std::snprintf(buf, sizeof buf, "; %.3g %% of the held-out gain, at most %.3g %% of a channel's", 100 * s.gain_share,
                  100 * s.channel_share);
    v += buf;
  }
  return v + (with_bic ? "; delta BIC " + format_delta_bic(s.delta_bic) : "") + ")";
}

// The named causes in order, then the steps of the final model that are not
// causes: too small a share of the held-out gain, or a parameter at its bound.
std::string steps_text(const RoverDiscrepancyReport& r) {
  const StepLists steps = list_steps(
      r.selection, [](const RoverSelectionStep& s) { return step_text(s, s.role == StepRole::cause); }, "; then ",
      true);
  const std::string& named = steps.named;
  const std::string& also = steps.also;
  const std::string& bound = steps.bound;
  const int causes = steps.causes;
  std::string v = causes == 0   ? "No cause named."
                  : causes == 1 ? "Cause: " + named + "."
                                : "Causes, in order: " + named + ".";
  char buf[200];
  if (!also.empty()) {
    std::snprintf(buf, sizeof buf,
                  ": none takes %.3g %% of any channel's held-out gain, so none is named as a cause (the final "
                  "model keeps them).",
                  100 * kNegligibleChannelShare);
    v += " Also consistent with " + also + buf;
  }
  if (!bound.empty()) {
    v += " Not a cause: " + bound +
         ": the fit stopped at a bound of its search, a fact about the search and not about the rover.";
  }
  return v;
}

}  // namespace

void write_verdict(RoverDiscrepancyReport& r) {
  const RoverChannelResiduals* worst = nullptr;
  for (const auto& c : r.channels) {
    if (worst == nullptr || c.rmse / c.sigma > worst->rmse / worst->sigma) worst = &c;
  }
  char buf[600];
  std::string failed;
  for (const auto& c : r.checks) failed += c.consistent ? "" : (failed.empty() ? "" : "; ") + c.name;
  if (worst == nullptr || worst->rmse / worst->sigma < 1.5) {
    // "Agrees" only when the study's own checks hold too.
    r.what_is_wrong = failed.empty() ? "The simulation agrees with every measured channel within its noise."
                                     : "Every measured channel is within the simulation's noise, yet these checks "
                                       "fail: " +
                                           failed + ".";
  } else {
    std::snprintf(
        buf, sizeof buf,
        "The simulation disagrees most on %s/%s: RMSE %.3g %s (%.3g noise sigmas), bias %.3g %s, drift %.3g %s "
        "per 100 s (t = %.3g).",
        worst->stream.c_str(), worst->channel.c_str(), worst->rmse, worst->unit.c_str(), worst->rmse / worst->sigma,
        worst->bias, worst->unit.c_str(), worst->drift, worst->unit.c_str(), worst->t_drift);
    r.what_is_wrong = buf;
  }
  // A stuck rover first: what the channels say about rolling is then little.
  if (r.slip_regime.stuck) {
    r.what_is_wrong = r.slip_regime.text + " The run describes a stuck rover, not a rolling one. " + r.what_is_wrong;
  }
  if (r.selection.empty()) {
    r.verdict = worst != nullptr && worst->rmse / worst->sigma >= 1.5
                    ? "Unexplained: no candidate lowers BIC by more than 10 with a smaller held-out error."
                    : "No cause: no candidate lowers BIC by more than 10 with a smaller held-out error.";
    return;
  }
  std::string v = steps_text(r);
  const double change = 100 * (1 - r.final_held_out / r.baseline_held_out);
  std::snprintf(buf, sizeof buf, " Held-out normalised error %.3g -> %.3g (%.0f %% %s).", r.baseline_held_out,
                r.final_held_out, std::abs(change), change >= 0 ? "lower" : "higher");
  v += buf;
  for (const auto& d : r.dropped) v += " Dropped " + d + ": the causes named after it explain what it did.";
  // A cause that explains the log leaves noise on every channel; a channel
  // still well above it means a cause is missing, and the sigmas above were
  // computed as if the model were complete (seed 104: a force scale 319 sigma
  // off beside an unnamed force offset).
  const RoverChannelResiduals* left = nullptr;
  for (const auto& c : r.channels) {
    if (left == nullptr || c.held_out_sigmas_after > left->held_out_sigmas_after) left = &c;
  }
  r.incomplete = left != nullptr && left->held_out_sigmas_after > kIncompleteSigmas;
  if (r.incomplete) {
    std::snprintf(buf, sizeof buf,
                  " The model is incomplete: the named causes leave %s/%s at %.3g noise sigmas on the test blocks "
                  "(about 1 when the model is right), so a cause is missing and the +-1 sigma above, which assume "
                  "a complete model, are not confidence intervals: the values may be off by many of them.",
                  left->stream.c_str(), left->channel.c_str(), left->held_out_sigmas_after);
    v += buf;
  }
  // A cause that explains the log leaves noise: a residual of a few sigmas means the model is still wrong.
  if (r.final_held_out > 3) {
    std::snprintf(buf, sizeof buf,
                  " The simulation still disagrees by %.3g noise sigmas on the test blocks: the scenario may not be "
                  "this run's model, or the cause is none of the candidates.",
                  r.final_held_out);
    v += buf;
  }
  r.verdict = v;
}

}  // namespace roverlab::analysis::rover

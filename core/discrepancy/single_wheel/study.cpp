#include "core/discrepancy/single_wheel/study.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <limits>
#include <mutex>
#include <numeric>
#include <random>
#include <thread>

#include "core/common/error.h"
#include "core/common/thread_pool.h"
#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/single_wheel/candidates.h"
#include "core/discrepancy/study.h"

namespace roverlab::analysis {

using namespace roverlab::terramechanics;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The study's progress as the share of its fits done, so that the percentage
// follows the work: a fit on all points (started afresh, or a selection step's
// at most 10 iterations) is kFitUnits, a held-out fold's refit (at most 5
// iterations from the fit on all points) one unit, each times the square of
// the candidates fitted together (measured on 300 points: one candidate's
// fits 0.9 s, 0.8 s and 0.32 s on one thread; three candidates' ten times that). Parts run on the pool count their
// fits; only the thread that made the meter reports (a report may throw to cancel).
constexpr double kFitUnits = 3.0;

class WorkMeter {
 public:
  explicit WorkMeter(std::function<void(double)> progress)
      : progress_(std::move(progress)), owner_(std::this_thread::get_id()) {}
  void expect(double units) {
    const std::lock_guard<std::mutex> lock(mutex_);
    total_ += units;
  }
  // `units` more done, and what is still expected at least (the selection's
  // steps are not known in advance: the total grows when a step outgrows it).
  void done(double units = 1.0, double still = 0.0) {
    double fraction = 0.0;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      done_ += units;
      total_ = std::max(total_, done_ + still);
      fraction = std::min(0.99, total_ > 0.0 ? done_ / total_ : 0.0);
      if (std::this_thread::get_id() != owner_) {
        // Work beside the owner's (compare_families) stops when the owner was cancelled.
        if (stopped_) throw DataError("cancelled");
        return;
      }
      if (fraction <= shown_) return;
      shown_ = fraction;
    }
    if (!progress_) return;
    try {
      progress_(fraction);
    } catch (...) {
      const std::lock_guard<std::mutex> lock(mutex_);
      stopped_ = true;
      throw;
    }
  }
  double remaining() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return std::max(0.0, total_ - done_);
  }
  void finish() const {
    if (progress_) progress_(1.0);
  }

 private:
  std::function<void(double)> progress_;
  std::thread::id owner_;
  mutable std::mutex mutex_;
  double total_ = 0.0, done_ = 0.0, shown_ = 0.0;
  bool stopped_ = false;  // the owner's progress threw (cancelled)
};

// RMS residual in the stated measurement sigmas (the fits may weight by others).
double score_of(const std::vector<PointResidual>& residuals, const MeasurementSigma& sigma) {
  double rss = 0.0;
  std::size_t m = 0;
  for (const auto& r : residuals) {
    const double z = (r.predicted - r.measured) / sigma.of(r.quantity);
    if (!std::isfinite(z)) continue;
    rss += z * z;
    ++m;
  }
  return m > 0 ? std::sqrt(rss / static_cast<double>(m)) : NAN;
}

std::string fmt(const char* format, double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, v);
  return buffer;
}

// A value in the unit users read: mm for sinkage.
std::string show(Quantity q, double v) {
  if (q == Quantity::sinkage) return fmt("%.2f", v * 1000.0) + " mm";
  if (q == Quantity::torque) return fmt("%.2f", v) + " N m";
  return fmt("%.2f", v) + " N";
}

std::string words(Quantity q) {
  switch (q) {
    case Quantity::drawbar_pull:
      return "drawbar pull";
    case Quantity::torque:
      return "torque";
    case Quantity::sinkage:
      return "sinkage";
    case Quantity::lateral_force:
      return "lateral force";
  }
  return "?";
}

// BIC with each measured quantity's own residual variance profiled out
// (likelihood.h): sum_q m_q ln(RSS_q / m_q) + k ln m, so that a quantity no
// candidate explains (drawbar pull) cannot set the scale against which
// another quantity's cause (sinkage) is judged. The floor is 1e-6 of the
// quantity's stated measurement sigma (an exact fit is not a -inf).
// Residuals in the stated sigmas: every model in the same unit.
double bic_of(const std::vector<PointResidual>& residuals, std::size_t k, const MeasurementSigma& stated) {
  std::vector<ResidualGroup> groups;
  std::vector<double> z;
  for (Quantity q : kQuantities) {
    ResidualGroup g{words(q), 0, false, 1e-6, false};
    for (const auto& r : residuals) {
      if (r.quantity != q) continue;
      const double v = (r.predicted - r.measured) / stated.of(q);
      if (!std::isfinite(v)) continue;
      z.push_back(v);
      ++g.size;
    }
    if (g.size > 0) groups.push_back(g);
  }
  if (z.empty()) return NAN;
  const GroupedLikelihood l(std::move(groups));
  return l.minus_two_log_l(z) + static_cast<double>(k) * std::log(static_cast<double>(z.size()));
}

// Each quantity's sigma for a fit that starts from a model: its residuals'
// RMS there, never below the stated measurement sigma (the profiled noise
// scale of likelihood.h), so that a quantity the model misses by far does
// not outweigh the others in the fit.
MeasurementSigma profiled_sigma(const std::vector<PointResidual>& residuals, const MeasurementSigma& stated) {
  MeasurementSigma out = stated;
  for (Quantity q : kQuantities) {
    std::vector<double> e;
    for (const auto& r : residuals) {
      if (r.quantity == q && std::isfinite(r.predicted)) e.push_back(r.predicted - r.measured);
    }
    if (e.empty()) continue;
    out.at(q) = std::max(rmse(e), stated.of(q));
  }
  return out;
}

// Quantity q's RMSE among a study's residual statistics; NaN if it has none.
double quantity_rmse(const std::vector<QuantityResiduals>& stats, Quantity q) {
  for (const auto& s : stats) {
    if (s.quantity == q) return s.rmse;
  }
  return NAN;
}

// The family's name in reports.
std::string family_name(ModelKind kind) {
  return kind == ModelKind::rft ? "RFT" : kind == ModelKind::ishigami ? "Ishigami (slip angle)" : "Wong-Reece";
}

// What a family's baseline fits: RFT its material scale zeta (Li et al.
// 2013), the Wong-Reece family nothing (the soil's description).
std::vector<Parameter> family_parameters(ModelKind kind) {
  if (kind == ModelKind::rft) return {Parameter::rft_scale};
  return {};
}

}  // namespace

std::vector<QuantityResiduals> residual_statistics(const std::vector<PointResidual>& residuals,
                                                   const std::vector<WheelTestPoint>& points) {
  std::vector<QuantityResiduals> out;
  for (Quantity q : kQuantities) {
    std::vector<double> e, slip, load, beta;
    for (const auto& r : residuals) {
      if (r.quantity != q || !std::isfinite(r.predicted)) continue;
      e.push_back(r.predicted - r.measured);
      slip.push_back(points[r.point].slip);
      load.push_back(points[r.point].load);
      beta.push_back(points[r.point].slip_angle);
    }
    if (e.empty()) continue;
    QuantityResiduals s;
    s.quantity = q;
    s.count = e.size();
    for (double v : e) s.bias += v;
    s.bias /= static_cast<double>(e.size());
    s.rmse = rmse(e);
    const auto m = static_cast<double>(e.size());
    const double sd = m > 1 ? std::sqrt(std::max(s.rmse * s.rmse - s.bias * s.bias, 0.0) * m / (m - 1)) : 0.0;
    s.t_bias = sd > 0 ? s.bias / (sd / std::sqrt(m)) : 0.0;
    // The single-wheel tables read "no measurable trend" (e.g. no slip angle
    // in the file) as a zero slope with t = 0.
    const auto or_zero = [](double v) { return std::isnan(v) ? 0.0 : v; };
    const Trend ls = regress(slip, e), ll = regress(load, e), lb = regress(beta, e);
    s.slope_vs_slip = or_zero(ls.slope);
    s.t_slip = or_zero(ls.t);
    s.slope_vs_load = or_zero(ll.slope);
    s.t_load = or_zero(ll.t);
    s.slope_vs_slip_angle = or_zero(lb.slope);
    s.t_slip_angle = or_zero(lb.t);
    out.push_back(s);
  }
  return out;
}

namespace {

// A parameter at or within 1 % of a bound of its search (issue 43) is at its
// bound and has no sigma: the search stopped there.
void mark_bounds(terramechanics::IdentificationResult& fit) {
  for (auto& p : fit.parameters) {
    p.at_bound = p.at_bound || near_bound(p.value, p.bounds.lower, p.bounds.upper);
    if (p.at_bound) p.sigma = NAN;
  }
}

bool any_at_bound(const CandidateResult& c) {
  return std::any_of(c.fit.parameters.begin(), c.fit.parameters.end(), [](const auto& p) { return p.at_bound; });
}

// m of the points drawn at random (a fixed seed: the same subset on every
// run), in file order. Not every k-th: a file ordered by slip angle and slip,
// or of rows repeated, would give a stride's few conditions only.
std::vector<WheelTestPoint> random_subset(const std::vector<WheelTestPoint>& points, std::size_t m) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::mt19937_64 rng(46);
  for (std::size_t i = 0; i < m && i + 1 < order.size(); ++i) {  // Fisher-Yates, the first m places
    std::swap(order[i], order[i + rng() % (order.size() - i)]);
  }
  order.resize(std::min(m, order.size()));
  std::sort(order.begin(), order.end());
  std::vector<WheelTestPoint> out;
  out.reserve(order.size());
  for (const std::size_t j : order) out.push_back(points[j]);
  return out;
}

// How SingleWheelStudy::fit_set fits a set (the default: afresh on all points, held out).
struct FitHow {
  const CandidateResult* start_from = nullptr;      // a previous fit: its soil, extensions and weights
  bool with_held_out = true;                        // false: judged by its BIC alone (a step's trial)
  const IdentificationResult* resume = nullptr;     // where a trial on the same objective stopped
  const std::vector<WheelTestPoint>* on = nullptr;  // a trial on the step screen's subset
  bool unless_at_bound = false;  // no held-out folds when a parameter ends at its bound: such a step cannot pass
};

// The study's steps: the baseline's residuals, each candidate's fit and
// held-out score, the winner, and the sentences on what is wrong and why.
class SingleWheelStudy {
 public:
  SingleWheelStudy(const Soil& soil, const std::vector<WheelTestPoint>& points, const DiscrepancyOptions& options,
                   WorkMeter& meter)
      : soil_(soil), points_(points), o_(options), meter_(meter) {}
  DiscrepancyReport run();

 private:
  void find_quantities();
  void score_baseline();
  CandidateResult named_set(const std::vector<const SingleWheelCandidate*>& set) const;
  CandidateResult fit_set(const std::vector<const SingleWheelCandidate*>& set, const FitHow& how = FitHow{}) const;
  void select_forward();
  struct Steps;  // select_forward's hooks (study.h)
  // The best partner of a weak first step, by BIC.
  int best_partner(int first, CandidateResult& pair_fit) const;
  std::vector<PointResidual> held_out(const IdentificationOptions& io, const IdentificationResult& fit,
                                      const std::vector<const SingleWheelCandidate*>& set) const;
  void choose_best();
  void write_what_is_wrong();
  void find_partial();
  void weigh_steps();
  void write_verdict();
  void judge_quantities();
  void score_per_wheel();
  std::string wheel_name(const WheelTestPoint& p) const;
  void write_no_significant_verdict();
  void write_chain_verdict();
  std::string cause_sentence(const std::string& lead, const CandidateResult& c, const std::string& end) const;
  bool held_out_gain(const std::vector<double>& rmse, const std::vector<double>& than) const;
  std::size_t fold_count() const {
    const std::size_t n = points_.size();
    return n <= o_.max_leave_one_out_points ? n : n <= o_.large_points ? o_.folds : std::min(o_.folds, o_.large_folds);
  }
  void assign_folds();
  // The fits of a set fitted with its held-out score: two on all points, one per fold.
  double held_out_fits(std::size_t together = 1) const {
    return units(together) * (2.0 * kFitUnits + (o_.leave_one_out ? static_cast<double>(folds_) : 0.0));
  }
  static double units(std::size_t together) { return static_cast<double>(together * together); }
  // A set not fitted: its share of the work done at once.
  CandidateResult not_applicable(CandidateResult c, bool with_held_out) const {
    meter_.done(with_held_out ? held_out_fits() : kFitUnits * units(1));
    return c;
  }

  const Soil& soil_;
  const std::vector<WheelTestPoint>& points_;
  const DiscrepancyOptions& o_;
  WorkMeter& meter_;
  MeasurementSigma weights_;  // the fits' per-quantity sigmas: the baseline's profiled scales
  bool any_grousers_ = false;
  std::vector<std::unique_ptr<SingleWheelCandidate>> candidates_;
  DiscrepancyReport report_;
  std::vector<std::size_t> fold_of_;  // held-out fold of each point
  std::size_t folds_ = 0;
  // The step screen's subset (DiscrepancyOptions::step_screen_points); empty: no screen.
  std::vector<WheelTestPoint> step_screen_;
};

// A candidate fitted and held out needs a few points, at two slips at least:
// with one slip no trend with slip exists and the extensions cannot be told
// apart.
void check_points_can_tell_candidates_apart(const std::vector<WheelTestPoint>& points) {
  constexpr std::size_t kMinimum = 4;
  if (points.size() < kMinimum) {
    throw DataError("a discrepancy study needs at least " + std::to_string(kMinimum) +
                    " points, to fit a candidate and hold points out (the file has " + std::to_string(points.size()) +
                    ")");
  }
  // Points at a slip angle (or with a lateral force) are predicted by the
  // slip-angle model (study_single_wheel sets it): two slip angles 1 deg
  // apart tell the candidates apart as well as two slips do.
  const auto [lo, hi] =
      std::minmax_element(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.slip < b.slip; });
  const auto [blo, bhi] = std::minmax_element(points.begin(), points.end(),
                                              [](const auto& a, const auto& b) { return a.slip_angle < b.slip_angle; });
  if (hi->slip - lo->slip < 0.01 && bhi->slip_angle - blo->slip_angle < kPi / 180.0) {
    throw DataError("every point is at slip " + fmt("%.3g", lo->slip) +
                    "; a discrepancy study needs points at two slips at least, 0.01 apart (or at two slip angles)");
  }
}

DiscrepancyReport SingleWheelStudy::run() {
  if (points_.empty()) throw DataError("no single-wheel points");
  report_.points = points_.size();
  report_.baseline_model = family_name(o_.baseline.kind);  // its points checked by run_in_family
  assign_folds();
  find_quantities();
  score_baseline();
  any_grousers_ = std::any_of(points_.begin(), points_.end(),
                              [](const auto& p) { return p.wheel.grouser_count > 0 && p.wheel.grouser_height > 0.0; });
  candidates_ = single_wheel_candidates();
  // The screen: each candidate fitted alone, in parallel (core/common/thread_pool.h).
  // Its fits, and half a step of the selection (its steps are known only as it goes:
  // the total grows with each step begun).
  const auto n = static_cast<double>(candidates_.size());
  meter_.expect(n * held_out_fits() + 0.5 * (n - 1.0) * kFitUnits * units(2));
  for (auto& c : screen_candidates<CandidateResult>(candidates_.size(),
                                                    [&](std::size_t i) { return fit_set({candidates_[i].get()}); }))
    report_.candidates.push_back(std::move(c));
  choose_best();
  if (o_.step_screen_points > 0 && points_.size() > o_.step_screen_points)
    step_screen_ = random_subset(points_, o_.step_screen_points);
  report_.step_screen_points = step_screen_.size();
  report_.selection.reserve(candidates_.size());  // select_forward keeps pointers into it
  select_forward();
  weigh_steps();
  report_.significant = std::any_of(report_.selection.begin(), report_.selection.end(),
                                    [](const CandidateResult& c) { return c.role == StepRole::cause; });
  write_what_is_wrong();
  find_partial();
  write_verdict();
  judge_quantities();
  score_per_wheel();
  return std::move(report_);
}

// The held-out folds: point j in fold j mod folds, or one fold per wheel
// label or per slip value (grouped: a wheel or a slip the fit never saw).
void SingleWheelStudy::assign_folds() {
  const std::size_t n = points_.size();
  fold_of_.assign(n, 0);
  if (!o_.leave_one_out) {
    report_.held_out_method = "in-sample";
    return;
  }
  if (o_.hold_out == HoldOut::points) {
    folds_ = fold_count();
    for (std::size_t j = 0; j < n; ++j) fold_of_[j] = j % folds_;
    report_.held_out_method = n <= o_.max_leave_one_out_points ? "leave-one-out" : std::to_string(folds_) + "-fold";
    return;
  }
  const bool by_wheel = o_.hold_out == HoldOut::wheel;
  std::vector<std::string> keys;
  for (std::size_t j = 0; j < n; ++j) {
    const auto& w = points_[j].wheel;  // a wheel: its label and its geometry
    const std::string key = by_wheel ? points_[j].wheel_label + fmt("|%.6g", w.radius) + fmt("|%.6g", w.width) +
                                           fmt("|%.6g", w.grouser_count * w.grouser_height)
                                     : fmt("%.6g", points_[j].slip);
    auto at = std::find(keys.begin(), keys.end(), key);
    if (at == keys.end()) at = keys.insert(keys.end(), key);
    fold_of_[j] = static_cast<std::size_t>(at - keys.begin());
  }
  folds_ = keys.size();
  if (folds_ < 2) {
    throw DataError(std::string("holding out by ") + (by_wheel ? "wheel needs two wheels" : "slip needs two slips") +
                    " at least (the points have one)");
  }
  report_.held_out_method = by_wheel ? "leave-one-wheel-out" : "leave-one-slip-out";
}

std::string SingleWheelStudy::wheel_name(const WheelTestPoint& p) const {
  if (!p.wheel_label.empty()) return p.wheel_label;
  return "r " + fmt("%.4g", p.wheel.radius) + " m, b " + fmt("%.4g", p.wheel.width) + " m" +
         (p.wheel.grouser_count > 0 ? ", " + std::to_string(p.wheel.grouser_count) + " grousers" : std::string());
}

// Per wheel and quantity: the baseline's RMSE and the final model's held-out
// RMSE (the figures a wheel's own reference model is compared with).
void SingleWheelStudy::score_per_wheel() {
  IdentificationOptions base;
  base.model = o_.baseline;
  base.sigma = o_.sigma;
  const std::vector<PointResidual> baseline = identify_soil(soil_, points_, base).residuals;
  const bool chain = !report_.selection.empty() && !report_.selection.back().held_out.empty();
  report_.final_model = chain ? report_.selection.back().name : "baseline";
  const std::vector<PointResidual>& model = chain ? report_.selection.back().held_out : baseline;
  std::vector<std::string> wheels;
  for (const auto& p : points_) {
    if (std::find(wheels.begin(), wheels.end(), wheel_name(p)) == wheels.end()) wheels.push_back(wheel_name(p));
  }
  const auto wheel_rmse = [&](const std::vector<PointResidual>& rs, const std::string& wheel, Quantity q,
                              std::size_t& n) {
    std::vector<double> e;
    for (const auto& r : rs) {
      if (r.quantity == q && std::isfinite(r.predicted) && wheel_name(points_[r.point]) == wheel)
        e.push_back(r.predicted - r.measured);
    }
    n = e.size();
    return rmse(e);
  };
  for (const auto& wheel : wheels) {
    for (Quantity q : report_.quantities) {
      WheelHeldOut w;
      w.wheel = wheel;
      w.quantity = q;
      w.baseline_rmse = wheel_rmse(baseline, wheel, q, w.count);
      std::size_t m = 0;
      w.model_rmse = wheel_rmse(model, wheel, q, m);
      if (w.count > 0) report_.per_wheel.push_back(w);
    }
  }
}

void SingleWheelStudy::find_quantities() {
  for (Quantity q : kQuantities) {
    if (std::any_of(points_.begin(), points_.end(), [&](const auto& p) { return p.measured(q).has_value(); })) {
      report_.quantities.push_back(q);
    }
  }
  if (report_.quantities.empty()) throw DataError("no measured drawbar pull, torque, sinkage or lateral force");
}

void SingleWheelStudy::score_baseline() {
  IdentificationOptions base;
  base.model = o_.baseline;
  base.sigma = o_.sigma;
  const IdentificationResult baseline = identify_soil(soil_, points_, base);  // nothing free: predictions
  report_.baseline = residual_statistics(baseline.residuals, points_);
  report_.baseline_score = score_of(baseline.residuals, o_.sigma);
  report_.baseline_bic = bic_of(baseline.residuals, family_parameters(o_.baseline.kind).size(), o_.sigma);
  weights_ = profiled_sigma(baseline.residuals, o_.sigma);
  report_.measurements = baseline.measurements;
  for (const auto& r : baseline.residuals) report_.unsupported += std::isfinite(r.predicted) ? 0 : 1;
  for (Quantity q : report_.quantities) report_.baseline_held_out_rmse.push_back(quantity_rmse(report_.baseline, q));
}

// The set's name and cause, and whether it applies to the data and family.
CandidateResult SingleWheelStudy::named_set(const std::vector<const SingleWheelCandidate*>& set) const {
  CandidateResult c;
  for (const auto* candidate : set) {
    c.name += (c.name.empty() ? "" : " + ") + std::string(candidate->name());
    c.cause += (c.cause.empty() ? "" : "; ") + std::string(candidate->cause());
    if (!c.applicable) continue;
    if (candidate->needs_grousers() && !any_grousers_) {
      c.not_applicable_because = "no wheel in the data has grousers (columns grouser_count and grouser_height_m)";
    } else if (!candidate->belongs_to(o_.baseline.kind)) {
      c.not_applicable_because = "not an extension of the " + family_name(o_.baseline.kind) + " family";
    } else if (candidate->needs_lateral_force() && !has_lateral_force(o_.baseline.kind)) {
      c.not_applicable_because = "no point has a slip angle or a measured lateral force";
    }
    c.applicable = c.not_applicable_because.empty();
  }
  return c;
}

// Fits the candidates' parameters together on all points (started from
// `start`, a previous fit's soil and extensions, when given), then scores the
// extended model on held-out points.
CandidateResult SingleWheelStudy::fit_set(const std::vector<const SingleWheelCandidate*>& set,
                                          const FitHow& how) const {
  const CandidateResult* start_from = how.start_from;
  const bool with_held_out = how.with_held_out;
  CandidateResult c = named_set(set);
  if (!c.applicable) return not_applicable(std::move(c), with_held_out);
  IdentificationOptions io;
  io.model = o_.baseline;
  io.free = family_parameters(o_.baseline.kind);  // refitted with every candidate (RFT: its material scale)
  io.sigma = start_from != nullptr ? profiled_sigma(start_from->fit.residuals, o_.sigma) : weights_;
  Soil start = soil_;
  if (start_from != nullptr) {
    start = start_from->fit.soil;
    io.model.extensions = start_from->fit.extensions;
  }
  for (const auto* candidate : set) {
    candidate->configure(io.model.extensions);
    for (const auto& entry : candidate->parameters()) {
      const Parameter parameter = entry.first;
      const double value = entry.second;
      if (std::find(io.free.begin(), io.free.end(), parameter) != io.free.end()) continue;
      io.free.push_back(parameter);
      const bool fitted_before =
          start_from != nullptr && std::any_of(start_from->fit.parameters.begin(), start_from->fit.parameters.end(),
                                               [&](const auto& e) { return e.parameter == parameter; });
      if (value >= 0.0 && !fitted_before) set_parameter(start, io.model.extensions, parameter, value);
    }
  }
  if (how.resume != nullptr) {
    // The same objective (start_from's weights) as the trial that stopped at
    // `resume`: its fit goes on from there instead of starting again.
    start = how.resume->soil;
    io.model.extensions = how.resume->extensions;
  }
  // A step of forward selection is first judged by its BIC alone: at most
  // 10 steps, no covariance; the step that passes is fitted again in full.
  if (!with_held_out) {
    io.max_iterations = 10;
    io.covariance = false;
  }
  // A trial on the step screen's subset (`on`, without its held-out score):
  // its BIC ranks it among the step's trials and nothing else.
  const std::vector<WheelTestPoint>& points = how.on != nullptr && !with_held_out ? *how.on : points_;
  c.fit = identify_soil(start, points, io);
  meter_.done(kFitUnits * units(set.size()) * static_cast<double>(points.size()) / static_cast<double>(points_.size()));
  if (&points != &points_) {
    c.bic = bic_of(c.fit.residuals, io.free.size(), o_.sigma);
    return c;
  }
  if (with_held_out) {
    // Second pass at the solution's own per-quantity scales (the profile
    // likelihood's weights there): its sigmas are in the right units.
    io.sigma = profiled_sigma(c.fit.residuals, o_.sigma);
    io.model.extensions = c.fit.extensions;
    c.fit = identify_soil(c.fit.soil, points_, io);
    meter_.done(kFitUnits * units(set.size()));
  }
  mark_bounds(c.fit);
  c.in_sample = residual_statistics(c.fit.residuals, points_);
  c.bic = bic_of(c.fit.residuals, io.free.size(), o_.sigma);
  c.delta_bic = c.bic - report_.baseline_bic;
  // held_out_rmse empty: no held-out test passes
  if (!with_held_out || (how.unless_at_bound && any_at_bound(c))) return c;
  const std::vector<PointResidual> predicted = o_.leave_one_out ? held_out(io, c.fit, set) : c.fit.residuals;
  const auto held_stats = residual_statistics(predicted, points_);
  for (Quantity q : report_.quantities) c.held_out_rmse.push_back(quantity_rmse(held_stats, q));
  c.held_out_score = score_of(predicted, o_.sigma);
  c.held_out = predicted;
  return c;
}

int SingleWheelStudy::best_partner(int first, CandidateResult& pair_fit) const {
  const auto best = static_cast<std::size_t>(first);
  int partner = -1;
  std::vector<std::size_t> partners;
  for (std::size_t i = 0; i < candidates_.size(); ++i) {
    if (i != best && report_.candidates[i].applicable) partners.push_back(i);
  }
  // The pairs fitted in parallel, then compared in candidate order.
  std::vector<CandidateResult> pair_fits(partners.size());
  shared_thread_pool().for_each_index(partners.size(), [&](std::size_t k) {
    pair_fits[k] =
        fit_set({candidates_[best].get(), candidates_[partners[k]].get()}, FitHow{&report_.candidates[best], false});
  });
  for (std::size_t k = 0; k < partners.size(); ++k) {
    if (partner < 0 || pair_fits[k].bic < pair_fit.bic) {
      partner = static_cast<int>(partners[k]);
      pair_fit = std::move(pair_fits[k]);
    }
  }
  return partner;
}

// Several causes at once (study.h, select_forward): the candidate with the
// best BIC first, then each of the others refitted on top of the chain; a
// step is kept while it lowers BIC by more than the threshold and the
// held-out error falls. A first step too weak alone is kept when it and the
// best second step together pass against the baseline (two causes that
// hide each other). Steps are fitted without their held-out scores (ten
// refits each), which are computed only for the step whose BIC passes.
struct SingleWheelStudy::Steps {
  using Trial = CandidateResult;
  SingleWheelStudy& s;
  const CandidateResult* at = nullptr;  // the chain's fit
  double bic;
  const std::vector<double>* held_rmse;
  int partner = -1;                                 // a weak first step's partner, joining with it
  const std::vector<std::size_t>* chain = nullptr;  // select_forward's chain

  std::vector<const SingleWheelCandidate*> set(const std::vector<std::size_t>& chain, std::size_t i) const {
    std::vector<const SingleWheelCandidate*> out;
    out.reserve(chain.size() + 1);
    for (std::size_t j : chain) out.push_back(s.candidates_[j].get());
    out.push_back(s.candidates_[i].get());
    return out;
  }
  bool passes(const CandidateResult& c, double than_bic) const {
    return c.applicable && std::isfinite(c.bic) && c.bic - than_bic < s.o_.bic_threshold && !any_at_bound(c) &&
           s.held_out_gain(c.held_out_rmse, *held_rmse);
  }
  // A trial whose BIC passes, fitted on (from where it stopped) and held
  // out; a chain's step (`step`) not when it ends at a bound (it cannot pass).
  void with_held_out(CandidateResult& fit, const std::vector<const SingleWheelCandidate*>& set,
                     const CandidateResult* from, bool step) const {
    if (fit.held_out_rmse.empty() && fit.applicable && std::isfinite(fit.bic) && fit.bic - bic < s.o_.bic_threshold)
      fit = s.fit_set(set, FitHow{from, true, from != nullptr ? &fit.fit : nullptr, nullptr, step});
  }
  bool open(const std::vector<std::size_t>& /*chain*/, std::size_t i) const {
    return s.report_.candidates[i].applicable;
  }
  CandidateResult trial(const std::vector<std::size_t>& chain, std::size_t i) const {
    if (chain.empty()) return s.report_.candidates[i];
    return s.fit_set(set(chain, i), FitHow{at, false, nullptr, s.step_screen_.empty() ? nullptr : &s.step_screen_});
  }
  int best(const std::vector<std::size_t>& open, std::vector<CandidateResult>& trials) const;
  bool accept(const std::vector<std::size_t>& chain, std::size_t best, CandidateResult& fit);
  void join(std::vector<std::size_t>& chain, std::size_t i, CandidateResult&& fit) {
    if (partner >= 0) {
      chain = {i, static_cast<std::size_t>(partner)};
      partner = -1;
    } else {
      chain.push_back(i);
    }
    bic = fit.bic;
    s.report_.selection.push_back(std::move(fit));
    at = &s.report_.selection.back();
    held_rmse = &at->held_out_rmse;
  }
};

// The lowest BIC. With the step screen (trials on its subset), the
// `step_screen_keep` best there are fitted again on all points, from where
// their trials stopped, and the lowest BIC among them on all points is taken.
int SingleWheelStudy::Steps::best(const std::vector<std::size_t>& open, std::vector<CandidateResult>& trials) const {
  const auto lower_bic = [](const CandidateResult& a, const CandidateResult& b) { return a.bic < b.bic; };
  if (chain->empty() || s.step_screen_.empty()) return best_trial(open, trials, lower_bic);
  std::vector<std::size_t> ranked;
  for (std::size_t i : open) {
    if (trials[i].applicable && std::isfinite(trials[i].bic)) ranked.push_back(i);
  }
  std::stable_sort(ranked.begin(), ranked.end(),
                   [&](std::size_t a, std::size_t b) { return lower_bic(trials[a], trials[b]); });
  ranked.resize(std::min(ranked.size(), std::max<std::size_t>(s.o_.step_screen_keep, 1)));
  std::sort(ranked.begin(), ranked.end());  // candidate order, as without the screen
  shared_thread_pool().for_each_index(ranked.size(), [&](std::size_t k) {
    CandidateResult& t = trials[ranked[k]];
    t = s.fit_set(set(*chain, ranked[k]), FitHow{at, false, &t.fit});
  });
  return best_trial(ranked, trials, lower_bic);
}

bool SingleWheelStudy::Steps::accept(const std::vector<std::size_t>& chain, std::size_t best, CandidateResult& fit) {
  // The step's fits still to come: the partner search's, the next step's.
  const auto open = static_cast<double>(std::count_if(s.report_.candidates.begin(), s.report_.candidates.end(),
                                                      [](const CandidateResult& c) { return c.applicable; }));
  s.meter_.done(0.0,
                std::max(0.0, open - static_cast<double>(chain.size()) - 1.0) * kFitUnits * units(chain.size() + 2) +
                    s.held_out_fits(chain.size() + 1));
  with_held_out(fit, set(chain, best), at, !chain.empty());
  if (passes(fit, bic)) return true;
  if (!chain.empty()) return false;
  // Look one step further: the weak first step with its best partner.
  CandidateResult pair_fit;
  const int found = s.best_partner(static_cast<int>(best), pair_fit);
  if (found >= 0)
    with_held_out(pair_fit, {s.candidates_[best].get(), s.candidates_[static_cast<std::size_t>(found)].get()},
                  &s.report_.candidates[best], false);  // reported: held out even at a bound
  s.report_.best_pair = pair_fit;
  if (found < 0 || !passes(pair_fit, bic)) return false;
  partner = found;
  fit = std::move(pair_fit);
  return true;
}

void SingleWheelStudy::select_forward() {
  std::vector<std::size_t> chain;
  Steps steps{*this, nullptr, report_.baseline_bic, &report_.baseline_held_out_rmse, -1, &chain};
  analysis::select_forward(steps, candidates_.size(), candidates_.size(), chain);
}

// The held-out test of a step, per quantity (a quantity no candidate
// explains must not hide another's cause): some quantity's held-out RMSE
// falls by min_held_out_gain at least, and the held-out likelihood with a
// noise scale per quantity, sum_q m_q ln(RMSE_q^2), falls.
bool SingleWheelStudy::held_out_gain(const std::vector<double>& rmse, const std::vector<double>& than) const {
  bool one_falls = false;
  double log_ratio = 0;
  for (std::size_t i = 0; i < report_.quantities.size() && i < rmse.size() && i < than.size(); ++i) {
    if (!std::isfinite(rmse[i]) || !std::isfinite(than[i]) || !(than[i] > 0) || !(rmse[i] > 0)) continue;
    one_falls = one_falls || rmse[i] < (1.0 - o_.min_held_out_gain) * than[i];
    double m = 0;
    for (const auto& s : report_.baseline) m += s.quantity == report_.quantities[i] ? static_cast<double>(s.count) : 0;
    log_ratio += m * std::log(rmse[i] * rmse[i] / (than[i] * than[i]));
  }
  return one_falls && log_ratio < 0;
}

// Held out: refit without each fold of points (one point each up to
// max_leave_one_out_points), predict the fold.
std::vector<PointResidual> SingleWheelStudy::held_out(const IdentificationOptions& io, const IdentificationResult& fit,
                                                      const std::vector<const SingleWheelCandidate*>& set) const {
  const std::size_t n = points_.size();
  const std::size_t folds = folds_;
  std::vector<PointResidual> out;
  IdentificationOptions refit = io;
  refit.model.extensions = fit.extensions;
  refit.covariance = false;
  refit.tolerance = 1e-6;  // started at the fit on all points: a few steps away
  // ... or a long way along a valley the data hardly determine, where further
  // steps barely change the held-out predictions: at most 5 steps.
  refit.max_iterations = 5;
  Soil from = fit.soil;
  if (o_.hold_out != HoldOut::points) {
    // A wheel or a slip the fit never saw: each fold is fitted afresh from the
    // nominal soil and the candidates' start values, so that a parameter the
    // other folds cannot determine (grousers without a grousered wheel) does
    // not keep the value the held-out fold gave it.
    from = soil_;
    refit.model.extensions = o_.baseline.extensions;
    for (const auto* candidate : set) {
      candidate->configure(refit.model.extensions);
      for (const auto& [parameter, value] : candidate->parameters()) {
        if (value >= 0.0) set_parameter(from, refit.model.extensions, parameter, value);
      }
    }
    refit.tolerance = io.tolerance;
    refit.max_iterations = 100;
  }
  // The folds refitted in parallel, their residuals joined in fold order.
  std::vector<std::vector<PointResidual>> per_fold(folds);
  shared_thread_pool().for_each_index(folds, [&](std::size_t fold) {
    std::vector<WheelTestPoint> train, test;
    std::vector<std::size_t> test_index;
    train.reserve(n);
    for (std::size_t j = 0; j < n; ++j) {
      if (fold_of_[j] == fold) {
        test.push_back(points_[j]);
        test_index.push_back(j);
      } else {
        train.push_back(points_[j]);
      }
    }
    const IdentificationResult f = identify_soil(from, train, refit);
    meter_.done(units(set.size()));
    IdentificationOptions predict_only;
    predict_only.model = refit.model;
    predict_only.model.extensions = f.extensions;
    predict_only.sigma = o_.sigma;
    const IdentificationResult pred = identify_soil(f.soil, test, predict_only);
    for (auto r : pred.residuals) {
      r.point = test_index[r.point];
      per_fold[fold].push_back(r);
    }
  });
  for (const auto& f : per_fold) out.insert(out.end(), f.begin(), f.end());
  return out;
}

// The winner: lowest BIC among applicable candidates; significant when its
// BIC gain and its held-out gain are both large enough.
void SingleWheelStudy::choose_best() {
  double best_bic = INFINITY;
  for (std::size_t i = 0; i < report_.candidates.size(); ++i) {
    const auto& c = report_.candidates[i];
    if (!c.applicable || !std::isfinite(c.bic)) continue;
    if (c.bic < best_bic) {
      best_bic = c.bic;
      report_.best = static_cast<int>(i);
    }
  }
  if (report_.best >= 0) {
    const auto& c = report_.candidates[static_cast<std::size_t>(report_.best)];
    report_.significant = c.delta_bic < o_.bic_threshold && !any_at_bound(c) &&
                          held_out_gain(c.held_out_rmse, report_.baseline_held_out_rmse);
  }
}

// What the baseline gets wrong, in one sentence.
void SingleWheelStudy::write_what_is_wrong() {
  const QuantityResiduals* worst = nullptr;
  for (const auto& s : report_.baseline) {
    if (worst == nullptr || s.rmse / o_.sigma.of(s.quantity) > worst->rmse / o_.sigma.of(worst->quantity)) {
      worst = &s;
    }
  }
  if (report_.baseline_score <= 1.5) {
    report_.what_is_wrong = "The baseline " + report_.baseline_model +
                            " model fits every measured quantity within about its measurement error (RMS " +
                            fmt("%.2f", report_.baseline_score) + " sigma).";
    return;
  }
  std::string s = "The baseline " + report_.baseline_model + " model " +
                  std::string(worst->bias > 0 ? "over-predicts " : "under-predicts ") + words(worst->quantity) +
                  " by " + show(worst->quantity, std::abs(worst->bias)) + " on average (RMSE " +
                  show(worst->quantity, worst->rmse) + ")";
  if (std::abs(worst->t_slip) >= 3.0) {
    s += ", and the error " + std::string(worst->slope_vs_slip * worst->bias > 0 ? "grows" : "changes") +
         " with slip (" + (worst->slope_vs_slip > 0 ? "+" : "-") +
         show(worst->quantity, std::abs(worst->slope_vs_slip)) + " per unit slip)";
  } else if (std::abs(worst->t_slip_angle) >= 3.0) {
    s += ", and the error changes with slip angle (" + std::string(worst->slope_vs_slip_angle > 0 ? "+" : "-") +
         show(worst->quantity, std::abs(worst->slope_vs_slip_angle) * kPi / 18.0) + " per 10 deg)";
  } else if (std::abs(worst->t_load) >= 3.0) {
    s += ", and the error changes with load (" + std::string(worst->slope_vs_load > 0 ? "+" : "-") +
         show(worst->quantity, std::abs(worst->slope_vs_load) * 100.0) + " per 100 N)";
  }
  // Other quantities with a strong slip trend (|t| >= 5) are named too.
  for (const auto& o : report_.baseline) {
    if (&o == worst || std::abs(o.t_slip) < 5.0) continue;
    s += "; its " + words(o.quantity) + " error trends with slip (" + (o.slope_vs_slip > 0 ? "+" : "-") +
         show(o.quantity, std::abs(o.slope_vs_slip)) + " per unit slip, t = " + fmt("%.1f", o.t_slip) +
         (o.slope_vs_slip < 0 ? ": measured " + words(o.quantity) + " grows faster with slip than predicted"
                              : ": predicted " + words(o.quantity) + " grows faster with slip than measured") +
         ")";
  }
  report_.what_is_wrong = s + ".";
}

// Per quantity: the candidate that best predicts it on held-out points, when
// it cuts that quantity's held-out RMSE by at least 30 %.
void SingleWheelStudy::find_partial() {
  for (std::size_t qi = 0; qi < report_.quantities.size(); ++qi) {
    int best_q = -1;
    for (std::size_t i = 0; i < report_.candidates.size(); ++i) {
      const auto& c = report_.candidates[i];
      if (!c.applicable || !std::isfinite(c.held_out_rmse[qi])) continue;
      if (best_q < 0 || c.held_out_rmse[qi] < report_.candidates[static_cast<std::size_t>(best_q)].held_out_rmse[qi]) {
        best_q = static_cast<int>(i);
      }
    }
    if (best_q >= 0 && report_.candidates[static_cast<std::size_t>(best_q)].held_out_rmse[qi] <
                           0.7 * report_.baseline_held_out_rmse[qi]) {
      report_.partial.emplace_back(report_.quantities[qi], best_q);
    }
  }
}

// Each step's share of the chain's held-out gain and whether it is named
// (issue 43): a step under kNegligibleGainShare of the gain, or that cuts no
// quantity's held-out RMSE by 30 % against the step before (the per-quantity
// sentences would say nothing explains it), is "also consistent with".
void SingleWheelStudy::weigh_steps() {
  if (report_.selection.empty()) return;
  double before = report_.baseline_score;
  const std::vector<double>* rmse_before = &report_.baseline_held_out_rmse;
  const double final_score = report_.selection.back().held_out_score;
  const auto without = [&](const CandidateResult& step) {
    const double w = without_step(final_score, before, step.held_out_score);
    before = step.held_out_score;
    return w;
  };
  const auto role = [&](const CandidateResult& step) {
    bool cuts = false;
    for (std::size_t qi = 0; qi < report_.quantities.size() && qi < step.held_out_rmse.size(); ++qi)
      cuts = cuts || step.held_out_rmse[qi] <= 0.7 * (*rmse_before)[qi];
    rmse_before = &step.held_out_rmse;
    return step_role(any_at_bound(step), step.gain_share, kNegligibleGainShare, cuts);
  };
  analysis::weigh_steps(report_.selection, report_.baseline_score, final_score, without, role);
}

void SingleWheelStudy::write_verdict() {
  if (report_.best < 0) {
    report_.verdict = "No candidate could be fitted.";
    return;
  }
  if (report_.selection.empty()) {
    write_no_significant_verdict();
    return;
  }
  write_chain_verdict();
}

// The named cause(s), fitted parameters, held-out gain and BIC change, in words.
std::string SingleWheelStudy::cause_sentence(const std::string& lead, const CandidateResult& c,
                                             const std::string& end) const {
  std::string v = lead + c.name + " (" + c.cause + "),";
  for (const auto& p : c.fit.parameters) {
    v += " " + std::string(to_string(p.parameter)) + " = " + fmt("%.3g", p.value) +
         (p.at_bound               ? std::string(" (at its bound)")
          : std::isfinite(p.sigma) ? " +- " + fmt("%.2g", p.sigma)
                                   : std::string(" (no sigma)")) +
         ";";
  }
  v += " held-out RMSE";
  for (std::size_t i = 0; i < report_.quantities.size(); ++i) {
    v += std::string(i ? "," : "") + " " + words(report_.quantities[i]) + " " +
         show(report_.quantities[i], report_.baseline_held_out_rmse[i]) + " -> " +
         show(report_.quantities[i], c.held_out_rmse[i]);
  }
  return v + "; delta BIC " + format_delta_bic(c.delta_bic) + end;
}

// The named steps with their shares; the final joint fit's values and gain
// (the model every figure is of); the steps only consistent with the data.
void SingleWheelStudy::write_chain_verdict() {
  const StepLists steps = list_steps(
      report_.selection,
      [](const CandidateResult& step) {
        return step_share_text(step.name, step.gain_share) +
               (step.role == StepRole::at_bound ? ", a parameter at its bound" : "");
      },
      ", then ");
  const std::string& named = steps.named;
  const std::string& also = steps.also;
  const int causes = steps.causes;
  const bool chain = report_.selection.size() >= 2 || report_.selection.back().name.find(" + ") != std::string::npos;
  const std::string lead = causes == 0   ? "No cause named; the model fitted is "
                           : causes == 1 ? "Cause: " + named + "; the model fitted is "
                                         : "Causes (forward selection): " + named + "; the model fitted is ";
  report_.verdict = cause_sentence(lead, report_.selection.back(), chain ? " against the baseline." : ".");
  if (also.empty()) return;
  report_.verdict += " Also consistent with " + also + ": under " + fmt("%.3g", 100.0 * kNegligibleGainShare) +
                     " % of the held-out gain, or no quantity's held-out RMSE cut by 30 %, so not named as a cause.";
}

// Per quantity: significant when |t| >= 3 for the baseline's bias or either
// trend it prints; explained by the selection step that cut its held-out
// RMSE by 30 % or more. Appended to the verdict, which therefore never
// calls "not significant" a quantity whose printed t says otherwise.
void SingleWheelStudy::judge_quantities() {
  std::string all;
  for (std::size_t qi = 0; qi < report_.quantities.size(); ++qi) {
    const Quantity q = report_.quantities[qi];
    QuantityVerdict v;
    v.quantity = q;
    v.held_out_before = report_.baseline_held_out_rmse[qi];
    std::string why;
    for (const auto& b : report_.baseline) {
      if (b.quantity != q) continue;
      const std::pair<const char*, double> ts[] = {
          {"bias", b.t_bias}, {"slip trend", b.t_slip}, {"load trend", b.t_load}, {"slip-angle trend", b.t_slip_angle}};
      for (const auto& [name, t] : ts) {
        if (std::abs(t) < 3.0) continue;
        v.significant = true;
        why += std::string(why.empty() ? "" : ", ") + name + " t = " + fmt("%.1f", t);
      }
    }
    double before = v.held_out_before;
    for (const auto& step : report_.selection) {  // each step's gain on this quantity
      const double after = step.held_out_rmse[qi];
      if (after <= 0.7 * before && v.explained_by.empty()) {
        v.explained_by = last_link(step.name);
        v.explained_by_chain = step.name;
        v.held_out_step_before = before;
        v.held_out_after = after;
      }
      before = after;
    }
    int best = -1;
    for (std::size_t i = 0; i < report_.candidates.size(); ++i) {
      const auto& c = report_.candidates[i];
      if (c.applicable && std::isfinite(c.held_out_rmse[qi]) &&
          (best < 0 || c.held_out_rmse[qi] < report_.candidates[static_cast<std::size_t>(best)].held_out_rmse[qi]))
        best = static_cast<int>(i);
    }
    const CandidateResult* bc = best >= 0 ? &report_.candidates[static_cast<std::size_t>(best)] : nullptr;
    if (bc != nullptr) v.best_candidate = bc->name;
    if (v.explained_by.empty() && bc != nullptr) v.held_out_after = bc->held_out_rmse[qi];
    std::string t = words(q) + ": ";
    // The cut the step made, and what the whole chain so far makes of the baseline.
    const std::string step_cut =
        v.explained_by_chain == v.explained_by
            ? " cuts its held-out RMSE " + show(q, v.held_out_before) + " -> " + show(q, v.held_out_after)
            : ", added to the chain (" + v.explained_by_chain + "), cuts its held-out RMSE " +
                  show(q, v.held_out_step_before) + " -> " + show(q, v.held_out_after) + " (baseline " +
                  show(q, v.held_out_before) + ")";
    if (!v.significant && !v.explained_by.empty()) {
      t += "no bias or trend with slip or load with |t| >= 3, yet " + v.explained_by + step_cut;
    } else if (!v.significant) {
      t += "no significant discrepancy (|t| < 3 for its bias and its trends with slip and load)";
    } else if (!v.explained_by.empty()) {
      t += "significant (" + why + "), explained by " + v.explained_by + " (which" + step_cut + ")";
    } else if (bc != nullptr && v.held_out_after <= 0.7 * v.held_out_before) {
      t += "significant (" + why + "); " + bc->name + " alone cuts its held-out RMSE " + show(q, v.held_out_before) +
           " -> " + show(q, v.held_out_after) + ", but the evidence over all quantities is not decisive (delta BIC " +
           format_delta_bic(bc->delta_bic) + ")";
    } else {
      t += "significant (" + why + "), and no candidate explains it" +
           (bc != nullptr ? " (best held out: " + bc->name + ", " + show(q, v.held_out_before) + " -> " +
                                show(q, v.held_out_after) + ")"
                          : std::string());
    }
    // A chain explains it but no candidate alone cuts it by 30 %: say so, with the best single figure.
    if (!v.explained_by.empty() && bc != nullptr && bc->held_out_rmse[qi] > 0.7 * v.held_out_before) {
      t += ", but alone no candidate cuts it by 30 % (best " + bc->name + ": " + show(q, v.held_out_before) + " -> " +
           show(q, bc->held_out_rmse[qi]) + ", " +
           fmt("%+.0f", 100.0 * (bc->held_out_rmse[qi] / v.held_out_before - 1.0)) + " %)";
    }
    v.sentence = t;
    all += (all.empty() ? " Per quantity: " : "; ") + t;
    report_.quantity_verdicts.push_back(std::move(v));
  }
  report_.verdict += all + (all.empty() ? "" : ".");
}

void SingleWheelStudy::write_no_significant_verdict() {
  const auto& c = report_.candidates[static_cast<std::size_t>(report_.best)];
  const bool any = std::any_of(report_.baseline.begin(), report_.baseline.end(), [](const QuantityResiduals& b) {
    return std::abs(b.t_bias) >= 3.0 || std::abs(b.t_slip) >= 3.0 || std::abs(b.t_load) >= 3.0 ||
           std::abs(b.t_slip_angle) >= 3.0;
  });
  report_.verdict = std::string(any ? "No cause is decisive" : "No significant discrepancy") +
                    ": the best candidate, " + c.name + ", changes BIC by " + format_delta_bic(c.delta_bic) +
                    " (needs < " + fmt("%.0f", o_.bic_threshold) + ") and the held-out error from " +
                    fmt("%.2f", report_.baseline_score) + " to " + fmt("%.2f", c.held_out_score) + " sigma";
  for (const auto& [q, index] : report_.partial) {
    const std::size_t qi = static_cast<std::size_t>(std::find(report_.quantities.begin(), report_.quantities.end(), q) -
                                                    report_.quantities.begin());
    const auto& pc = report_.candidates[static_cast<std::size_t>(index)];
    report_.verdict += "; for " + words(q) + " alone, " + pc.name + " cuts the held-out RMSE from " +
                       show(q, report_.baseline_held_out_rmse[qi]) + " to " + show(q, pc.held_out_rmse[qi]);
  }
  if (report_.best_pair && report_.best_pair->applicable) {
    report_.verdict +=
        "; together, " + report_.best_pair->name + " change BIC by " + format_delta_bic(report_.best_pair->delta_bic) +
        (report_.best_pair->held_out_rmse.empty()
             ? std::string()
             : " and the held-out error to " + fmt("%.2f", report_.best_pair->held_out_score) + " sigma") +
        ": not significant either";
  }
  report_.verdict += ".";
}

}  // namespace

double final_held_out_score(const DiscrepancyReport& r) {
  return r.selection.empty() ? r.baseline_score : r.selection.back().held_out_score;
}

HoldOut parse_hold_out(const std::string& text) {
  if (text == "points") return HoldOut::points;
  if (text == "wheel") return HoldOut::wheel;
  if (text == "slip") return HoldOut::slip;
  throw DataError("unknown hold-out '" + text + "' (points, wheel, slip)");
}

namespace {

// The BIC of a study's final model (its forward selection's last step, else
// the baseline).
double final_bic(const DiscrepancyReport& r) { return r.selection.empty() ? r.baseline_bic : r.selection.back().bic; }

// A family baseline's held-out folds: as many as the study's own on a long
// file (DiscrepancyOptions::large_folds), at least 2.
std::size_t family_folds(const DiscrepancyOptions& o, std::size_t n) {
  const std::size_t asked = n > o.large_points ? std::min(o.folds, o.large_folds) : o.folds;
  return std::min<std::size_t>(std::max<std::size_t>(asked, 2), n);
}

// A family's baseline on all points: its parameters fitted (with their
// sigmas) and, when it fits any, its held-out error by `folds` folds (point
// j in fold j mod folds); nothing fitted: its in-sample error. `fitted` gets
// the soil with the fitted values.
FamilyBaseline family_baseline(const Soil& soil, const std::vector<WheelTestPoint>& points, const DiscrepancyOptions& o,
                               Soil& fitted, WorkMeter& meter) {
  FamilyBaseline f;
  f.family = family_name(o.baseline.kind);
  IdentificationOptions io;
  io.model = o.baseline;
  io.sigma = o.sigma;
  io.free = family_parameters(o.baseline.kind);
  const IdentificationResult all = identify_soil(soil, points, io);
  meter.done(kFitUnits);
  fitted = all.soil;
  f.parameters = all.parameters;
  std::vector<PointResidual> held = all.residuals;
  f.held_out_method = "in-sample";
  if (!io.free.empty() && o.leave_one_out) {
    const std::size_t folds = family_folds(o, points.size());
    f.held_out_method = std::to_string(folds) + "-fold";
    held.clear();
    io.covariance = false;
    // The folds in parallel, their residuals joined in fold order.
    std::vector<std::vector<PointResidual>> per_fold(folds);
    shared_thread_pool().for_each_index(folds, [&](std::size_t fold) {
      std::vector<WheelTestPoint> train, test;
      std::vector<std::size_t> index;
      for (std::size_t j = 0; j < points.size(); ++j) {
        (j % folds == fold ? test : train).push_back(points[j]);
        if (j % folds == fold) index.push_back(j);
      }
      IdentificationOptions predict = io;
      predict.free.clear();
      // Each fold's fit starts from the fit on all points (the same optimum, fewer steps).
      for (auto r : identify_soil(identify_soil(all.soil, train, io).soil, test, predict).residuals) {
        r.point = index[r.point];
        per_fold[fold].push_back(r);
      }
      meter.done(kFitUnits);
    });
    for (const auto& f : per_fold) held.insert(held.end(), f.begin(), f.end());
  }
  const auto stats = residual_statistics(held, points);
  for (Quantity q : kQuantities) {
    const double held_out = quantity_rmse(stats, q);
    if (std::any_of(points.begin(), points.end(), [&](const auto& p) { return p.measured(q).has_value(); })) {
      f.held_out_rmse.push_back(held_out);
    }
  }
  f.held_out_score = score_of(held, o.sigma);
  return f;
}

// The held-out RMS (stated sigmas) of a study's final model: its last step's,
// or the family's baseline's when no step passed.
double final_score(const DiscrepancyReport& r, const FamilyBaseline& f) {
  return r.selection.empty() ? f.held_out_score : r.selection.back().held_out_score;
}

// A final model whose held-out residuals are no larger than the stated
// measurement noise (RMS <= 1 stated sigma) leaves nothing for another
// family to explain.
constexpr double kWithinTheNoise = 1.0;

// The family step (issue 43): each family's baseline held out; then the study
// run within the family whose baseline is better (RFT from its material scale
// fitted on all points) and, unless its final model is already within the
// noise, within the other one too; the family whose final model has the
// lower held-out error is taken, with a sentence saying which and by how much.
DiscrepancyReport compare_families(const Soil& soil, const std::vector<WheelTestPoint>& points,
                                   const DiscrepancyOptions& o, WorkMeter& meter) {
  DiscrepancyOptions options[2] = {o, o};
  if (options[0].baseline.kind == ModelKind::rft) options[0].baseline.kind = ModelKind::ishigami;
  options[1].baseline.kind = ModelKind::rft;
  Soil start[2];
  std::vector<FamilyBaseline> families(2);
  // The two baselines side by side (the same results as one after the other).
  shared_thread_pool().run_beside([&] { families[1] = family_baseline(soil, points, options[1], start[1], meter); },
                                  [&] { families[0] = family_baseline(soil, points, options[0], start[0], meter); });
  start[0] = soil;  // Wong-Reece / Ishigami: nothing fitted in its baseline
  const int first = families[1].held_out_score < families[0].held_out_score ? 1 : 0;
  const int second = 1 - first;
  DiscrepancyReport studies[2];
  const auto study = [&](int k) {
    studies[k] = SingleWheelStudy(start[k], points, options[k], meter).run();
    families[k].final_model = studies[k].final_model;
    families[k].final_held_out_score = final_score(studies[k], families[k]);
    families[k].studied_points = 0;
  };
  // The second family is studied after the first, not beside it: each study
  // keeps the cores busy on its own (its screens, steps and folds run on the
  // pool), and beside it the second's work was lost whenever the first fitted
  // within the noise (tried: no faster on 2 cores, up to 40 % more CPU).
  study(first);
  bool both = !(families[first].final_held_out_score <= kWithinTheNoise);
  if (both && points.size() > o.family_screen_points && o.family_screen_points > 0) {
    // The screen: on a long file, the second family's study on a random subset first.
    const std::vector<WheelTestPoint> subset = random_subset(points, o.family_screen_points);
    FamilyBaseline& s = families[second];
    const DiscrepancyReport screened = SingleWheelStudy(start[second], subset, options[second], meter).run();
    s.final_model = screened.final_model;
    s.final_held_out_score = final_held_out_score(screened);
    s.studied_points = subset.size();
    both = s.final_held_out_score < families[first].final_held_out_score;
  }
  if (both) study(second);
  const double w = families[0].final_held_out_score, r = families[1].final_held_out_score;
  const int taken = both ? ((r < w || (!std::isfinite(w) && std::isfinite(r))) ? 1 : 0) : first;
  const FamilyBaseline& t = families[taken];
  const FamilyBaseline& other = families[1 - taken];
  const auto named = [](const FamilyBaseline& f) {
    return f.family + (f.final_model == "baseline" ? "" : " + " + f.final_model);
  };
  const std::string baselines = "as baselines: " + fmt("%.2f", t.held_out_score) + " sigma, " + t.held_out_method +
                                ", against " + fmt("%.2f", other.held_out_score) + ", " + other.held_out_method;
  DiscrepancyReport out = std::move(studies[taken]);
  const std::string against = " against " + named(other) + (named(other).back() == 's' ? "' " : "'s ") +
                              fmt("%.2f", other.final_held_out_score) + " sigma";
  std::string how = ", within the stated noise, so " + other.family + " was not extended (";
  if (both) {
    how = against + ", " + fmt("%.0f", 100.0 * (1.0 - t.final_held_out_score / other.final_held_out_score)) +
          " % lower (";
  } else if (other.studied_points > 0) {
    how = against + " on " + fmt("%.0f", static_cast<double>(other.studied_points)) + " of the " +
          fmt("%.0f", static_cast<double>(points.size())) + " points (a random subset), so " + other.family +
          " was not studied on all of them (";
  }
  out.family_choice = "family " + t.family + ": its final model " + named(t) + " held out at " +
                      fmt("%.2f", t.final_held_out_score) + " sigma" + how + baselines + ")";
  out.families = std::move(families);
  return out;
}

// The study within one family, or within each and the better taken
// (compare_families); an RFT baseline starts from its material scale fitted
// on all points.
DiscrepancyReport run_in_family(const Soil& soil, const std::vector<WheelTestPoint>& points,
                                const DiscrepancyOptions& o) {
  WorkMeter meter(o.progress);
  check_points_can_tell_candidates_apart(points);  // before any family is fitted to them
  // A family's baseline: one fit on all points and one per fold.
  const double family_fits =
      kFitUnits * (1.0 + (o.leave_one_out ? static_cast<double>(family_folds(o, points.size())) : 0.0));
  if (o.compare_families) {
    meter.expect(2.0 * family_fits);
    DiscrepancyReport r = compare_families(soil, points, o, meter);
    meter.finish();
    return r;
  }
  Soil start = soil;
  std::vector<FamilyBaseline> families;
  std::string choice;
  if (o.baseline.kind == ModelKind::rft) {
    meter.expect(family_fits);
    families = {family_baseline(soil, points, o, start, meter)};
    choice = "baseline family RFT (given), material scale fitted";
  }
  DiscrepancyReport r = SingleWheelStudy(start, points, o, meter).run();
  meter.finish();
  r.families = std::move(families);
  r.family_choice = std::move(choice);
  return r;
}

// The named steps, " + "-joined, or "none".
std::string named_chain(const DiscrepancyReport& r) {
  const std::string names = named_causes(r);
  return names.empty() ? "none" : names;
}

// Two readings of one file differ materially: other causes named, or final
// held-out scores 10 % apart.
bool readings_differ(const DiscrepancyReport& a, const DiscrepancyReport& b) {
  return named_chain(a) != named_chain(b) || std::abs(final_held_out_score(a) - final_held_out_score(b)) >
                                                 0.1 * std::min(final_held_out_score(a), final_held_out_score(b));
}

// What the two readings give, for the sentence that prints both: each
// reading's causes and final held-out score, and which one alone fits within
// the stated noise (a fact to weigh, not a choice: both are printed).
std::string readings_compared(const DiscrepancyReport& as_longitudinal, const DiscrepancyReport& as_travel) {
  const double l = final_held_out_score(as_longitudinal), t = final_held_out_score(as_travel);
  std::string s = "read as longitudinal slip: causes " + named_chain(as_longitudinal) + ", final model held out at " +
                  fmt("%.2f", l) + " sigma; read as travel slip: causes " + named_chain(as_travel) + ", " +
                  fmt("%.2f", t) + " sigma";
  if ((l <= kWithinTheNoise) != (t <= kWithinTheNoise)) {
    s += std::string("; only the ") + (t <= kWithinTheNoise ? "travel" : "longitudinal") +
         " reading's final model fits within the stated noise";
  }
  return s;
}

// Why the study took the reading it took (travel when `travel`): the
// measurements the other reading cannot carry, else the two final BICs.
std::string reading_reason(const DiscrepancyReport& as_travel, const DiscrepancyReport& as_longitudinal, bool travel) {
  const std::size_t lost_travel = as_travel.unsupported, lost_longitudinal = as_longitudinal.unsupported;
  const char* chosen = travel ? "travel" : "longitudinal";
  const char* other = travel ? "longitudinal" : "travel";
  if (lost_travel != lost_longitudinal) {
    return std::string("read as ") + other + " slip the model cannot carry the load of " +
           fmt("%.0f", static_cast<double>(std::max(lost_travel, lost_longitudinal))) + " measurements, read as " +
           chosen + " of " + fmt("%.0f", static_cast<double>(std::min(lost_travel, lost_longitudinal)));
  } else {
    const double gap = std::abs(final_bic(as_travel) - final_bic(as_longitudinal));
    return std::string("each reading's final model fitted: BIC lower by ") + fmt("%.1f", gap) + " read as " + chosen +
           " slip (" + (travel ? as_travel : as_longitudinal).final_model + ") than as " + other + " (" +
           (travel ? as_longitudinal : as_travel).final_model + ")" +
           (gap < 10.0 ? "; the data barely tell them apart: give --slip-definition if the testbed's is known" : "");
  }
}

// The two readings side by side: the travel one on the pool, the
// longitudinal one here; the progress is their mean, reported by either (one
// at a time; the one done first would leave it standing), and a cancel stops both.
void run_both_readings(const Soil& soil, const std::vector<WheelTestPoint>& points, const DiscrepancyOptions& o,
                       DiscrepancyReport& as_longitudinal, DiscrepancyReport& as_travel) {
  const auto& progress = o.progress;
  std::atomic<bool> stop{false};
  std::mutex reporting;
  double done[2] = {0.0, 0.0};
  const auto report = [&](int reading, double f) {
    const std::lock_guard<std::mutex> lock(reporting);
    done[reading] = f;
    if (progress) progress(0.5 * (done[0] + done[1]));
  };
  DiscrepancyOptions longitudinal = o, travel_reading = o;
  longitudinal.baseline.slip_definition = SlipDefinition::longitudinal;
  longitudinal.progress = [&](double f) { report(0, f); };
  travel_reading.baseline.slip_definition = SlipDefinition::travel;
  travel_reading.progress = [&](double f) {
    if (stop.load()) throw DataError("cancelled");
    report(1, f);
  };
  shared_thread_pool().run_beside([&] { as_travel = run_in_family(soil, points, travel_reading); },
                                  [&] {
                                    try {
                                      as_longitudinal = run_in_family(soil, points, longitudinal);
                                    } catch (...) {
                                      stop = true;
                                      throw;
                                    }
                                  });
  if (progress) progress(1.0);
}

}  // namespace

std::string named_causes(const DiscrepancyReport& r) {
  std::string names;
  for (const auto& c : r.selection) {
    if (c.role == StepRole::cause) names += (names.empty() ? "" : " + ") + last_link(c.name);
  }
  return names;
}

DiscrepancyReport study_single_wheel(const Soil& soil, const std::vector<WheelTestPoint>& points,
                                     const DiscrepancyOptions& options) {
  // A wheel at a slip angle, or a measured lateral force: the baseline is the
  // slip-angle model (Ishigami et al. 2007; Wong-Reece at beta = 0).
  DiscrepancyOptions o = options;
  const bool lateral = std::any_of(points.begin(), points.end(), [](const WheelTestPoint& p) {
    return p.slip_angle != 0.0 || p.lateral_force.has_value();
  });
  if (lateral && o.baseline.kind == ModelKind::wong_reece) o.baseline.kind = ModelKind::ishigami;
  const bool at_angle = std::any_of(points.begin(), points.end(), [](const auto& p) { return p.slip_angle != 0.0; });
  if (!at_angle) return run_in_family(soil, points, o);
  // How the slip is read (SlipDefinition, model.h): given; the longitudinal
  // one when the readings differ by < 0.01 in slip at every point; else the
  // whole study under each (a hidden effect can mimic the other reading in
  // the baseline), keeping the one whose model carries more measurements;
  // when both carry them all and the readings differ materially, both are
  // reported (other_reading), each complete; else the lower final BIC.
  std::string why = "given";
  double largest = 0.0;
  for (const auto& p : points) largest = std::max(largest, (1.0 - p.slip) * (1.0 - std::cos(p.slip_angle)));
  if (!o.slip_definition && largest < 0.01) {
    o.slip_definition = SlipDefinition::longitudinal;
    why = "at these slip angles the two readings differ by at most " + fmt("%.3g", largest) + " in slip";
  }
  DiscrepancyReport r;
  if (o.slip_definition) {
    o.baseline.slip_definition = *o.slip_definition;
    r = run_in_family(soil, points, o);
  } else {
    DiscrepancyReport as_longitudinal, as_travel;
    run_both_readings(soil, points, o, as_longitudinal, as_travel);
    const std::size_t lost_travel = as_travel.unsupported, lost_longitudinal = as_longitudinal.unsupported;
    if (lost_travel == lost_longitudinal && readings_differ(as_longitudinal, as_travel)) {
      as_longitudinal.slip_definition = to_string(SlipDefinition::longitudinal);
      as_travel.slip_definition = to_string(SlipDefinition::travel);
      as_longitudinal.slip_definition_reason = as_travel.slip_definition_reason =
          "the file does not state its slip definition and the two readings give different results (" +
          readings_compared(as_longitudinal, as_travel) +
          "): both follow, each complete, the one whose final model holds out better first; give "
          "--slip-definition, or name the file's slip column travel_slip or longitudinal_slip";
      // The better-fitting reading first: the one a reader meets first is not the one the data reject.
      const bool travel_first = final_held_out_score(as_travel) < final_held_out_score(as_longitudinal);
      DiscrepancyReport& first = travel_first ? as_travel : as_longitudinal;
      first.other_reading.push_back(std::move(travel_first ? as_longitudinal : as_travel));
      return std::move(first);
    }
    const bool travel = lost_travel != lost_longitudinal ? lost_travel < lost_longitudinal
                                                         : final_bic(as_travel) < final_bic(as_longitudinal);
    why = reading_reason(as_travel, as_longitudinal, travel);
    o.baseline.slip_definition = travel ? SlipDefinition::travel : SlipDefinition::longitudinal;
    r = std::move(travel ? as_travel : as_longitudinal);
  }
  r.slip_definition = to_string(o.baseline.slip_definition);
  r.slip_definition_reason = why;
  return r;
}

}  // namespace roverlab::analysis

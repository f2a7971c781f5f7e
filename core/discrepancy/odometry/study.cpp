#include "core/discrepancy/odometry/study.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <Eigen/Dense>

#include "core/common/error.h"
#include "core/discrepancy/dense_algebra.h"
#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/odometry/candidates.h"
#include "core/discrepancy/study.h"
#include "core/models/reference_track.h"

namespace roverlab::analysis {

namespace {

using estimation::OdometryCorrections;
using estimation::ReferenceTrack;
using estimation::WheelSamples;

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

// m/s: a part of the drive starts once the reference moves at least this fast.
constexpr double kUnderWaySpeed = 0.2;

WheelSamples slice(const WheelSamples& w, double t0, double t1) {
  WheelSamples out;
  for (std::size_t i = 0; i < w.time.size(); ++i) {
    if (w.time[i] < t0 - 1e-9 || w.time[i] > t1 + 1e-9) continue;
    out.time.push_back(w.time[i]);
    out.left_rate.push_back(w.left_rate[i]);
    out.right_rate.push_back(w.right_rate[i]);
  }
  return out;
}

// One part of the drive: wheel samples, the reference samples in it, and the
// heading it starts with; the start position is the reference's at the first
// wheel sample (on the corrected clock).
struct Part {
  WheelSamples wheels;
  std::vector<std::size_t> ref;  // indices into the reference track
  double heading0 = 0;
};

// East/north errors of dead reckoning against the reference at its samples.
std::vector<double> track_errors(const Part& p, const ReferenceTrack& ref, const estimation::SkidSteerGeometry& g,
                                 const OdometryCorrections& c) {
  const double t0 = std::clamp(p.wheels.time.front() + c.time_offset, ref.time.front(), ref.time.back());
  const double east0 = log::interpolate_linear(ref.time, ref.east, t0);
  const double north0 = log::interpolate_linear(ref.time, ref.north, t0);
  const estimation::OdometryTrack tr = estimation::dead_reckon(p.wheels, g, c, east0, north0, p.heading0);
  std::vector<double> r;
  r.reserve(2 * p.ref.size());
  for (std::size_t k : p.ref) {
    const double t = ref.time[k];
    // Outside the (shifted) wheel span the track holds its end value.
    const double tc = std::clamp(t, tr.time.front(), tr.time.back());
    r.push_back(log::interpolate_linear(tr.time, tr.east, tc) - ref.east[k]);
    r.push_back(log::interpolate_linear(tr.time, tr.north, tc) - ref.north[k]);
  }
  return r;
}

// The RMS horizontal error of (east, north) residual pairs.
double horizontal_rmse(const std::vector<double>& r) { return rmse(r, 2.0); }

double final_of(const std::vector<double>& r) {
  return r.size() < 2 ? 0.0 : std::hypot(r[r.size() - 2], r[r.size() - 1]);
}

// The track errors' likelihood (likelihood.h): east and north each a group
// of increments (a dead-reckoning error is an integral) with its own noise
// scale and lag-1 autocorrelation, which may be negative: the GPS fixes'
// noise is white in position, so its increments have -0.5. 1 mm is the
// smallest scale trusted. (Tried: ARMA(1,1) increments, exact for a random
// walk plus white noise: on simulated drives, whose residuals are
// deterministic discretisation errors more than noise, its sigmas covered the
// hidden value 7 times in 36 within 1 sigma; these are conservative instead.)
GroupedLikelihood track_likelihood(std::size_t points) {
  return GroupedLikelihood({{"east", points, true, 1e-3, true, -0.9}, {"north", points, true, 1e-3, true, -0.9}});
}

// Interleaved (east, north) errors as east ones then north ones.
std::vector<double> by_axis(const double* r, std::size_t values) {
  std::vector<double> out(values);
  const std::size_t points = values / 2;
  for (std::size_t j = 0; j < points; ++j) {
    out[j] = r[2 * j];
    out[points + j] = r[2 * j + 1];
  }
  return out;
}

// BIC with k free parameters: -2 ln L of that likelihood + k ln n.
double bic(const std::vector<double>& r, int k) {
  const GroupedLikelihood l = track_likelihood(r.size() / 2);
  return l.minus_two_log_l(by_axis(r.data(), r.size())) +
         k * std::log(static_cast<double>(std::max<std::size_t>(l.effective_count(), 1)));
}

// The fit part's track errors as a Ceres cost of a candidate's parameters.
struct TrackCost {
  const OdometryCandidateModel* candidate;
  const Part* part;
  const ReferenceTrack* ref;
  const estimation::SkidSteerGeometry* rover;
  bool operator()(double const* const* x, double* residuals) const {
    const auto r = track_errors(*part, *ref, *rover, candidate->corrections(x[0]));
    std::copy(r.begin(), r.end(), residuals);
    return true;
  }
};

// Two sets of corrections applied together: scales multiply, time offsets
// add, slips compose as 1 - (1 - a)(1 - b).
OdometryCorrections combine(OdometryCorrections a, const OdometryCorrections& b) {
  a.radius_scale *= b.radius_scale;
  a.left_scale *= b.left_scale;
  a.right_scale *= b.right_scale;
  a.track_factor *= b.track_factor;
  a.time_offset += b.time_offset;
  if (a.slip.empty()) {
    a.slip = b.slip;
  } else if (!b.slip.empty()) {
    for (std::size_t i = 0; i < std::min(a.slip.size(), b.slip.size()); ++i)
      a.slip[i] = 1.0 - (1.0 - a.slip[i]) * (1.0 - b.slip[i]);
  }
  return a;
}

// Several candidates fitted together: their parameters side by side.
class ChainModel final : public OdometryCandidateModel {
 public:
  explicit ChainModel(std::vector<const OdometryCandidateModel*> links) : links_(std::move(links)) {}
  std::string name() const override {
    return join([](const OdometryCandidateModel& m) { return m.name(); }, " + ");
  }
  std::string cause() const override {
    return join([](const OdometryCandidateModel& m) { return m.cause(); }, "; and ");
  }
  std::vector<CandidateParameter> parameters() const override {
    std::vector<CandidateParameter> p;
    for (const auto* m : links_) {
      const auto q = m->parameters();
      p.insert(p.end(), q.begin(), q.end());
    }
    return p;
  }
  OdometryCorrections corrections(const double* x) const override { return apply(x, false); }
  OdometryCorrections held_out_corrections(const double* x) const override { return apply(x, true); }
  std::vector<OdometryParameter> summary(const std::vector<double>& x,
                                         const std::vector<double>& sigma) const override {
    std::vector<OdometryParameter> out;
    std::size_t at = 0;
    for (const auto* m : links_) {
      const std::size_t k = m->parameters().size();
      const std::vector<double> xs(x.begin() + static_cast<std::ptrdiff_t>(at),
                                   x.begin() + static_cast<std::ptrdiff_t>(at + k));
      const std::vector<double> ss(sigma.begin() + static_cast<std::ptrdiff_t>(at),
                                   sigma.begin() + static_cast<std::ptrdiff_t>(at + k));
      const auto part = m->summary(xs, ss);
      out.insert(out.end(), part.begin(), part.end());
      at += k;
    }
    return out;
  }

 private:
  template <class F>
  std::string join(F f, const char* sep) const {
    std::string s;
    for (const auto* m : links_) s += (s.empty() ? "" : sep) + f(*m);
    return s;
  }
  OdometryCorrections apply(const double* x, bool held_out) const {
    OdometryCorrections c;
    for (const auto* m : links_) {
      c = combine(c, held_out ? m->held_out_corrections(x) : m->corrections(x));
      x += m->parameters().size();
    }
    return c;
  }
  std::vector<const OdometryCandidateModel*> links_;
};

// The fitted parameters within 1 % of a bound of their search (issue 43):
// named in cand.at_bound; a reported parameter that is one of them (or, for a
// summary, takes the value of one) is marked and loses its sigma.
void mark_bounds(const std::vector<CandidateParameter>& parameters, OdometryCandidate& cand) {
  std::vector<double> values;
  for (std::size_t i = 0; i < parameters.size() && i < cand.fitted.size(); ++i) {
    if (!near_bound(cand.fitted[i], parameters[i].lower, parameters[i].upper)) continue;
    cand.at_bound.push_back(parameters[i].name);
    values.push_back(cand.fitted[i]);
  }
  for (auto& p : cand.parameters) {
    const bool named = std::find(cand.at_bound.begin(), cand.at_bound.end(), p.name) != cand.at_bound.end();
    const bool valued = std::find(values.begin(), values.end(), p.value) != values.end();
    if (!named && !valued) continue;
    p.at_bound = true;
    p.sigma = NAN;
  }
}

// The study's steps: inputs, the split, the baseline's residuals, each
// candidate's fit and held-out score, and the verdict.
class OdometryStudy {
 public:
  OdometryStudy(const log::Log& log, const OdometryStudyOptions& options) : log_(log), o_(options) {}
  OdometryDiscrepancyReport run();

 private:
  void read_inputs();
  void split();
  void score_baseline();
  void describe_baseline(const std::vector<double>& base_fit);
  OdometryCandidate fit_candidate(const OdometryCandidateModel& model) const;
  std::vector<double> parameter_sigmas(ceres::Problem& problem, std::vector<double>& x,
                                       const std::vector<double>& r_fit) const;
  void choose_cause();
  void residual_series();
  void select_forward();
  struct Steps;  // select_forward's hooks (study.h)
  void write_what_is_wrong();
  void weigh_steps();
  void write_verdict();
  void write_chain_verdict();

  const log::Log& log_;
  const OdometryStudyOptions& o_;
  ReferenceTrack ref_;
  WheelSamples wheels_;
  Part fit_, test_;
  std::vector<std::unique_ptr<OdometryCandidateModel>> models_;
  OdometryDiscrepancyReport rep_;
};

OdometryDiscrepancyReport OdometryStudy::run() {
  read_inputs();
  split();
  score_baseline();
  const OdometryCandidateContext context{fit_.wheels, test_.wheels.time.size(), o_};
  models_ = odometry_candidates(context);
  // The screen: each candidate fitted alone, in parallel.
  rep_.candidates =
      screen_candidates<OdometryCandidate>(models_.size(), [&](std::size_t i) { return fit_candidate(*models_[i]); });
  choose_cause();
  residual_series();
  select_forward();
  weigh_steps();
  write_what_is_wrong();
  write_verdict();
  return std::move(rep_);
}

void OdometryStudy::read_inputs() {
  const log::Stream& ws = log_.stream(o_.wheels);
  for (const char* c : {"angle_FL", "angle_FR", "angle_RL", "angle_RR"}) {
    if (ws.find_channel(c) == nullptr) throw DataError("stream '" + o_.wheels + "' has no channel '" + c + "'");
  }
  ref_ = estimation::reference_from_gps(log_, o_.reference);
  if (!ref_.present)
    throw DataError("no reference track: stream '" + o_.reference + "' with east and north is missing");
  wheels_ = estimation::wheel_rates(ws.time(), ws.channel("angle_FL").values, ws.channel("angle_FR").values,
                                    ws.channel("angle_RL").values, ws.channel("angle_RR").values);
  for (std::size_t i = 0; i < wheels_.time.size(); ++i) {
    if (!std::isfinite(wheels_.left_rate[i] + wheels_.right_rate[i])) {
      throw DataError("stream '" + o_.wheels + "': missing wheel angle near t = " + std::to_string(wheels_.time[i]) +
                      " s");
    }
  }
}

// Split where the driven distance reaches fit_fraction, within the wheel
// span; each part starts with the reference course over its first
// heading_distance metres.
void OdometryStudy::split() {
  const std::vector<double> dist = estimation::distance_along(ref_);
  rep_.distance = dist.back();
  if (rep_.distance < 5.0)
    throw DataError("the reference track covers only " + std::to_string(rep_.distance) + " m (need 5 m)");
  // Each part starts with the rover under way: its heading is the course
  // over the next metres, which a turn in place before them would falsify.
  const auto under_way = [&](std::size_t k) { return std::hypot(ref_.v_east[k], ref_.v_north[k]) >= kUnderWaySpeed; };
  std::size_t first = 0;
  while (first + 1 < dist.size() && (ref_.time[first] < wheels_.time.front() || !under_way(first))) ++first;
  const double t_begin = std::max(ref_.time[first], wheels_.time.front());
  const double t_end = std::min(ref_.time.back(), wheels_.time.back());
  std::size_t split = 0;
  while (split + 1 < dist.size() && dist[split] < o_.fit_fraction * rep_.distance) ++split;
  while (split + 1 < dist.size() && !under_way(split)) ++split;
  rep_.split_time = ref_.time[split];
  rep_.fit_distance = dist[split];

  fit_.wheels = slice(wheels_, t_begin, rep_.split_time);
  test_.wheels = slice(wheels_, rep_.split_time, t_end);
  for (std::size_t k = 0; k < ref_.time.size(); ++k) {
    if (ref_.time[k] < t_begin || ref_.time[k] > t_end) continue;
    (ref_.time[k] <= rep_.split_time ? fit_.ref : test_.ref).push_back(k);
  }
  rep_.fit_samples = fit_.ref.size();
  rep_.test_samples = test_.ref.size();
  if (fit_.ref.size() < 10 || test_.ref.size() < 10 || fit_.wheels.time.size() < 3 || test_.wheels.time.size() < 3) {
    throw DataError("too few samples on one side of the split at t = " + std::to_string(rep_.split_time) + " s");
  }
  fit_.heading0 = estimation::initial_course(ref_, o_.heading_distance, fit_.ref.front());
  if (!std::isfinite(fit_.heading0)) fit_.heading0 = 0.0;
  const double course_split = estimation::initial_course(ref_, o_.heading_distance, test_.ref.front());
  test_.heading0 = std::isfinite(course_split) ? course_split : fit_.heading0;
}

// The baseline (nominal geometry) on both parts.
void OdometryStudy::score_baseline() {
  const std::vector<double> base_fit = track_errors(fit_, ref_, o_.rover, {});
  const std::vector<double> base_test = track_errors(test_, ref_, o_.rover, {});
  rep_.baseline_fit_rmse = horizontal_rmse(base_fit);
  rep_.baseline_held_out_rmse = horizontal_rmse(base_test);
  rep_.baseline_held_out_final = final_of(base_test);
  rep_.baseline_bic = bic(base_fit, 0);
  describe_baseline(base_fit);
}

// What the baseline gets wrong on the fit part: distance ratio, heading
// error at the split, along- and cross-track components against the
// reference course.
void OdometryStudy::describe_baseline(const std::vector<double>& base_fit) {
  const auto tr = estimation::dead_reckon(fit_.wheels, o_.rover, {}, 0.0, 0.0, fit_.heading0);
  double odo = 0.0;
  for (std::size_t i = 1; i < tr.time.size(); ++i) {
    odo += std::hypot(tr.east[i] - tr.east[i - 1], tr.north[i] - tr.north[i - 1]);
  }
  rep_.distance_ratio = rep_.fit_distance > 0 ? odo / rep_.fit_distance : NAN;
  const double course = estimation::course_at(ref_, tr.time.back());
  rep_.heading_error_end = std::isfinite(course) ? wrap(tr.heading.back() - course) : NAN;
  double sa = 0, sc = 0;
  std::size_t n = 0;
  for (std::size_t j = 0; j < fit_.ref.size(); ++j) {
    const double c = estimation::course_at(ref_, ref_.time[fit_.ref[j]]);
    if (!std::isfinite(c)) continue;
    const double de = base_fit[2 * j], dn = base_fit[2 * j + 1];
    const double along = de * std::sin(c) + dn * std::cos(c);
    const double cross = de * std::cos(c) - dn * std::sin(c);
    sa += along * along;
    sc += cross * cross;
    ++n;
  }
  rep_.along_track_rmse = n ? std::sqrt(sa / static_cast<double>(n)) : NAN;
  rep_.cross_track_rmse = n ? std::sqrt(sc / static_cast<double>(n)) : NAN;
}

// Fits a candidate on the fit part (bounded least squares) and scores it on
// the held-out part.
OdometryCandidate OdometryStudy::fit_candidate(const OdometryCandidateModel& model) const {
  OdometryCandidate cand;
  cand.name = model.name();
  cand.cause = model.cause();
  const std::vector<CandidateParameter> parameters = model.parameters();
  const int k = static_cast<int>(parameters.size());
  cand.parameter_count = k;
  std::vector<double> x;
  x.reserve(parameters.size());
  for (const auto& p : parameters) x.push_back(p.start);
  ceres::Problem problem;
  auto* cost = new ceres::DynamicNumericDiffCostFunction<TrackCost, ceres::CENTRAL>(
      new TrackCost{&model, &fit_, &ref_, &o_.rover});
  cost->AddParameterBlock(k);
  cost->SetNumResiduals(static_cast<int>(2 * fit_.ref.size()));
  problem.AddResidualBlock(cost, nullptr, x.data());
  for (int i = 0; i < k; ++i) {
    problem.SetParameterLowerBound(x.data(), i, parameters[static_cast<std::size_t>(i)].lower);
    problem.SetParameterUpperBound(x.data(), i, parameters[static_cast<std::size_t>(i)].upper);
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 100;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  const std::vector<double> r_fit = track_errors(fit_, ref_, o_.rover, model.corrections(x.data()));
  cand.fit_rmse = horizontal_rmse(r_fit);
  cand.bic = bic(r_fit, k);
  cand.delta_bic = cand.bic - rep_.baseline_bic;
  cand.parameters = model.summary(x, parameter_sigmas(problem, x, r_fit));
  cand.fitted = x;
  mark_bounds(parameters, cand);
  const std::vector<double> r_test = track_errors(test_, ref_, o_.rover, model.held_out_corrections(x.data()));
  cand.held_out_rmse = horizontal_rmse(r_test);
  cand.held_out_final = final_of(r_test);
  cand.significant = cand.at_bound.empty() && cand.delta_bic < -10.0 &&
                     cand.held_out_rmse <= (1.0 - o_.min_gain) * rep_.baseline_held_out_rmse &&
                     cand.held_out_rmse <= rep_.baseline_held_out_rmse - o_.min_improvement;
  return cand;
}

// Parameter sigmas from the Gauss-Newton covariance of the track errors
// whitened by their likelihood at the solution (increments, a noise scale
// and autocorrelation per axis); NaN beyond 3 parameters or where the data
// do not determine a parameter.
std::vector<double> OdometryStudy::parameter_sigmas(ceres::Problem& problem, std::vector<double>& x,
                                                    const std::vector<double>& r_fit) const {
  const int k = static_cast<int>(x.size());
  std::vector<double> sigma(static_cast<std::size_t>(k), NAN);
  if (k > 3 || r_fit.size() < 4) return sigma;
  ceres::CRSMatrix crs;
  if (!problem.Evaluate(ceres::Problem::EvaluateOptions(), nullptr, nullptr, nullptr, &crs)) return sigma;
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row) {
    for (int i = crs.rows[static_cast<std::size_t>(row)]; i < crs.rows[static_cast<std::size_t>(row) + 1]; ++i)
      J(row, crs.cols[static_cast<std::size_t>(i)]) = crs.values[static_cast<std::size_t>(i)];
  }
  if (J.rows() != static_cast<Eigen::Index>(r_fit.size()) || J.cols() != k) return sigma;
  const GroupedLikelihood l = track_likelihood(r_fit.size() / 2);
  const LikelihoodProfile at = l.profile(by_axis(r_fit.data(), r_fit.size()));
  Eigen::MatrixXd Jw(static_cast<Eigen::Index>(l.effective_count()), k);
  for (int c = 0; c < k; ++c) {
    const Eigen::VectorXd column = J.col(c);
    const std::vector<double> ordered = by_axis(column.data(), r_fit.size());
    std::vector<double> w(l.effective_count());
    l.whiten(at, ordered.data(), w.data());
    for (std::size_t i = 0; i < w.size(); ++i) Jw(static_cast<Eigen::Index>(i), c) = w[i];
  }
  const Eigen::MatrixXd info = Jw.transpose() * Jw;
  const std::optional<EigenvalueRange> eigenvalues = symmetric_eigenvalue_range(info);
  if (!eigenvalues || !(eigenvalues->min > 1e-12 * eigenvalues->max)) return sigma;
  const Eigen::MatrixXd cov = lu_inverse(info);
  for (int i = 0; i < k; ++i) sigma[static_cast<std::size_t>(i)] = std::sqrt(std::max(0.0, cov(i, i)));
  return sigma;
}

// The named cause: among the significant candidates, the best held-out
// RMSE; held-out RMSEs within 10 % or min_improvement of each other count
// as equal, and then the candidate with fewer parameters wins.
void OdometryStudy::choose_cause() {
  for (std::size_t i = 0; i < rep_.candidates.size(); ++i) {
    const auto& c = rep_.candidates[i];
    if (!c.significant) continue;
    if (rep_.best < 0) {
      rep_.best = static_cast<int>(i);
      continue;
    }
    const auto& b = rep_.candidates[static_cast<std::size_t>(rep_.best)];
    const double tie = std::max(0.1 * b.held_out_rmse, o_.min_improvement);
    const bool equal = std::abs(c.held_out_rmse - b.held_out_rmse) < tie;
    if (equal ? c.parameter_count < b.parameter_count : c.held_out_rmse < b.held_out_rmse)
      rep_.best = static_cast<int>(i);
  }
}

// Several causes at once (the single-wheel study's forward selection): the
// named cause first; then each of the others refitted together with the
// chain, and of the steps that lower BIC by more than 10 and the held-out
// RMSE by min_improvement, the one with the lowest BIC is kept. (Chosen by
// BIC alone, the many-parameter slip episodes win every step: track errors
// are correlated in time, and BIC counts them as independent.)
// The residuals before and after the named cause along the whole drive, for
// the report's plots; the RMS over the held-out part is the study's score.
void OdometryStudy::residual_series() {
  OdometryResiduals& out = rep_.residuals;
  const OdometryCandidateModel* cause = rep_.best >= 0 ? models_[static_cast<std::size_t>(rep_.best)].get() : nullptr;
  const double* x = cause != nullptr ? rep_.candidates[static_cast<std::size_t>(rep_.best)].fitted.data() : nullptr;
  for (const Part* part : {&fit_, &test_}) {
    const std::vector<double> before = track_errors(*part, ref_, o_.rover, {});
    std::vector<double> after;
    if (cause != nullptr) {
      after =
          track_errors(*part, ref_, o_.rover, part == &fit_ ? cause->corrections(x) : cause->held_out_corrections(x));
    }
    for (std::size_t j = 0; j < part->ref.size(); ++j) {
      const std::size_t k = part->ref[j];
      out.time.push_back(ref_.time[k]);
      out.before.push_back(std::hypot(before[2 * j], before[2 * j + 1]));
      out.after.push_back(after.empty() ? NAN : std::hypot(after[2 * j], after[2 * j + 1]));
      const double wheel = o_.rover.wheel_radius * 0.5 *
                           (log::interpolate_linear(wheels_.time, wheels_.left_rate, ref_.time[k]) +
                            log::interpolate_linear(wheels_.time, wheels_.right_rate, ref_.time[k]));
      const double slip = 1.0 - std::hypot(ref_.v_east[k], ref_.v_north[k]) / wheel;
      out.slip.push_back(std::abs(wheel) >= 0.05 && std::abs(slip) <= 1.0 ? slip : NAN);
    }
  }
  out.rms_before = rep_.baseline_held_out_rmse;
  out.rms_after = cause != nullptr ? rep_.candidates[static_cast<std::size_t>(rep_.best)].held_out_rmse : NAN;
}

// The forward selection's hooks (study.h, select_forward): each open
// candidate refitted together with the chain; of the steps that lower BIC
// by more than 10 against the chain before and the held-out RMSE by at
// least min_improvement, the lowest BIC is kept.
struct OdometryStudy::Steps {
  using Trial = OdometryCandidate;
  OdometryStudy& s;
  std::optional<OdometryCandidate> closest;  // the round's best step by held-out RMSE, kept or not

  bool open(const std::vector<std::size_t>& /*chain*/, std::size_t /*i*/) const { return true; }
  OdometryCandidate trial(const std::vector<std::size_t>& chain, std::size_t i) const {
    std::vector<const OdometryCandidateModel*> links;
    links.reserve(chain.size() + 1);
    for (std::size_t j : chain) links.push_back(s.models_[j].get());
    links.push_back(s.models_[i].get());
    return s.fit_candidate(ChainModel(links));
  }
  bool passes(const OdometryCandidate& fit) const {
    const OdometryCandidate& at = s.rep_.selection.back();
    return fit.at_bound.empty() && fit.bic - at.bic < -10.0 &&
           fit.held_out_rmse <= at.held_out_rmse - s.o_.min_improvement;
  }
  int best(const std::vector<std::size_t>& open, const std::vector<OdometryCandidate>& trials) {
    closest.reset();
    for (std::size_t i : open) {
      if (!closest || trials[i].held_out_rmse < closest->held_out_rmse) closest = trials[i];
    }
    return best_trial(open, trials, [&](const OdometryCandidate& a, const OdometryCandidate& b) {
      return passes(a) && (!passes(b) || a.bic < b.bic);
    });
  }
  bool accept(const std::vector<std::size_t>& /*chain*/, std::size_t /*i*/, const OdometryCandidate& t) {
    if (passes(t)) return true;
    s.rep_.rejected_step = std::move(closest);
    return false;
  }
  void join(std::vector<std::size_t>& chain, std::size_t i, OdometryCandidate&& t) {
    chain.push_back(i);
    s.rep_.selection.push_back(std::move(t));
  }
};

void OdometryStudy::select_forward() {
  if (rep_.best < 0) return;
  std::vector<std::size_t> chain{static_cast<std::size_t>(rep_.best)};
  rep_.selection.push_back(rep_.candidates[static_cast<std::size_t>(rep_.best)]);
  Steps steps{*this, std::nullopt};
  analysis::select_forward(steps, models_.size(), models_.size(), chain);
}

void OdometryStudy::write_what_is_wrong() {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "On the fit part (%.1f m) wheel odometry has %.2f m RMSE: %.2f m along track, %.2f m across; "
                "it measures %.1f %% of the distance and ends %.1f deg off the reference course.",
                rep_.fit_distance, rep_.baseline_fit_rmse, rep_.along_track_rmse, rep_.cross_track_rmse,
                100.0 * rep_.distance_ratio, rep_.heading_error_end * 180.0 / M_PI);
  rep_.what_is_wrong = buf;
}

// "name = value, ..." of fitted parameters.
std::string parameters_text(const std::vector<OdometryParameter>& ps) {
  std::string text;
  for (const auto& p : ps) {
    char one[96];
    std::snprintf(one, sizeof one, "%s%s = %.4g%s", text.empty() ? "" : ", ", p.name.c_str(), p.value,
                  p.at_bound ? " (at its bound)" : "");
    text += one;
  }
  return text;
}

// Each step's share of the chain's held-out gain (issue 43): the held-out
// RMSE it cut against the step before, over the whole chain's cut; a step
// under kNegligibleGainShare is "also consistent with", not a cause.
void OdometryStudy::weigh_steps() {
  if (rep_.selection.empty()) return;
  double before = rep_.baseline_held_out_rmse;
  const double final_rmse = rep_.selection.back().held_out_rmse;
  const auto without = [&](const OdometryCandidate& step) {
    const double w = without_step(final_rmse, before, step.held_out_rmse);
    before = step.held_out_rmse;
    return w;
  };
  analysis::weigh_steps(rep_.selection, rep_.baseline_held_out_rmse, final_rmse, without,
                        [](const OdometryCandidate& step) {
                          return step_role(!step.at_bound.empty(), step.gain_share, kNegligibleGainShare);
                        });
}

// Several steps: the named ones with their shares, the values of the final
// joint fit, then the steps that are only consistent with the data.
void OdometryStudy::write_chain_verdict() {
  const OdometryCandidate& last = rep_.selection.back();
  const StepLists steps = list_steps(
      rep_.selection, [](const OdometryCandidate& step) { return step_share_text(step.name, step.gain_share); },
      ", then ");
  const std::string& named = steps.named;
  const std::string& also = steps.also;
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "%s: %s. Fitted together on the first %.0f %% of the drive (%s), the model cuts the position RMSE on "
                "the rest from %.2f m to %.2f m (final error %.2f m -> %.2f m), delta BIC %.0f against the baseline.",
                named.empty() ? "No cause named" : "Causes (forward selection)", named.c_str(), 100.0 * o_.fit_fraction,
                parameters_text(last.parameters).c_str(), rep_.baseline_held_out_rmse, last.held_out_rmse,
                rep_.baseline_held_out_final, last.held_out_final, last.delta_bic);
  rep_.verdict = buf;
  if (also.empty()) return;
  std::snprintf(buf, sizeof buf, " Also consistent with %s: under %.3g %% of the held-out gain, not named as a cause.",
                also.c_str(), 100.0 * kNegligibleGainShare);
  rep_.verdict += buf;
}

void OdometryStudy::write_verdict() {
  char buf[1024];
  if (rep_.best < 0) {
    std::snprintf(buf, sizeof buf,
                  "No candidate explains the disagreement: none cuts the held-out RMSE (%.2f m) by %.0f %% and "
                  "%.2f m with a clear BIC gain.",
                  rep_.baseline_held_out_rmse, 100.0 * o_.min_gain, o_.min_improvement);
    rep_.verdict = buf;
    return;
  }
  if (rep_.selection.size() >= 2) {
    write_chain_verdict();
    return;
  }
  const auto& b = rep_.candidates[static_cast<std::size_t>(rep_.best)];
  const std::string params = parameters_text(b.parameters);
  std::snprintf(buf, sizeof buf,
                "Cause: %s (%s). Fitted on the first %.0f %% of the drive (%s), it cuts the position RMSE on the "
                "rest from %.2f m to %.2f m (final error %.2f m -> %.2f m).",
                b.name.c_str(), b.cause.c_str(), 100.0 * o_.fit_fraction, params.c_str(), rep_.baseline_held_out_rmse,
                b.held_out_rmse, rep_.baseline_held_out_final, b.held_out_final);
  rep_.verdict = buf;
  // A runner-up that also explains much of it is worth saying.
  int second = -1;
  for (std::size_t i = 0; i < rep_.candidates.size(); ++i) {
    if (static_cast<int>(i) == rep_.best || !rep_.candidates[i].significant) continue;
    if (second < 0 ||
        rep_.candidates[i].held_out_rmse < rep_.candidates[static_cast<std::size_t>(second)].held_out_rmse) {
      second = static_cast<int>(i);
    }
  }
  if (second >= 0) {
    const auto& c = rep_.candidates[static_cast<std::size_t>(second)];
    char more[256];
    std::snprintf(more, sizeof more,
                  " Runner-up: %s (held-out %.2f m); data with other manoeuvres would separate them.", c.name.c_str(),
                  c.held_out_rmse);
    rep_.verdict += more;
  }
  if (!rep_.selection.empty() && rep_.rejected_step) {
    const auto& r = *rep_.rejected_step;
    std::snprintf(buf, sizeof buf,
                  " Fitted together, %s change BIC by %.0f more and the held-out RMSE to %.2f m: this drive cannot "
                  "tell a second cause apart.",
                  r.name.c_str(), r.bic - rep_.selection.back().bic, r.held_out_rmse);
    rep_.verdict += buf;
  }
}

}  // namespace

OdometryDiscrepancyReport study_odometry(const log::Log& lg, const OdometryStudyOptions& o) {
  return OdometryStudy(lg, o).run();
}

}  // namespace roverlab::analysis

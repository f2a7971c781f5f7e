#include "core/analysis/odometry_discrepancy.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>

#include "core/common/error.h"
#include "core/estimation/reference_track.h"

namespace roverlab::analysis {

namespace {

using estimation::OdometryCorrections;
using estimation::ReferenceTrack;
using estimation::WheelSamples;

double wrap(double a) { return std::remainder(a, 2.0 * M_PI); }

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

double rmse_of(const std::vector<double>& r) {
  double s = 0.0;
  for (double x : r) s += x * x;
  return r.empty() ? 0.0 : std::sqrt(2.0 * s / static_cast<double>(r.size()));  // horizontal
}

double final_of(const std::vector<double>& r) {
  return r.size() < 2 ? 0.0 : std::hypot(r[r.size() - 2], r[r.size() - 1]);
}

// BIC of Gaussian residuals with k free parameters.
double bic(const std::vector<double>& r, int k) {
  double s = 0.0;
  for (double x : r) s += x * x;
  const double n = static_cast<double>(r.size());
  return n * std::log(std::max(s / n, 1e-300)) + k * std::log(n);
}

struct Spec {
  std::string name, cause;
  std::vector<std::string> names;
  std::vector<double> start, lower, upper;
  // Corrections from parameters; `held_out` is true for the test part.
  std::function<OdometryCorrections(const double*, bool held_out)> corrections;
};

struct TrackCost {
  const Spec* spec;
  const Part* part;
  const ReferenceTrack* ref;
  const estimation::SkidSteerGeometry* rover;
  bool operator()(double const* const* x, double* residuals) const {
    const auto r = track_errors(*part, *ref, *rover, spec->corrections(x[0], false));
    std::copy(r.begin(), r.end(), residuals);
    return true;
  }
};

}  // namespace

OdometryDiscrepancyReport study_odometry(const log::Log& lg, const OdometryStudyOptions& o) {
  const log::Stream& ws = lg.stream(o.wheels);
  for (const char* c : {"angle_FL", "angle_FR", "angle_RL", "angle_RR"}) {
    if (ws.find_channel(c) == nullptr) throw DataError("stream '" + o.wheels + "' has no channel '" + c + "'");
  }
  const ReferenceTrack ref = estimation::reference_from_gps(lg, o.reference);
  if (!ref.present) throw DataError("no reference track: stream '" + o.reference + "' with east and north is missing");
  const WheelSamples w = estimation::wheel_rates(ws.time(), ws.channel("angle_FL").values, ws.channel("angle_FR").values,
                                                 ws.channel("angle_RL").values, ws.channel("angle_RR").values);
  for (std::size_t i = 0; i < w.time.size(); ++i) {
    if (!std::isfinite(w.left_rate[i] + w.right_rate[i])) {
      throw DataError("stream '" + o.wheels + "': missing wheel angle near t = " + std::to_string(w.time[i]) + " s");
    }
  }

  OdometryDiscrepancyReport rep;
  const std::vector<double> dist = estimation::distance_along(ref);
  rep.distance = dist.back();
  if (rep.distance < 5.0) throw DataError("the reference track covers only " + std::to_string(rep.distance) + " m (need 5 m)");
  // Split where the driven distance reaches fit_fraction, within the wheel span.
  const double t_begin = std::max(ref.time.front(), w.time.front());
  const double t_end = std::min(ref.time.back(), w.time.back());
  std::size_t split = 0;
  while (split + 1 < dist.size() && dist[split] < o.fit_fraction * rep.distance) ++split;
  rep.split_time = ref.time[split];
  rep.fit_distance = dist[split];

  Part fit, test;
  fit.wheels = slice(w, t_begin, rep.split_time);
  test.wheels = slice(w, rep.split_time, t_end);
  for (std::size_t k = 0; k < ref.time.size(); ++k) {
    if (ref.time[k] < t_begin || ref.time[k] > t_end) continue;
    (ref.time[k] <= rep.split_time ? fit.ref : test.ref).push_back(k);
  }
  rep.fit_samples = fit.ref.size();
  rep.test_samples = test.ref.size();
  if (fit.ref.size() < 10 || test.ref.size() < 10 || fit.wheels.time.size() < 3 || test.wheels.time.size() < 3) {
    throw DataError("too few samples on one side of the split at t = " + std::to_string(rep.split_time) + " s");
  }
  // Start headings: the reference course over the first heading_distance
  // metres of each part.
  fit.heading0 = estimation::initial_course(ref, o.heading_distance, fit.ref.front());
  if (!std::isfinite(fit.heading0)) fit.heading0 = 0.0;
  const double course_split = estimation::initial_course(ref, o.heading_distance, test.ref.front());
  test.heading0 = std::isfinite(course_split) ? course_split : fit.heading0;

  // Baseline.
  const std::vector<double> base_fit = track_errors(fit, ref, o.rover, {});
  const std::vector<double> base_test = track_errors(test, ref, o.rover, {});
  rep.baseline_fit_rmse = rmse_of(base_fit);
  rep.baseline_held_out_rmse = rmse_of(base_test);
  rep.baseline_held_out_final = final_of(base_test);
  rep.baseline_bic = bic(base_fit, 0);
  {
    const auto tr = estimation::dead_reckon(fit.wheels, o.rover, {}, 0.0, 0.0, fit.heading0);
    double odo = 0.0;
    for (std::size_t i = 1; i < tr.time.size(); ++i) {
      odo += std::hypot(tr.east[i] - tr.east[i - 1], tr.north[i] - tr.north[i - 1]);
    }
    rep.distance_ratio = rep.fit_distance > 0 ? odo / rep.fit_distance : NAN;
    const double course = estimation::course_at(ref, tr.time.back());
    rep.heading_error_end = std::isfinite(course) ? wrap(tr.heading.back() - course) : NAN;
    // Along- and cross-track components against the reference course.
    double sa = 0, sc = 0;
    std::size_t n = 0;
    for (std::size_t j = 0; j < fit.ref.size(); ++j) {
      const double c = estimation::course_at(ref, ref.time[fit.ref[j]]);
      if (!std::isfinite(c)) continue;
      const double de = base_fit[2 * j], dn = base_fit[2 * j + 1];
      const double along = de * std::sin(c) + dn * std::cos(c);
      const double cross = de * std::cos(c) - dn * std::sin(c);
      sa += along * along;
      sc += cross * cross;
      ++n;
    }
    rep.along_track_rmse = n ? std::sqrt(sa / n) : NAN;
    rep.cross_track_rmse = n ? std::sqrt(sc / n) : NAN;
  }

  // Candidates.
  std::vector<Spec> specs;
  specs.push_back({"radius scale", "the wheels roll a different distance per turn than the nominal radius says, on both sides (effective radius, or a steady slip)",
                   {"radius_scale"}, {1.0}, {0.5}, {1.5},
                   [](const double* x, bool) {
                     OdometryCorrections c;
                     c.radius_scale = x[0];
                     return c;
                   }});
  specs.push_back({"per-side scale",
                   "the left and right wheels roll different distances per turn (radius, tyre or encoder scale per side)",
                   {"left_scale", "right_scale"}, {1.0, 1.0}, {0.5, 0.5}, {1.5, 1.5},
                   [](const double* x, bool) {
                     OdometryCorrections c;
                     c.left_scale = x[0];
                     c.right_scale = x[1];
                     return c;
                   }});
  specs.push_back({"turning track",
                   "skid-steer turning: the wheels skid, so the rover turns less than the wheel-speed difference says",
                   {"track_factor"}, {1.2}, {0.3}, {6.0},
                   [](const double* x, bool) {
                     OdometryCorrections c;
                     c.track_factor = x[0];
                     return c;
                   }});
  specs.push_back({"time offset", "the wheel and reference clocks disagree by a constant offset", {"time_offset_s"},
                   {0.0}, {-2.0}, {2.0},
                   [](const double* x, bool) {
                     OdometryCorrections c;
                     c.time_offset = x[0];
                     return c;
                   }});
  // Slip episodes: one slip value per window of the fit part; the test part
  // can only use their median (episodes are not predictable).
  const double fit_span = fit.wheels.time.back() - fit.wheels.time.front();
  const int windows = std::max(1, static_cast<int>(std::ceil(fit_span / o.slip_window)));
  {
    Spec s{"slip episodes", "the wheels slip by different amounts over the drive (terrain changes)", {}, {}, {}, {}, {}};
    for (int k = 0; k < windows; ++k) {
      s.names.push_back("slip_" + std::to_string(k));
      s.start.push_back(0.0);
      s.lower.push_back(-0.5);
      s.upper.push_back(0.9);
    }
    const WheelSamples* fw = &fit.wheels;
    const std::size_t test_n = test.wheels.time.size();
    const double window = o.slip_window;
    s.corrections = [fw, test_n, windows, window](const double* x, bool held_out) {
      OdometryCorrections c;
      if (held_out) {
        std::vector<double> v(x, x + windows);
        std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
        c.slip.assign(test_n, v[v.size() / 2]);
      } else {
        c.slip.resize(fw->time.size());
        for (std::size_t i = 0; i < c.slip.size(); ++i) {
          const int k = std::min(windows - 1, static_cast<int>((fw->time[i] - fw->time.front()) / window));
          c.slip[i] = x[k];
        }
      }
      return c;
    };
    specs.push_back(std::move(s));
  }

  for (const Spec& spec : specs) {
    OdometryCandidate cand;
    cand.name = spec.name;
    cand.cause = spec.cause;
    const int k = static_cast<int>(spec.start.size());
    cand.parameter_count = k;
    std::vector<double> x = spec.start;
    ceres::Problem problem;
    auto* cost = new ceres::DynamicNumericDiffCostFunction<TrackCost, ceres::CENTRAL>(
        new TrackCost{&spec, &fit, &ref, &o.rover});
    cost->AddParameterBlock(k);
    cost->SetNumResiduals(static_cast<int>(2 * fit.ref.size()));
    problem.AddResidualBlock(cost, nullptr, x.data());
    for (int i = 0; i < k; ++i) {
      problem.SetParameterLowerBound(x.data(), i, spec.lower[static_cast<std::size_t>(i)]);
      problem.SetParameterUpperBound(x.data(), i, spec.upper[static_cast<std::size_t>(i)]);
    }
    ceres::Solver::Options so;
    so.linear_solver_type = ceres::DENSE_QR;
    so.max_num_iterations = 100;
    so.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(so, &problem, &summary);
    const std::vector<double> r_fit = track_errors(fit, ref, o.rover, spec.corrections(x.data(), false));
    cand.fit_rmse = rmse_of(r_fit);
    cand.bic = bic(r_fit, k);
    cand.delta_bic = cand.bic - rep.baseline_bic;
    // Parameter sigmas from the covariance, scaled by the residual variance
    // (optimistic: track errors are correlated in time).
    std::vector<double> sigma(static_cast<std::size_t>(k), NAN);
    if (k <= 3) {
      ceres::Covariance::Options co;
      co.algorithm_type = ceres::DENSE_SVD;
      co.null_space_rank = -1;
      ceres::Covariance cov(co);
      std::vector<std::pair<const double*, const double*>> blocks{{x.data(), x.data()}};
      std::vector<double> c(static_cast<std::size_t>(k * k), NAN);
      if (cov.Compute(blocks, &problem) && cov.GetCovarianceBlock(x.data(), x.data(), c.data())) {
        double s2 = 0.0;
        for (double v : r_fit) s2 += v * v;
        s2 /= std::max<double>(1.0, static_cast<double>(r_fit.size()) - k);
        for (int i = 0; i < k; ++i) sigma[static_cast<std::size_t>(i)] = std::sqrt(std::max(0.0, c[static_cast<std::size_t>(i * k + i)] * s2));
      }
    }
    if (spec.name == "slip episodes") {
      std::vector<double> v = x;
      std::sort(v.begin(), v.end());
      cand.parameters.push_back({"windows", static_cast<double>(k), NAN});
      cand.parameters.push_back({"median_slip", v[v.size() / 2], NAN});
      cand.parameters.push_back({"min_slip", v.front(), NAN});
      cand.parameters.push_back({"max_slip", v.back(), NAN});
    } else {
      for (int i = 0; i < k; ++i) {
        cand.parameters.push_back({spec.names[static_cast<std::size_t>(i)], x[static_cast<std::size_t>(i)],
                                   sigma[static_cast<std::size_t>(i)]});
      }
    }
    const std::vector<double> r_test = track_errors(test, ref, o.rover, spec.corrections(x.data(), true));
    cand.held_out_rmse = rmse_of(r_test);
    cand.held_out_final = final_of(r_test);
    cand.significant = cand.delta_bic < -10.0 &&
                       cand.held_out_rmse <= (1.0 - o.min_gain) * rep.baseline_held_out_rmse &&
                       cand.held_out_rmse <= rep.baseline_held_out_rmse - o.min_improvement;
    rep.candidates.push_back(std::move(cand));
  }

  // The named cause: among the significant candidates, the best held-out
  // RMSE; held-out RMSEs within 10 % or min_improvement of each other count
  // as equal, and then the candidate with fewer parameters wins.
  for (std::size_t i = 0; i < rep.candidates.size(); ++i) {
    const auto& c = rep.candidates[i];
    if (!c.significant) continue;
    if (rep.best < 0) {
      rep.best = static_cast<int>(i);
      continue;
    }
    const auto& b = rep.candidates[static_cast<std::size_t>(rep.best)];
    const double tie = std::max(0.1 * b.held_out_rmse, o.min_improvement);
    const bool equal = std::abs(c.held_out_rmse - b.held_out_rmse) < tie;
    if (equal ? c.parameter_count < b.parameter_count : c.held_out_rmse < b.held_out_rmse) rep.best = static_cast<int>(i);
  }

  char buf[512];
  std::snprintf(buf, sizeof buf,
                "On the fit part (%.1f m) wheel odometry has %.2f m RMSE: %.2f m along track, %.2f m across; "
                "it measures %.1f %% of the distance and ends %.1f deg off the reference course.",
                rep.fit_distance, rep.baseline_fit_rmse, rep.along_track_rmse, rep.cross_track_rmse,
                100.0 * rep.distance_ratio, rep.heading_error_end * 180.0 / M_PI);
  rep.what_is_wrong = buf;
  if (rep.best < 0) {
    std::snprintf(buf, sizeof buf,
                  "No candidate explains the disagreement: none cuts the held-out RMSE (%.2f m) by %.0f %% and "
                  "%.2f m with a clear BIC gain.",
                  rep.baseline_held_out_rmse, 100.0 * o.min_gain, o.min_improvement);
  } else {
    const auto& b = rep.candidates[static_cast<std::size_t>(rep.best)];
    std::string params;
    for (const auto& p : b.parameters) {
      char one[96];
      std::snprintf(one, sizeof one, "%s%s = %.4g", params.empty() ? "" : ", ", p.name.c_str(), p.value);
      params += one;
    }
    std::snprintf(buf, sizeof buf,
                  "Cause: %s (%s). Fitted on the first %.0f %% of the drive (%s), it cuts the position RMSE on the "
                  "rest from %.2f m to %.2f m (final error %.2f m -> %.2f m).",
                  b.name.c_str(), b.cause.c_str(), 100.0 * o.fit_fraction, params.c_str(), rep.baseline_held_out_rmse,
                  b.held_out_rmse, rep.baseline_held_out_final, b.held_out_final);
    // A runner-up that also explains much of it is worth saying.
    int second = -1;
    for (std::size_t i = 0; i < rep.candidates.size(); ++i) {
      if (static_cast<int>(i) == rep.best || !rep.candidates[i].significant) continue;
      if (second < 0 || rep.candidates[i].held_out_rmse < rep.candidates[static_cast<std::size_t>(second)].held_out_rmse) {
        second = static_cast<int>(i);
      }
    }
    if (second >= 0) {
      const auto& c = rep.candidates[static_cast<std::size_t>(second)];
      char more[256];
      std::snprintf(more, sizeof more, " Runner-up: %s (held-out %.2f m); data with other manoeuvres would separate them.",
                    c.name.c_str(), c.held_out_rmse);
      rep.verdict = std::string(buf) + more;
      return rep;
    }
  }
  rep.verdict = buf;
  return rep;
}

}  // namespace roverlab::analysis

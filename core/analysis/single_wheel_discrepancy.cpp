#include "core/analysis/single_wheel_discrepancy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/common/error.h"

namespace roverlab::analysis {

using namespace roverlab::terramechanics;

namespace {

struct Line {
  double slope = 0.0, t = 0.0;
};

// Least-squares slope of y on x with its t statistic.
Line regress(const std::vector<double>& x, const std::vector<double>& y) {
  const std::size_t n = x.size();
  if (n < 3) return {};
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < n; ++i) {
    mx += x[i];
    my += y[i];
  }
  mx /= static_cast<double>(n);
  my /= static_cast<double>(n);
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  if (sxx <= 0.0) return {};
  Line l;
  l.slope = sxy / sxx;
  double sse = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = y[i] - my - l.slope * (x[i] - mx);
    sse += e * e;
  }
  const double se = std::sqrt(sse / static_cast<double>(n - 2) / sxx);
  l.t = se > 0.0 ? l.slope / se : (l.slope != 0.0 ? std::copysign(1e9, l.slope) : 0.0);
  return l;
}

double score_of(const std::vector<PointResidual>& residuals, double* rss_out = nullptr,
                std::size_t* m_out = nullptr) {
  double rss = 0.0;
  std::size_t m = 0;
  for (const auto& r : residuals) {
    const double z = (r.predicted - r.measured) / r.sigma;
    if (!std::isfinite(z)) continue;
    rss += z * z;
    ++m;
  }
  if (rss_out) *rss_out = rss;
  if (m_out) *m_out = m;
  return m > 0 ? std::sqrt(rss / static_cast<double>(m)) : NAN;
}

// BIC with the residual variance estimated (Gaussian): m ln(RSS/m) + k ln m.
double bic_of(const std::vector<PointResidual>& residuals, std::size_t k) {
  double rss = 0.0;
  std::size_t m = 0;
  score_of(residuals, &rss, &m);
  if (m == 0) return NAN;
  const double md = static_cast<double>(m);
  return md * std::log(std::max(rss, 1e-300) / md) + static_cast<double>(k) * std::log(md);
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
    case Quantity::drawbar_pull: return "drawbar pull";
    case Quantity::torque: return "torque";
    case Quantity::sinkage: return "sinkage";
  }
  return "?";
}

// A candidate cause: the extension it switches on and the parameters it
// fits (a negative start keeps the soil's own value as the start).
struct CandidateSpec {
  const char* name;
  const char* cause;
  std::vector<std::pair<Parameter, double>> parameters;
  bool needs_grousers;
  void (*configure)(Extensions&);
};

const CandidateSpec kCandidates[] = {
    // Ding et al. 2011: n = n0 + n1 |s|; n0 is refitted with n1 since the
    // static exponent is what the slip term grows from.
    {"slip-sinkage", "sinkage grows with slip and the static model cannot follow it",
     {{Parameter::slip_sinkage_n1, 0.0}, {Parameter::n, -1.0}}, false, [](Extensions&) {}},
    {"grousers", "the grousered wheel pulls more than the smooth-wheel model predicts",
     {{Parameter::grouser_effectiveness, 0.5}}, true, [](Extensions& e) { e.grousers = true; }},
    {"bulldozing", "soil pushed ahead of the wheel resists its motion",
     {{Parameter::bulldozing_scale, 1.0}}, false, [](Extensions& e) { e.bulldozing = true; }},
    {"soil-strength", "the soil is uniformly weaker or stronger than its description",
     {{Parameter::soil_strength, 1.0}}, false, [](Extensions&) {}},
};

}  // namespace

std::vector<QuantityResiduals> residual_statistics(const std::vector<PointResidual>& residuals,
                                                   const std::vector<WheelTestPoint>& points) {
  std::vector<QuantityResiduals> out;
  for (Quantity q : kQuantities) {
    std::vector<double> e, slip, load;
    for (const auto& r : residuals) {
      if (r.quantity != q || !std::isfinite(r.predicted)) continue;
      e.push_back(r.predicted - r.measured);
      slip.push_back(points[r.point].slip);
      load.push_back(points[r.point].load);
    }
    if (e.empty()) continue;
    QuantityResiduals s;
    s.quantity = q;
    s.count = e.size();
    for (double v : e) {
      s.bias += v;
      s.rmse += v * v;
    }
    s.bias /= static_cast<double>(e.size());
    s.rmse = std::sqrt(s.rmse / static_cast<double>(e.size()));
    const Line ls = regress(slip, e), ll = regress(load, e);
    s.slope_vs_slip = ls.slope;
    s.t_slip = ls.t;
    s.slope_vs_load = ll.slope;
    s.t_load = ll.t;
    out.push_back(s);
  }
  return out;
}

DiscrepancyReport study_single_wheel(const Soil& soil, const std::vector<WheelTestPoint>& points,
                                     const DiscrepancyOptions& options) {
  if (points.empty()) throw DataError("no single-wheel points");
  DiscrepancyReport report;
  report.points = points.size();
  for (Quantity q : kQuantities) {
    if (std::any_of(points.begin(), points.end(), [&](const auto& p) { return p.measured(q).has_value(); })) {
      report.quantities.push_back(q);
    }
  }
  if (report.quantities.empty()) throw DataError("no measured drawbar pull, torque or sinkage");

  IdentificationOptions base;
  base.model = options.baseline;
  base.sigma = options.sigma;
  const IdentificationResult baseline = identify_soil(soil, points, base);  // nothing free: predictions
  report.baseline = residual_statistics(baseline.residuals, points);
  report.baseline_score = score_of(baseline.residuals);
  report.baseline_bic = bic_of(baseline.residuals, 0);
  report.measurements = baseline.measurements;
  for (const auto& r : baseline.residuals) report.unsupported += std::isfinite(r.predicted) ? 0 : 1;
  auto rmse_of = [](const std::vector<QuantityResiduals>& stats, Quantity q) -> double {
    for (const auto& s : stats) {
      if (s.quantity == q) return s.rmse;
    }
    return NAN;
  };
  for (Quantity q : report.quantities) report.baseline_held_out_rmse.push_back(rmse_of(report.baseline, q));

  const bool any_grousers = std::any_of(points.begin(), points.end(), [](const auto& p) {
    return p.wheel.grouser_count > 0 && p.wheel.grouser_height > 0.0;
  });

  for (const auto& spec : kCandidates) {
    CandidateResult c;
    c.name = spec.name;
    c.cause = spec.cause;
    if (spec.needs_grousers && !any_grousers) {
      c.applicable = false;
      c.not_applicable_because = "no wheel in the data has grousers";
      report.candidates.push_back(c);
      continue;
    }
    IdentificationOptions io;
    io.model = options.baseline;
    spec.configure(io.model.extensions);
    io.sigma = options.sigma;
    Soil start = soil;
    for (const auto& [parameter, value] : spec.parameters) {
      io.free.push_back(parameter);
      if (value >= 0.0) set_parameter(start, io.model.extensions, parameter, value);
    }
    c.fit = identify_soil(start, points, io);
    c.in_sample = residual_statistics(c.fit.residuals, points);
    c.bic = bic_of(c.fit.residuals, io.free.size());
    c.delta_bic = c.bic - report.baseline_bic;

    // Leave-one-out: refit without each point, predict it.
    std::vector<PointResidual> held_out;
    if (options.leave_one_out) {
      IdentificationOptions lo = io;
      lo.model.extensions = c.fit.extensions;
      for (std::size_t i = 0; i < points.size(); ++i) {
        std::vector<WheelTestPoint> train;
        train.reserve(points.size() - 1);
        for (std::size_t j = 0; j < points.size(); ++j) {
          if (j != i) train.push_back(points[j]);
        }
        const IdentificationResult f = identify_soil(c.fit.soil, train, lo);
        IdentificationOptions predict_only;
        predict_only.model = lo.model;
        predict_only.model.extensions = f.extensions;
        predict_only.sigma = options.sigma;
        const IdentificationResult pred = identify_soil(f.soil, {points[i]}, predict_only);
        for (auto r : pred.residuals) {
          r.point = i;
          held_out.push_back(r);
        }
      }
    } else {
      held_out = c.fit.residuals;
    }
    const auto held_stats = residual_statistics(held_out, points);
    for (Quantity q : report.quantities) c.held_out_rmse.push_back(rmse_of(held_stats, q));
    c.held_out_score = score_of(held_out);
    report.candidates.push_back(std::move(c));
  }

  // The winner: lowest BIC among applicable candidates.
  double best_bic = INFINITY;
  for (std::size_t i = 0; i < report.candidates.size(); ++i) {
    const auto& c = report.candidates[i];
    if (!c.applicable || !std::isfinite(c.bic)) continue;
    if (c.bic < best_bic) {
      best_bic = c.bic;
      report.best = static_cast<int>(i);
    }
  }
  if (report.best >= 0) {
    const auto& c = report.candidates[static_cast<std::size_t>(report.best)];
    report.significant = c.delta_bic < options.bic_threshold &&
                         c.held_out_score < (1.0 - options.min_held_out_gain) * report.baseline_score;
  }

  // What the baseline gets wrong, in one sentence.
  const QuantityResiduals* worst = nullptr;
  for (const auto& s : report.baseline) {
    if (worst == nullptr || s.rmse / options.sigma.of(s.quantity) > worst->rmse / options.sigma.of(worst->quantity)) {
      worst = &s;
    }
  }
  if (report.baseline_score <= 1.5) {
    report.what_is_wrong = "The baseline Wong-Reece model fits every measured quantity within about its measurement error (RMS " +
                           fmt("%.2f", report.baseline_score) + " sigma).";
  } else {
    std::string s = "The baseline Wong-Reece model " +
                    std::string(worst->bias > 0 ? "over-predicts " : "under-predicts ") +
                    words(worst->quantity) + " by " + show(worst->quantity, std::abs(worst->bias)) +
                    " on average (RMSE " + show(worst->quantity, worst->rmse) + ")";
    if (std::abs(worst->t_slip) >= 3.0) {
      s += ", and the error " + std::string(worst->slope_vs_slip * worst->bias > 0 ? "grows" : "changes") +
           " with slip (" + (worst->slope_vs_slip > 0 ? "+" : "-") +
           show(worst->quantity, std::abs(worst->slope_vs_slip)) + " per unit slip)";
    } else if (std::abs(worst->t_load) >= 3.0) {
      s += ", and the error changes with load (" + std::string(worst->slope_vs_load > 0 ? "+" : "-") +
           show(worst->quantity, std::abs(worst->slope_vs_load) * 100.0) + " per 100 N)";
    }
    // Other quantities with a strong slip trend (|t| >= 5) are named too.
    for (const auto& o : report.baseline) {
      if (&o == worst || std::abs(o.t_slip) < 5.0) continue;
      s += "; its " + words(o.quantity) + " error trends with slip (" + (o.slope_vs_slip > 0 ? "+" : "-") +
           show(o.quantity, std::abs(o.slope_vs_slip)) + " per unit slip, t = " + fmt("%.1f", o.t_slip) +
           (o.slope_vs_slip < 0 ? ": measured " + words(o.quantity) + " grows faster with slip than predicted"
                                : ": predicted " + words(o.quantity) + " grows faster with slip than measured") +
           ")";
    }
    report.what_is_wrong = s + ".";
  }

  // Per quantity: the candidate that best predicts it on held-out points, when
  // it cuts that quantity's held-out RMSE by at least 30 %.
  for (std::size_t qi = 0; qi < report.quantities.size(); ++qi) {
    int best_q = -1;
    for (std::size_t i = 0; i < report.candidates.size(); ++i) {
      const auto& c = report.candidates[i];
      if (!c.applicable || !std::isfinite(c.held_out_rmse[qi])) continue;
      if (best_q < 0 || c.held_out_rmse[qi] < report.candidates[static_cast<std::size_t>(best_q)].held_out_rmse[qi]) {
        best_q = static_cast<int>(i);
      }
    }
    if (best_q >= 0 && report.candidates[static_cast<std::size_t>(best_q)].held_out_rmse[qi] <
                           0.7 * report.baseline_held_out_rmse[qi]) {
      report.partial.push_back({report.quantities[qi], best_q});
    }
  }

  if (report.significant) {
    const auto& c = report.candidates[static_cast<std::size_t>(report.best)];
    std::string v = "Cause: " + c.name + " (" + c.cause + "),";
    for (const auto& p : c.fit.parameters) {
      v += " " + std::string(to_string(p.parameter)) + " = " + fmt("%.3g", p.value) + " +- " + fmt("%.2g", p.sigma) + ";";
    }
    v += " held-out RMSE";
    for (std::size_t i = 0; i < report.quantities.size(); ++i) {
      v += std::string(i ? "," : "") + " " + words(report.quantities[i]) + " " +
           show(report.quantities[i], report.baseline_held_out_rmse[i]) + " -> " +
           show(report.quantities[i], c.held_out_rmse[i]);
    }
    v += "; delta BIC " + fmt("%.1f", c.delta_bic) + ".";
    report.verdict = v;
  } else if (report.best >= 0) {
    const auto& c = report.candidates[static_cast<std::size_t>(report.best)];
    report.verdict = "No significant discrepancy: the best candidate, " + c.name + ", changes BIC by " +
                     fmt("%.1f", c.delta_bic) + " (needs < " + fmt("%.0f", options.bic_threshold) +
                     ") and the held-out error from " + fmt("%.2f", report.baseline_score) + " to " +
                     fmt("%.2f", c.held_out_score) + " sigma";
    for (const auto& [q, index] : report.partial) {
      const std::size_t qi = static_cast<std::size_t>(
          std::find(report.quantities.begin(), report.quantities.end(), q) - report.quantities.begin());
      const auto& pc = report.candidates[static_cast<std::size_t>(index)];
      report.verdict += "; for " + words(q) + " alone, " + pc.name + " cuts the held-out RMSE from " +
                        show(q, report.baseline_held_out_rmse[qi]) + " to " + show(q, pc.held_out_rmse[qi]);
    }
    report.verdict += ".";
  } else {
    report.verdict = "No candidate could be fitted.";
  }
  return report;
}

}  // namespace roverlab::analysis

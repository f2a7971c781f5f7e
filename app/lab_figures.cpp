#include "app/lab_figures.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <set>
#include <utility>

#include "app/command_support.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "importers/soil_file.h"

namespace roverlab::app {

using terramechanics::PointResidual;
using terramechanics::Quantity;
using terramechanics::WheelTestPoint;

namespace {

constexpr int kCurvePoints = 61;

std::string number(double v, const char* format = "%g") {
  char text[48];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

double degrees_2dp(double rad) { return std::round(rad * 180.0 / M_PI * 100.0) / 100.0; }

// The model's value of `q` (NaN where it cannot carry the load).
double value_of(const terramechanics::SlipAngleTraction& t, Quantity q) {
  if (!t.ok()) return NAN;
  switch (q) {
    case Quantity::drawbar_pull:
      return t.drawbar_pull;
    case Quantity::torque:
      return t.resistive_torque;
    case Quantity::sinkage:
      return t.sinkage;
    case Quantity::lateral_force:
      return t.lateral_force;
  }
  return NAN;
}

terramechanics::SlipAngleTraction predict(const SingleWheelModel& m, const WheelTestPoint& p) {
  terramechanics::GridModel model = m.model;
  model.wheel = p.wheel;
  return terramechanics::model_at(model, p.load, p.slip, m.at_slip_angle ? std::optional(p.slip_angle) : std::nullopt);
}

// Each measured quantity of each point against the model (nothing fitted: held out by construction).
std::vector<PointResidual> residuals_of(const SingleWheelModel& m, const std::vector<WheelTestPoint>& points) {
  const terramechanics::MeasurementSigma sigma;
  std::vector<PointResidual> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const terramechanics::SlipAngleTraction t = predict(m, points[i]);
    for (Quantity q : terramechanics::kQuantities) {
      if (const auto measured = points[i].measured(q)) out.push_back({i, q, *measured, value_of(t, q), sigma.of(q)});
    }
  }
  return out;
}

// Sum of squared residuals in sigmas (a point the model cannot carry counts 100 sigma^2).
double score(const std::vector<PointResidual>& residuals) {
  double sum = 0.0;
  for (const auto& r : residuals) {
    const double z = (r.predicted - r.measured) / r.sigma;
    sum += std::isfinite(z) ? z * z : 100.0;
  }
  return sum;
}

const char* quantity_words(Quantity q) { return q == Quantity::drawbar_pull ? "drawbar pull" : "lateral force"; }

// A wheel tested at more loads than this (to 0.1 N) has its loads binned
// into kLoadBins groups of about equal numbers of points: a file of jittered
// loads would otherwise draw a curve and a key entry per row.
constexpr std::size_t kMaxLoadsPerWheel = 6;
constexpr std::size_t kLoadBins = 4;

// The points' groups: one per wheel and load (0.1 N), or per wheel and load
// bin, in order of first appearance.
struct Groups {
  std::vector<int> of_point;
  std::vector<std::string> names;
  std::vector<std::size_t> first_point;  // a point of each group (its wheel)
  std::vector<double> load;              // the load its curve is drawn at: its points' (median when binned)
  std::size_t binned_wheels = 0;
};

// Each point's load bin within its wheel: -1 where the wheel's loads are few
// enough to be shown one by one; else 0..kLoadBins-1, cut at the quantiles of
// the wheel's loads.
std::vector<int> load_bins(const std::vector<WheelTestPoint>& points, std::size_t& binned_wheels) {
  std::map<std::string, std::vector<double>> loads;
  for (const auto& p : points) loads[p.wheel_label].push_back(p.load);
  std::map<std::string, std::vector<double>> cuts;  // the upper edges of bins 0..kLoadBins-2
  for (auto& [label, l] : loads) {
    std::set<long> distinct;
    for (double v : l) distinct.insert(std::lround(v * 10.0));
    if (distinct.size() <= kMaxLoadsPerWheel) continue;
    std::sort(l.begin(), l.end());
    auto& c = cuts[label];
    for (std::size_t k = 1; k < kLoadBins; ++k) c.push_back(l[k * l.size() / kLoadBins]);
    ++binned_wheels;
  }
  std::vector<int> bin(points.size(), -1);
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto it = cuts.find(points[i].wheel_label);
    if (it == cuts.end()) continue;
    bin[i] =
        static_cast<int>(std::upper_bound(it->second.begin(), it->second.end(), points[i].load) - it->second.begin());
  }
  return bin;
}

Groups groups_of(const std::vector<WheelTestPoint>& points) {
  Groups g;
  const std::vector<int> bin = load_bins(points, g.binned_wheels);
  std::map<std::string, std::size_t> wheel_order;  // wheels as first seen
  for (const auto& p : points) wheel_order.emplace(p.wheel_label, wheel_order.size());
  // A group's key: its wheel and its load bin, or its load to 0.1 N.
  const auto key_of = [&](std::size_t i) {
    return std::make_pair(wheel_order.at(points[i].wheel_label),
                          bin[i] >= 0 ? static_cast<long>(bin[i]) : std::lround(points[i].load * 10.0));
  };
  // Groups numbered in order of first appearance; by wheel, then by load,
  // when a wheel's loads are binned (the bins are met in any order).
  std::map<std::pair<std::size_t, long>, int> index;
  if (g.binned_wheels > 0) {
    for (std::size_t i = 0; i < points.size(); ++i) index.emplace(key_of(i), 0);
    int k = 0;
    for (auto& entry : index) entry.second = k++;
  }
  for (std::size_t i = 0; i < points.size(); ++i) {
    g.of_point.push_back(index.emplace(key_of(i), static_cast<int>(index.size())).first->second);
  }
  g.names.resize(index.size());
  g.load.resize(index.size());
  g.first_point.resize(index.size());
  for (std::size_t i = points.size(); i-- > 0;) g.first_point[static_cast<std::size_t>(g.of_point[i])] = i;
  // Names: the load, or a bin's range of loads; the curve at a bin's median load.
  for (std::size_t k = 0; k < g.names.size(); ++k) {
    const WheelTestPoint& first = points[g.first_point[k]];
    std::string load = number(first.load, "%.3g") + " N";
    g.load[k] = first.load;
    if (bin[g.first_point[k]] >= 0) {
      std::vector<double> l;
      for (std::size_t i = 0; i < points.size(); ++i) {
        if (g.of_point[i] == static_cast<int>(k)) l.push_back(points[i].load);
      }
      std::sort(l.begin(), l.end());
      g.load[k] = l[l.size() / 2];
      load = number(l.front(), "%.3g") + "-" + number(l.back(), "%.3g") + " N";
    }
    const std::string label = first.wheel_label.empty() ? "wheel" : first.wheel_label;
    g.names[k] = wheel_order.size() > 1 || !first.wheel_label.empty() ? label + ", " + load : load;
  }
  return g;
}

// The slip angles (deg, to 0.01) of the points measuring `q`.
std::set<double> angles_measuring(const std::vector<WheelTestPoint>& points, Quantity q) {
  std::set<double> angles;
  for (const auto& p : points) {
    if (p.measured(q)) angles.insert(degrees_2dp(p.slip_angle));
  }
  return angles;
}

// One row of the slip panels: `q` against slip, a panel per slip angle, each
// group's points and the model's curve at its wheel and load, +-2 sigma around it.
views::PanelRow slip_row(const std::vector<WheelTestPoint>& points, const SingleWheelModel& m, const Groups& groups,
                         Quantity q, double band) {
  views::PanelRow row;
  row.y_title = std::string(quantity_words(q)) + " (N)";
  double slip_lo = 1.0, slip_hi = -1.0;
  for (const auto& p : points) {
    slip_lo = std::min(slip_lo, p.slip);
    slip_hi = std::max(slip_hi, p.slip);
  }
  for (double angle : angles_measuring(points, q)) {
    views::Panel panel;
    panel.title = "slip angle " + number(angle) + " deg";
    for (std::size_t g = 0; g < groups.names.size(); ++g) {
      views::PanelSeries s;
      s.group = static_cast<int>(g);
      s.band = band;
      for (std::size_t i = 0; i < points.size(); ++i) {
        const auto v = points[i].measured(q);
        if (!v || groups.of_point[i] != s.group || degrees_2dp(points[i].slip_angle) != angle) continue;
        s.x.push_back(points[i].slip);
        s.y.push_back(*v);
      }
      if (s.x.empty()) continue;
      terramechanics::GridModel model = m.model;
      model.wheel = points[groups.first_point[g]].wheel;
      const double beta = angle * M_PI / 180.0;
      const terramechanics::ModelCurve c = terramechanics::model_curve(
          model, groups.load[g], m.at_slip_angle ? std::optional(beta) : std::nullopt, slip_lo, slip_hi, kCurvePoints);
      s.curve_x = c.slip;
      for (const auto& t : c.traction) s.curve_y.push_back(value_of(t, q));
      panel.series.push_back(std::move(s));
    }
    row.panels.push_back(std::move(panel));
  }
  return row;
}

// One row of the residuals figure: measured - predicted of `q` against slip
// angle (against slip when `by_slip`: a file at one slip angle), per group,
// over a zero line with its +-2 sigma band.
views::PanelRow residual_row(const std::vector<WheelTestPoint>& points, const SingleWheelModel& m, const Groups& groups,
                             Quantity q, double band, bool by_slip) {
  views::Panel panel;
  panel.title = quantity_words(q);
  std::vector<views::PanelSeries> by_group(groups.names.size());
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& r : m.held_out) {
    if (r.quantity != q || r.point >= points.size() || !std::isfinite(r.predicted)) continue;
    const double x = by_slip ? points[r.point].slip : degrees_2dp(points[r.point].slip_angle);
    views::PanelSeries& s = by_group[static_cast<std::size_t>(groups.of_point[r.point])];
    s.group = groups.of_point[r.point];
    s.x.push_back(x);
    s.y.push_back(r.measured - r.predicted);
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  views::PanelSeries zero;
  zero.group = -1;  // grey
  zero.band = band;
  for (int k = 0; k <= 10; ++k) {
    zero.curve_x.push_back(lo + (hi - lo) * k / 10.0);
    zero.curve_y.push_back(0.0);
  }
  if (lo <= hi) panel.series.push_back(zero);
  for (auto& s : by_group) {
    if (!s.x.empty()) panel.series.push_back(std::move(s));
  }
  views::PanelRow row;
  row.y_title = "measured - predicted (N)";
  row.panels.push_back(std::move(panel));
  return row;
}

std::string band_text(Quantity q, double band) {
  return std::string(quantity_words(q)) + (std::isfinite(band) ? " +-" + number(band, "%.2g") + " N" : " (none)");
}

}  // namespace

double rms_residual(const std::vector<PointResidual>& residuals, Quantity q) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const auto& r : residuals) {
    if (r.quantity != q || !std::isfinite(r.predicted) || !std::isfinite(r.measured)) continue;
    sum += (r.measured - r.predicted) * (r.measured - r.predicted);
    ++n;
  }
  return n > 0 ? std::sqrt(sum / static_cast<double>(n)) : NAN;
}

SingleWheelModel baseline_single_wheel_model(const terramechanics::Soil& soil,
                                             const std::vector<WheelTestPoint>& points) {
  using terramechanics::ModelKind;
  using terramechanics::SlipDefinition;
  const bool at_angle = std::any_of(points.begin(), points.end(),
                                    [](const WheelTestPoint& p) { return p.slip_angle != 0.0 || p.lateral_force; });
  SingleWheelModel best;
  double best_score = std::numeric_limits<double>::infinity();
  for (SlipDefinition d : {SlipDefinition::longitudinal, SlipDefinition::travel}) {
    if (!at_angle && d == SlipDefinition::travel) continue;  // no slip angle: the two readings agree
    SingleWheelModel m;
    m.model.soil = soil;
    m.model.options.kind = at_angle ? ModelKind::ishigami : ModelKind::wong_reece;
    m.model.options.slip_definition = d;
    m.at_slip_angle = at_angle;
    m.held_out = residuals_of(m, points);
    m.held_out_method = "nothing fitted";
    m.name = std::string("baseline ") + (at_angle ? "Ishigami (slip angle)" : "Wong-Reece") + " on " + soil.name;
    if (at_angle) m.name += std::string(", ") + terramechanics::to_string(d) + " slip";
    if (const double s = score(m.held_out); s < best_score) {
      best_score = s;
      best = std::move(m);
    }
  }
  if (at_angle) best.name += " (the reading nearer the points)";
  return best;
}

SingleWheelModel final_single_wheel_model(const terramechanics::Soil& soil, const std::vector<WheelTestPoint>& points,
                                          const analysis::DiscrepancyReport& r) {
  using terramechanics::ModelKind;
  SingleWheelModel m;
  m.model.soil = soil;
  m.model.options.kind = r.baseline_model == "RFT"                     ? ModelKind::rft
                         : r.baseline_model == "Ishigami (slip angle)" ? ModelKind::ishigami
                                                                       : ModelKind::wong_reece;
  if (!r.slip_definition.empty()) {
    m.model.options.slip_definition = terramechanics::parse_slip_definition(r.slip_definition);
  }
  m.at_slip_angle = m.model.options.kind != ModelKind::wong_reece;
  const std::string reading = r.slip_definition.empty() ? "" : ", " + r.slip_definition + " slip";
  for (const auto& c : r.selection) {
    if (c.name != r.final_model) continue;
    m.model.soil = c.fit.soil;
    m.model.options.extensions = c.fit.extensions;
    m.held_out = c.held_out;
    m.held_out_method = r.held_out_method;
    m.name = "the study's final model, " + r.baseline_model + " + " + c.name + " on " + soil.name + reading;
    return m;
  }
  m.held_out = residuals_of(m, points);
  m.held_out_method = "nothing fitted";
  m.name = "the study's final model, the baseline " + r.baseline_model + " on " + soil.name + reading;
  return m;
}

views::LabFigures single_wheel_figures(const std::vector<WheelTestPoint>& points, const SingleWheelModel& m) {
  views::LabFigures f;
  const Groups groups = groups_of(points);
  views::PanelFigure panels, residuals;
  std::string bands;
  // At one slip angle the residuals are drawn against slip: against the
  // angle they would stand in one vertical line.
  std::set<double> angles;
  for (const auto& p : points) angles.insert(degrees_2dp(p.slip_angle));
  const bool by_slip = angles.size() < 2;
  for (Quantity q : {Quantity::drawbar_pull, Quantity::lateral_force}) {
    if (angles_measuring(points, q).empty()) continue;
    const double band = 2.0 * rms_residual(m.held_out, q);
    panels.rows.push_back(slip_row(points, m, groups, q, band));
    residuals.rows.push_back(residual_row(points, m, groups, q, band, by_slip));
    bands += (bands.empty() ? "" : ", ") + band_text(q, band);
  }
  if (panels.rows.empty()) {
    f.why_not = "the file has no drawbar_pull_N or lateral_force_N values";
    return f;
  }
  const std::string method =
      m.held_out_method == "nothing fitted" ? "nothing fitted, so all held out" : m.held_out_method + " held out";
  panels.caption =
      "Lines: " + m.name + ".\nShaded: +-2 sigma of its held-out residuals (" + method + "): " + bands + ".";
  panels.x_title = "slip";
  residuals.caption = "Measured - predicted by " + m.name + ".\nGrey: +-2 sigma of the held-out residuals (" + method +
                      "): " + bands + ".";
  residuals.x_title = by_slip ? "slip" : "slip angle (deg)";
  if (by_slip) {
    residuals.notes.push_back("one slip angle (" + number(*angles.begin()) +
                              " deg) in the file: the residuals are drawn against slip");
  }
  panels.group_names = residuals.group_names = groups.names;
  if (groups.binned_wheels > 0) {
    panels.notes.push_back("loads binned: a wheel tested at more than " + std::to_string(kMaxLoadsPerWheel) +
                           " loads has its points in " + std::to_string(kLoadBins) +
                           " groups of about equal size, each line at its group's median load");
  }
  std::size_t uncarried = 0;
  for (const auto& r : m.held_out) uncarried += std::isfinite(r.predicted) ? 0 : 1;
  if (uncarried > 0) {
    residuals.notes.push_back(std::to_string(uncarried) + " measurements the model cannot carry are left out");
  }
  f.slip_panels = std::move(panels);
  f.residuals = std::move(residuals);
  return f;
}

namespace {

const char* fit_name(terramechanics::PressureModel m) {
  return m == terramechanics::PressureModel::bekker  ? "Bekker"
         : m == terramechanics::PressureModel::reece ? "Reece"
                                                     : "RFT";
}

// One record: its samples (the fitted virgin loading apart from the rest
// after contact) and each fitted relation's force over its depths.
views::Panel plate_panel(const terramechanics::PlateRecord& rec, const terramechanics::PlateAnalysis& a,
                         std::size_t r) {
  views::Panel panel;
  const terramechanics::Plate& plate = rec.plate;
  panel.title = plate.circular ? "plate of diameter " + number(plate.width * 1000.0, "%.4g") + " mm"
                               : "plate " + number(plate.width * 1000.0, "%.4g") + " x " +
                                     number(plate.length * 1000.0, "%.4g") + " mm";
  views::PanelSeries virgin, other;
  virgin.group = 0;
  other.group = 1;
  std::vector<bool> fitted(rec.depth.size(), false);
  for (std::size_t i : a.records[r].virgin) fitted[i] = true;
  for (std::size_t i = 0; i < rec.depth.size(); ++i) {
    views::PanelSeries& s = fitted[i] ? virgin : other;
    s.x.push_back(rec.depth[i] * 1000.0);
    s.y.push_back(rec.force[i]);
  }
  panel.series.push_back(std::move(other));
  panel.series.push_back(std::move(virgin));
  const auto [lo, hi] = std::minmax_element(rec.depth.begin(), rec.depth.end());
  for (std::size_t k = 0; k < a.fits.size(); ++k) {
    const terramechanics::PressureSinkageFit& fit = a.fits[k];
    views::PanelSeries curve;
    curve.group = static_cast<int>(k) + 2;
    const double z0 = r < fit.contact_depths.size() ? fit.contact_depths[r] : 0.0;
    for (int j = 0; j <= 100; ++j) {
      const double z = *lo + (*hi - *lo) * j / 100.0;
      curve.curve_x.push_back(z * 1000.0);
      curve.curve_y.push_back(terramechanics::fitted_force(fit, plate, z0, z));
    }
    panel.series.push_back(std::move(curve));
  }
  return panel;
}

views::PanelFigure plate_figure(const std::vector<terramechanics::PlateRecord>& records) {
  using terramechanics::PlateAnalysis;
  const PlateAnalysis a = terramechanics::analyse_plate_tests(records, terramechanics::PlateFitOptions{});
  views::PanelFigure f;
  f.x_title = "depth (mm)";
  f.group_names = {"virgin loading (fitted)", "unloading, reloading, approach"};
  std::string fits;
  for (const auto& fit : a.fits) {
    f.group_names.push_back(std::string(fit_name(fit.model)) + " (held out " + number(fit.held_out_rmse_N, "%.3g") +
                            " N)");
    fits += (fits.empty() ? "" : ", ") + std::string(fit_name(fit.model));
  }
  f.caption =
      "Lines: " + fits + " fitted to the virgin loading samples (soil plate); key: held-out RMSE.\n" +
      (a.plate_sizes.size() < 2 ? "One plate size: Bekker's k_c and k_phi are not separated (one lumped modulus)."
                                : std::to_string(a.plate_sizes.size()) + " plate sizes.");
  views::PanelRow row;
  row.y_title = "force (N)";
  for (std::size_t r = 0; r < records.size(); ++r) {
    row.panels.push_back(plate_panel(records[r], a, r));
  }
  f.rows.push_back(std::move(row));
  return f;
}

}  // namespace

views::LabFigures lab_figures_of(const ViewInput& in, const std::optional<std::string>& soil_name) {
  if (in.is_plate_test()) {
    views::LabFigures f;
    f.force_depth = about_file(in.file, [&] { return plate_figure(in.plate_records); });
    f.why_not = "a plate test, not a single-wheel test table";
    return f;
  }
  if (!in.is_wheel_test()) {
    views::LabFigures f;
    f.why_not =
        "not a single-wheel test table (load_N, slip and drawbar_pull_N or lateral_force_N columns) nor a "
        "plate test (depth_m, force_N)";
    return f;
  }
  const terramechanics::Soil soil = io::find_soil(soil_name.value_or("dry_sand"), resource_subfolders("soils"));
  return single_wheel_figures(in.wheel_points, baseline_single_wheel_model(soil, in.wheel_points));
}

}  // namespace roverlab::app

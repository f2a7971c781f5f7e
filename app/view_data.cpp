#include "app/view_data.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>

#include "app/analysis.h"
#include "app/commands.h"
#include "app/lab_figures.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/terramechanics/model.h"
#include "core/terramechanics/model_grid.h"
#include "core/terramechanics/slip_angle_model.h"
#include "importers/rover_file.h"
#include "importers/soil_file.h"
#include "views/timeseries_chart.h"

namespace roverlab::app {

estimation::SkidSteerGeometry rover_geometry(const log::Log& lg) {
  if (lg.metadata.rover_id.empty()) return {};
  try {
    const io::RoverDescription d = io::find_rover_named(lg.metadata.rover_id, resource_subfolders("rovers"), "log");
    if (d.skid_steer) return *d.skid_steer;
  } catch (const InputError&) {
  }
  return {};
}

std::optional<kinematics::RoverModel> rover_kinematics(const log::Log& lg) {
  if (lg.metadata.rover_id.empty()) return std::nullopt;
  try {
    return io::find_rover_named(lg.metadata.rover_id, resource_subfolders("rovers"), "log").dh;
  } catch (const InputError&) {
    return std::nullopt;
  }
}

namespace {

// The traction surfaces of an analysis's result (a rover's own, from its
// estimates: the net-traction estimator, seed 003 section 5.7).
bool analysis_surface(const ViewInput& in, bool dp, views::TractionSurfaceData& d,
                      terramechanics::SurfaceFit* fit_out) {
  for (const auto& run : in.analyses) {
    if (!run.analysis->presentation().draws_traction_surfaces() ||
        !run.analysis->presentation().traction_surface(run.document, dp, d))
      continue;
    if (fit_out) {
      fit_out->surface = d.surface;
      fit_out->error = terramechanics::fit_error(d.surface, d.points);
    }
    return true;
  }
  return false;
}

// The analysis whose estimates the log holds without its result (a log
// written before results were stored with it): its command, else empty.
std::string estimates_without_result(const ViewInput& in) {
  for (const auto& a : all_analyses()) {
    if (a->presentation().draws_traction_surfaces() && a->missing(in.log).empty() && !a->runs_on_open(in.log) &&
        in.result(a->name()) == nullptr) {
      return a->identity().command;
    }
  }
  return {};
}

// A soil model's surface over load (half the points' lowest to 1.5 x their
// highest; 10-200 N without points) and d's slip range: the model's
// `value` on a 40 x 40 grid (core/terramechanics/model_grid.h), fitted at
// order 4 as in seed 003 Appendix A. Sets d's load range and `fit`; returns the soil's name.
std::string model_surface(const ViewInput& in, const std::string& soil_name, double load_lo, double load_hi,
                          views::TractionSurfaceData& d, terramechanics::SurfaceFit& fit,
                          const terramechanics::ModelOptions& options, std::optional<double> slip_angle,
                          std::vector<terramechanics::SurfaceSample> terramechanics::ModelGrid::*value) {
  using namespace terramechanics;
  GridModel model;
  model.soil = io::find_soil(soil_name, resource_subfolders("soils"));
  model.wheel = Wheel{0.075, 0.07, 0, 0.0};  // Kapvik's wheel when no points say otherwise
  if (!in.wheel_points.empty()) model.wheel = in.wheel_points.front().wheel;
  model.options = options;
  d.load_min = std::isfinite(load_lo) ? 0.5 * load_lo : 10.0;
  d.load_max = std::isfinite(load_hi) ? 1.5 * load_hi : 200.0;
  const GridRange range{d.load_min, d.load_max, d.slip_min, d.slip_max, 40, 40};
  const std::vector<SurfaceSample> grid = model_grid(model, range, slip_angle).*value;
  if (grid.size() < 30) throw InputError(in.file, "soil " + model.soil.name + " cannot carry these loads");
  fit.surface = fit_surface(grid, 4);
  fit.error = fit_error(fit.surface, grid);
  return model.soil.name;
}

// Groups 1.. by the points' wheel label, in order of first appearance, named in the view's key.
void group_by_wheel(const std::vector<std::string>& labels, views::TractionSurfaceData& d) {
  d.point_group.clear();
  d.group_names.clear();
  for (const auto& label : labels) {
    const auto at = std::find(d.group_names.begin(), d.group_names.end(), label);
    d.point_group.push_back(static_cast<int>(at - d.group_names.begin()) + 1);
    if (at == d.group_names.end()) d.group_names.push_back(label);
  }
  if (d.group_names.size() == 1 && d.group_names.front().empty()) d.group_names.front() = "wheel";
}

std::string degrees_text(double deg) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", std::round(deg * 100.0) / 100.0);
  return text;
}

// The slip axis holds every point: 0..1 and the points' slips beyond it
// (braking, s < 0, included).
void span_slips(views::TractionSurfaceData& d) {
  d.slip_min = 0.0;
  d.slip_max = 1.0;
  for (const auto& p : d.points) {
    d.slip_min = std::min(d.slip_min, p.slip);
    d.slip_max = std::max(d.slip_max, p.slip);
  }
}

// The slip angles (deg, to 0.01) of the points with a value of `has`.
template <typename Has>
std::set<double> slip_angles_deg(const ViewInput& in, Has has) {
  std::set<double> angles;
  for (const auto& p : in.wheel_points) {
    if (has(p)) angles.insert(std::round(p.slip_angle * 180.0 / M_PI * 100.0) / 100.0);
  }
  return angles;
}

// The slip angle (deg) a drawbar-pull or torque surface of single-wheel
// points is drawn at: the asked one, else the one nearest 0 the points have.
template <typename Has>
double longitudinal_slip_angle_deg(const ViewInput& in, Has has, std::optional<double> asked_deg) {
  const std::set<double> angles = slip_angles_deg(in, has);
  if (asked_deg) {
    if (angles.empty() || angles.count(std::round(*asked_deg * 100.0) / 100.0) > 0) return *asked_deg;
    std::string have;
    for (double a : angles) have += (have.empty() ? "" : ", ") + degrees_text(a);
    throw InputError(in.file, "no points at slip angle " + degrees_text(*asked_deg) +
                                  " deg (the file has slip angles " + have + " deg)");
  }
  if (angles.empty()) return 0.0;
  return *std::min_element(angles.begin(), angles.end(), [](double a, double b) { return std::abs(a) < std::abs(b); });
}

// The slip angle (rad) the lateral-force surface is drawn at: the asked one,
// else the largest |beta| of the points with a lateral force, else 10 deg.
double lateral_slip_angle(const ViewInput& in, std::optional<double> asked_deg) {
  if (asked_deg) return *asked_deg * M_PI / 180.0;
  double largest = 0.0;
  for (const auto& p : in.wheel_points) {
    if (p.lateral_force && std::abs(p.slip_angle) > std::abs(largest)) largest = p.slip_angle;
  }
  return largest != 0.0 ? largest : 10.0 * M_PI / 180.0;
}

// F_y(W, s) at one slip angle (Ishigami et al. 2007): the points at that
// angle, and the soil's model surface on a grid or a surface fitted to them.
views::TractionSurfaceData lateral_surface_of(const ViewInput& in, const std::optional<std::string>& soil_name,
                                              terramechanics::SurfaceFit* fit_out, std::optional<double> asked_deg) {
  using namespace terramechanics;
  const double beta = lateral_slip_angle(in, asked_deg);
  const std::string at = "slip angle " + degrees_text(beta * 180.0 / M_PI) + " deg";
  views::TractionSurfaceData d;
  d.unit = "N";
  std::set<double> loads, angles;
  std::vector<std::string> labels;
  for (const auto& p : in.wheel_points) {
    if (!p.lateral_force) continue;
    angles.insert(std::round(p.slip_angle * 180.0 / M_PI * 100.0) / 100.0);
    if (std::abs(p.slip_angle - beta) > 0.005 * M_PI / 180.0 + 1e-9 * std::abs(beta)) continue;
    d.points.push_back({p.load, p.slip, *p.lateral_force});
    labels.push_back(p.wheel_label);
    loads.insert(p.load);
  }
  if (in.is_wheel_test() && angles.empty() && !soil_name) throw InputError(in.file, "no lateral_force_N values");
  if (in.is_wheel_test() && !angles.empty() && d.points.empty() && !soil_name) {
    std::string have;
    for (double a : angles) have += (have.empty() ? "" : ", ") + degrees_text(a);
    throw InputError(in.file, "no lateral_force_N at " + at + " (the file has slip angles " + have + " deg)");
  }
  if (!in.is_wheel_test() && !soil_name) {
    throw InputError(in.file, "a lateral-force surface needs a single-wheel CSV with lateral_force_N or --soil NAME");
  }
  group_by_wheel(labels, d);
  span_slips(d);
  const double lo = loads.empty() ? NAN : *loads.begin(), hi = loads.empty() ? NAN : *loads.rbegin();
  SurfaceFit fit;
  if (soil_name) {
    // The slip's reading (model.h): travel when a point read longitudinally
    // would slide sideways at over 10 times its rim speed. A rule of thumb
    // (the study fits both readings instead): the title says which it drew.
    ModelOptions m;
    m.kind = ModelKind::ishigami;
    for (const auto& p : in.wheel_points) {
      if ((1.0 - p.slip) * std::abs(std::tan(p.slip_angle)) > 10.0) m.slip_definition = SlipDefinition::travel;
    }
    const std::string soil = model_surface(in, *soil_name, lo, hi, d, fit, m, beta, &ModelGrid::lateral_force);
    d.quantity = "lateral force F_y (" + soil + " model, " + at + ", " + to_string(m.slip_definition) + " slip)";
  } else {
    if (loads.size() < 2) {
      throw InputError(
          in.file, "all points at " + at + " are at one load: give --soil NAME to draw the model surface through them");
    }
    fit = fit_surface_cross_validated(d.points, 4);
    d.load_min = lo;
    d.load_max = hi;
    d.quantity = "lateral force F_y (fitted to the points at " + at + ")";
  }
  d.surface = fit.surface;
  if (fit_out) *fit_out = fit;
  return d;
}

}  // namespace

views::TractionSurfaceData traction_surface_of(const ViewInput& in, const std::string& quantity,
                                               const std::optional<std::string>& soil_name,
                                               terramechanics::SurfaceFit* fit_out,
                                               std::optional<double> slip_angle_deg) {
  using namespace terramechanics;
  if (quantity == "lateral-force") return lateral_surface_of(in, soil_name, fit_out, slip_angle_deg);
  if (quantity != "drawbar-pull" && quantity != "torque") {
    throw std::invalid_argument("quantity must be drawbar-pull, torque or lateral-force");
  }
  const bool dp = quantity == "drawbar-pull";
  views::TractionSurfaceData d;
  d.quantity = dp ? "drawbar pull" : "resistive torque";
  d.unit = dp ? "N" : "N m";
  if (!in.is_wheel_test() && !soil_name && analysis_surface(in, dp, d, fit_out)) return d;
  if (const std::string command = in.is_wheel_test() || soil_name ? "" : estimates_without_result(in);
      !command.empty()) {
    // The estimator is not run again over a log that holds its streams, and the surfaces are fitted in its run.
    throw InputError(in.file, "the log holds the estimates of `" + command +
                                  "` but not its result (written before RoverLab stored results with a log): run "
                                  "it again on the measured log with -o, or give --soil NAME");
  }
  if (!in.is_wheel_test() && !soil_name) {
    throw InputError(in.file,
                     "no traction data: give a single-wheel CSV (load_N, slip, drawbar_pull_N / torque_Nm), "
                     "a planar rocker-bogie log the net-traction estimator can run on, or --soil NAME for the "
                     "model surface");
  }
  std::set<double> loads;
  std::vector<std::string> labels;
  double load_lo = std::numeric_limits<double>::infinity(), load_hi = -load_lo;
  const auto has = [dp](const WheelTestPoint& p) { return (dp ? p.drawbar_pull : p.torque).has_value(); };
  const double beta_deg = longitudinal_slip_angle_deg(in, has, slip_angle_deg);
  const std::string at = "slip angle " + degrees_text(beta_deg) + " deg";
  for (const auto& p : in.wheel_points) {
    const auto v = dp ? p.drawbar_pull : p.torque;
    if (!v || std::abs(p.slip_angle * 180.0 / M_PI - beta_deg) > 0.005) continue;
    d.points.push_back({p.load, p.slip, *v});
    labels.push_back(p.wheel_label);
    loads.insert(p.load);
    load_lo = std::min(load_lo, p.load);
    load_hi = std::max(load_hi, p.load);
  }
  if (in.is_wheel_test() && d.points.empty()) {
    throw InputError(in.file, std::string("no ") + (dp ? "drawbar_pull_N" : "torque_Nm") + " values");
  }
  group_by_wheel(labels, d);
  span_slips(d);
  SurfaceFit fit;
  if (soil_name) {
    // The model surface: Wong-Reece on a grid, fitted as in seed 003 Appendix A (at a slip angle: Ishigami 2007).
    const double beta = beta_deg * M_PI / 180.0;
    const std::string soil = model_surface(in, *soil_name, load_lo, load_hi, d, fit, ModelOptions{},
                                           beta == 0.0 ? std::nullopt : std::optional(beta),
                                           dp ? &ModelGrid::drawbar_pull : &ModelGrid::resistive_torque);
    d.quantity += " (" + soil + " model" + (in.is_wheel_test() || beta != 0.0 ? ", " + at : "") + ")";
  } else {
    if (in.is_wheel_test()) d.quantity += " (fitted to the points at " + at + ")";
    if (loads.size() < 2) {
      throw InputError(in.file, "all points are at one load: give --soil NAME to draw the model surface through them");
    }
    fit = fit_surface_cross_validated(d.points, 4);
    d.load_min = load_lo;
    d.load_max = load_hi;
  }
  d.surface = fit.surface;
  if (fit_out) *fit_out = fit;
  return d;
}

namespace {

// --x and --y, one channel each (or the channels given).
std::vector<views::ChannelRef> channel_pair(const ViewInput& in, const ViewOptions& o) {
  if (!o.x_channel && !o.y_channel) return o.channels;
  if (!o.x_channel || !o.y_channel)
    throw UsageError(std::string(o.x_channel ? "--y" : "--x") +
                     ": missing (a scatter plot needs --x STREAM:CH and --y STREAM:CH)");
  std::vector<views::ChannelRef> pair;
  for (const auto& [option, spec] : {std::pair{"--x", *o.x_channel}, std::pair{"--y", *o.y_channel}}) {
    if (spec.find(':') == std::string::npos || spec.find(',') != std::string::npos)
      throw UsageError(std::string(option) + " " + spec + ": expected one STREAM:CHANNEL");
    try {
      pair.push_back(views::parse_channels(in.log, spec).at(0));
    } catch (const DataError& e) {
      throw InputError(in.file, std::string(option) + ": " + e.what());
    }
  }
  return pair;
}

}  // namespace

views::SceneInput scene_input(const ViewInput& in, const views::View& view, const ViewOptions& o) {
  if (in.is_wheel_test() && !view.uses_surface_data() && !view.uses_lab_figures()) {
    throw InputError(in.file, "single-wheel test points are not a log: no " + view.name() + " view");
  }
  if (in.is_plate_test() && !view.uses_lab_figures()) {
    throw InputError(in.file, "plate test samples are not a log: no " + view.name() + " view");
  }
  views::SceneInput s;
  s.log = &in.log;
  s.time = o.time;
  if (view.uses_surface_data()) {
    s.surface = traction_surface_of(in, o.quantity, o.soil, nullptr, o.slip_angle_deg);
  } else if (view.uses_lab_figures()) {
    s.lab = lab_figures_of(in, o.soil);
  } else {
    s.rover = rover_geometry(in.log);
    s.articulated = rover_kinematics(in.log);
  }
  if (view.uses_channels() || view.compares_runs()) {
    s.channels = o.channels;
    try {
      if (o.channel_spec) s.channels = views::parse_channels(in.log, *o.channel_spec);
    } catch (const DataError& e) {
      throw InputError(in.file, e.what());
    }
  }
  if (view.plots_channel_pair()) s.channels = channel_pair(in, o);
  if (view.compares_runs()) s.compared = o.compared;
  const std::string missing = view.needs(s);
  if (!missing.empty()) throw InputError(in.file, missing);
  return s;
}

}  // namespace roverlab::app

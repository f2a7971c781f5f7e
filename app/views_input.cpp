#include "app/views_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "app/command_support.h"
#include "app/log_input.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/terramechanics/model.h"
#include "importers/csv_text.h"
#include "importers/rover_file.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"

namespace roverlab::app {

namespace {

bool looks_like_wheel_test_csv(const std::string& file) {
  std::error_code ec;
  // Not a regular file: load_log says why (a pipe would block here).
  if (std::filesystem::path(file).extension() != ".csv" || !std::filesystem::is_regular_file(file, ec)) return false;
  std::ifstream in = io::csv::open_text_file(file);
  std::string header;
  int line_number = 0;
  if (!io::csv::next_content_line(in, header, line_number, file)) return false;
  return header.find("load_N") != std::string::npos && header.find("slip") != std::string::npos;
}

}  // namespace

const nlohmann::json* ViewInput::result(const std::string& name) const {
  for (const auto& a : analyses) {
    if (a.name == name) return &a.document;
  }
  return nullptr;
}

void ViewInput::add(const Analysis& analysis, AnalysisResult r) {
  for (const auto& s : r.estimates.streams()) {
    if (log.find_stream(s.name()) == nullptr) log.add_stream(s);
  }
  AnalysisRun run{analysis.name(), analysis.title(), std::move(r.document)};
  for (auto& a : analyses) {
    if (a.name == run.name) {
      a = std::move(run);
      return;
    }
  }
  // Keep registry order, so the report and the GUI list results alike.
  const std::vector<std::string> order = all_analysis_names();
  const auto rank = [&](const std::string& n) { return std::find(order.begin(), order.end(), n) - order.begin(); };
  auto at = std::find_if(analyses.begin(), analyses.end(), [&](const AnalysisRun& a) { return rank(a.name) > rank(run.name); });
  analyses.insert(at, std::move(run));
}

std::vector<std::string> all_analysis_names() {
  std::vector<std::string> names;
  for (const auto& a : all_analyses()) names.push_back(a->name());
  return names;
}

AnalysisResult run_for_views(Analysis& analysis, const log::Log& lg, const std::string& file,
                             const std::function<void(double)>& progress) {
  return about_file(file, [&] { return analysis.run({lg, file, progress}); });
}

ViewInput load_view_input(const std::string& file, const std::optional<std::string>& mapping,
                          const ViewInputOptions& o) {
  ViewInput in;
  in.file = file;
  if (looks_like_wheel_test_csv(file)) {
    in.wheel_points = io::read_wheel_test_csv(file);
    in.notes.push_back("single-wheel test points: " + std::to_string(in.wheel_points.size()));
    return in;
  }
  in.log = load_input(file, mapping).log;
  for (const auto& name : o.analyses) {
    const std::unique_ptr<Analysis> a = make_analysis(name);
    if (!a) throw std::logic_error("no analysis named " + name);
    const std::string missing = a->missing(in.log);
    if (!missing.empty()) {
      in.notes.push_back("not run: " + a->command() + " (the log has " + missing + ")");
      continue;
    }
    if (!a->runs_on_open(in.log)) continue;
    a->use_view_defaults();
    try {
      in.add(*a, run_for_views(*a, in.log, file));
    } catch (const InputError& e) {
      in.notes.push_back("not run: " + a->command() + " (" + e.problem() + ")");
      continue;
    }
    in.notes.push_back("ran " + a->command() + " on the log: " + a->title());
  }
  return in;
}

std::string rover_name_of(const log::Log& lg) {
  return lg.metadata.rover_id.empty() ? "exomars_bb2" : lg.metadata.rover_id;
}

estimation::SkidSteerGeometry rover_geometry(const log::Log& lg) {
  if (lg.metadata.rover_id.empty()) return {};
  try {
    const io::RoverDescription d = io::find_rover(lg.metadata.rover_id, resource_subfolders("rovers"));
    if (d.skid_steer) return *d.skid_steer;
  } catch (const InputError&) {
  }
  return {};
}

views::TractionSurfaceData traction_surface_of(const ViewInput& in, const std::string& quantity,
                                               const std::optional<std::string>& soil_name,
                                               terramechanics::SurfaceFit* fit_out) {
  using namespace terramechanics;
  if (quantity != "drawbar-pull" && quantity != "torque") {
    throw std::invalid_argument("quantity must be drawbar-pull or torque");
  }
  const bool dp = quantity == "drawbar-pull";
  views::TractionSurfaceData d;
  d.quantity = dp ? "drawbar pull" : "resistive torque";
  d.unit = dp ? "N" : "N m";
  if (!in.is_wheel_test() && !soil_name) {
    throw InputError(in.file, "no traction data: give a single-wheel CSV (load_N, slip, drawbar_pull_N / torque_Nm) "
                              "or --soil NAME for the model surface");
  }
  std::set<double> loads;
  double load_lo = INFINITY, load_hi = -INFINITY;
  for (const auto& p : in.wheel_points) {
    const auto v = dp ? p.drawbar_pull : p.torque;
    if (!v) continue;
    d.points.push_back({p.load, p.slip, *v});
    loads.insert(p.load);
    load_lo = std::min(load_lo, p.load);
    load_hi = std::max(load_hi, p.load);
  }
  if (in.is_wheel_test() && d.points.empty()) {
    throw InputError(in.file, std::string("no ") + (dp ? "drawbar_pull_N" : "torque_Nm") + " values");
  }
  SurfaceFit fit;
  if (soil_name) {
    // The model surface: Wong-Reece on a grid, fitted as in seed 003 Appendix A.
    const Soil soil = io::find_soil(*soil_name, resource_subfolders("soils"));
    Wheel wheel{0.075, 0.07, 0, 0.0};  // Kapvik's wheel when no points say otherwise
    if (!in.wheel_points.empty()) wheel = in.wheel_points.front().wheel;
    d.load_min = std::isfinite(load_lo) ? 0.5 * load_lo : 10.0;
    d.load_max = std::isfinite(load_hi) ? 1.5 * load_hi : 200.0;
    std::vector<SurfaceSample> grid;
    for (int i = 0; i < 40; ++i) {
      for (int k = 0; k < 40; ++k) {
        const double W = d.load_min + (d.load_max - d.load_min) * i / 39.0, s = k / 39.0;
        const Traction t = evaluate(soil, wheel, W, s, ModelOptions{});
        if (t.ok()) grid.push_back({W, s, dp ? t.drawbar_pull : t.resistive_torque});
      }
    }
    if (grid.size() < 30) throw InputError(in.file, "soil " + soil.name + " cannot carry these loads");
    fit.surface = fit_surface(grid, 4);
    fit.error = fit_error(fit.surface, grid);
    d.quantity += " (" + soil.name + " model)";
  } else {
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

}  // namespace roverlab::app

// `roverlab terramechanics` (evaluate), `... surface` and `... fit`.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include <CLI/CLI.hpp>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/terramechanics/model.h"
#include "core/terramechanics/model_grid.h"
#include "core/terramechanics/slip_angle_model.h"
#include "core/terramechanics/traction_surface.h"
#include "importers/soil_file.h"
#include "importers/table_csv.h"

namespace roverlab::app {

struct TerramechanicsOptions {
  std::string soil;
  double radius = 0.0, width = 0.0;
  int grousers = 0;
  double grouser_height = 0.0;
  double grouser_thickness = 0.0;
  std::vector<double> loads, slips;
  std::vector<double> slip_angles_deg;  // with these (or --model ishigami): the slip-angle model
  std::string lateral_shear = "shared";
  std::string slip_definition = "longitudinal";
  double sidewall_scale = 1.0;
  std::string model = "wong";
  std::string integration = "simpson";
  int riemann_points = 500;
  double slip_sinkage_n1 = 0.3;
  double grouser_effectiveness = 1.0;
  double bulldozing_scale = 1.0;
  double soil_strength = 1.0;
  double shear_modulus_slip = 2.0;
  double rear_angle_ratio = 0.2;
  double shear_residual_ratio = 0.7;
  double shear_peak_displacement = 0.02;
  double rft_scale = 0.0;  // zeta, N/m^3; 0: the soil's
  double rft_pileup = 0.5;
  double rft_depth_scale = 1.0;
  std::string format = "csv";
};

struct SurfaceOptions {
  TerramechanicsOptions model;
  double load_min = 0.1, load_max = 200.0, slip_min = 0.0, slip_max = 1.0;
  int grid = 100;
  std::string order = "4";  // 1..6 or auto
  bool json = false;
};

struct FitOptions {
  std::string file;
  std::string order = "auto";
  int grid_bins = 10;
  bool json = false;
};

using nlohmann::json;
using namespace roverlab::terramechanics;

namespace {

// "wong", "bekker", "wong+slip-sinkage+grousers", ...
ModelOptions model_options(const TerramechanicsOptions& o) try {
  ModelOptions m;
  std::stringstream parts(o.model);
  std::string part;
  bool first = true;
  while (std::getline(parts, part, '+')) {
    if (first) {
      m.kind = parse_model_kind(part);
      first = false;
    } else if (part == "slip-sinkage") {
      m.extensions.slip_sinkage_n1 = o.slip_sinkage_n1;
    } else if (part == "grousers") {
      m.extensions.grousers = true;
      m.extensions.grouser_effectiveness = o.grouser_effectiveness;
    } else if (part == "bulldozing") {
      m.extensions.bulldozing = true;
      m.extensions.bulldozing_scale = o.bulldozing_scale;
    } else if (part == "slip-shear-modulus") {
      m.extensions.shear_modulus_slip = o.shear_modulus_slip;
    } else if (part == "rear-angle") {
      m.extensions.rear_angle_ratio = o.rear_angle_ratio;
    } else if (part == "shear-peak") {
      m.extensions.shear_peak = true;
      m.extensions.shear_residual_ratio = o.shear_residual_ratio;
      m.extensions.shear_peak_displacement = o.shear_peak_displacement;
    } else if (part == "pile-up") {
      m.extensions.rft_pileup = o.rft_pileup;
    } else if (part == "depth-scale") {
      m.extensions.rft_depth_scale = o.rft_depth_scale;
    } else {
      throw DataError("unknown model extension '" + part +
                      "' (slip-sinkage, grousers, bulldozing, slip-shear-modulus, rear-angle, shear-peak; rft: "
                      "pile-up, depth-scale)");
    }
  }
  m.extensions.soil_strength = o.soil_strength;
  m.integration = parse_integration(o.integration);
  m.slip_definition = parse_slip_definition(o.slip_definition);
  m.riemann_points = o.riemann_points;
  if (o.riemann_points < 2) throw DataError("--riemann-points must be at least 2");
  return m;
} catch (const DataError& e) {
  throw UsageError(e.what());
}

Wheel wheel_of(const TerramechanicsOptions& o) {
  if (!(o.radius > 0.0) || !(o.width > 0.0)) throw UsageError("--radius and --width must be positive (metres)");
  Wheel w;
  w.radius = o.radius;
  w.width = o.width;
  w.grouser_count = o.grousers;
  w.grouser_height = o.grouser_height;
  w.grouser_thickness = o.grouser_thickness;
  return w;
}

std::string num(double v) {
  if (!std::isfinite(v)) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

json surface_json(const SurfaceFit& fit) {
  json j = {{"order", fit.surface.order()},
            {"coefficients", fit.surface.coefficients()},
            {"mean_abs_error", fit.error.mean_abs},
            {"rmse", fit.error.rmse},
            {"max_abs_error", fit.error.max_abs}};
  j["cross_validation"] = json::array();
  for (const auto& s : fit.orders) {
    j["cross_validation"].push_back({{"order", s.order}, {"train_rmse", s.train_rmse}, {"cv_rmse", s.cv_rmse}});
  }
  return j;
}

void print_surface(const std::string& title, const char* unit, const SurfaceFit& fit) {
  std::printf("%s: order %d, mean |error| %.6g %s, RMSE %.6g %s, max |error| %.6g %s\n", title.c_str(),
              fit.surface.order(), fit.error.mean_abs, unit, fit.error.rmse, unit, fit.error.max_abs, unit);
  if (!fit.orders.empty()) {
    std::printf("  order  train RMSE   5-fold CV RMSE\n");
    for (const auto& s : fit.orders) {
      std::printf("  %5d  %11.5g  %11.5g%s\n", s.order, s.train_rmse, s.cv_rmse,
                  s.order == fit.surface.order() ? "  <- chosen" : "");
    }
  }
  std::printf("  coefficients p_kl of s^k W^l (Eq. 2.28 order):\n");
  for (std::size_t i = 0; i < fit.surface.coefficients().size(); ++i) {
    const auto [k, l] = PolynomialSurface::exponents(i);
    std::printf("    p%d%d = % .10e\n", k, l, fit.surface.coefficients()[i]);
  }
}

SurfaceFit fit_with(const std::vector<SurfaceSample>& samples, const std::string& order) {
  if (order == "auto") return fit_surface_cross_validated(samples);
  int o = 0;
  try {
    o = std::stoi(order);
  } catch (const std::exception&) {
    throw UsageError("--order must be 1..6 or auto");
  }
  SurfaceFit fit;
  fit.surface = fit_surface(samples, o);
  fit.error = fit_error(fit.surface, samples);
  return fit;
}

}  // namespace

namespace {

const char* status_word(TractionStatus status) {
  return status == TractionStatus::ok                 ? "ok"
         : status == TractionStatus::unsupported_load ? "unsupported_load"
                                                      : "invalid_input";
}

LateralOptions lateral_options(const TerramechanicsOptions& o) {
  LateralOptions l;
  if (o.lateral_shear == "shared") {
    l.shear = LateralShear::shared;
  } else if (o.lateral_shear == "independent") {
    l.shear = LateralShear::independent;
  } else {
    throw UsageError("--lateral-shear must be shared or independent");
  }
  l.sidewall_scale = o.sidewall_scale;
  return l;
}

// One row per load, slip and slip angle of the slip-angle model (Ishigami 2007).
void print_slip_angle_rows(const TerramechanicsOptions& o, const Soil& soil, const Wheel& wheel, ModelOptions m) {
  if (m.kind == ModelKind::bekker) throw UsageError("--slip-angle needs --model wong, ishigami or rft (not bekker)");
  if (m.kind != ModelKind::rft) m.kind = ModelKind::ishigami;
  const LateralOptions lateral = lateral_options(o);
  const std::vector<double> angles = o.slip_angles_deg.empty() ? std::vector<double>{0.0} : o.slip_angles_deg;
  json rows = json::array();
  if (o.format == "csv") {
    std::cout << "load_N,slip,slip_angle_deg,drawbar_pull_N,lateral_force_N,resistive_torque_Nm,sinkage_m,"
                 "entry_angle_rad,sidewall_force_N,status\n";
  }
  for (double load : o.loads) {
    for (double slip : o.slips) {
      for (double deg : angles) {
        const SlipAngleTraction t = evaluate_slip_angle(soil, wheel, load, slip, deg * M_PI / 180.0, m, lateral);
        if (o.format == "csv") {
          std::cout << num(load) << "," << num(slip) << "," << num(deg) << ","
                    << (t.ok() ? num(t.drawbar_pull) + "," + num(t.lateral_force) + "," + num(t.resistive_torque) +
                                     "," + num(t.sinkage) + "," + num(t.entry_angle) + "," + num(t.sidewall)
                               : std::string(",,,,,"))
                    << "," << status_word(t.status) << "\n";
        } else {
          json r = {{"load_N", load}, {"slip", slip}, {"slip_angle_deg", deg}, {"status", to_string(t.status)}};
          if (t.ok()) {
            r["drawbar_pull_N"] = t.drawbar_pull;
            r["lateral_force_N"] = t.lateral_force;
            r["resistive_torque_Nm"] = t.resistive_torque;
            r["sinkage_m"] = t.sinkage;
            r["entry_angle_rad"] = t.entry_angle;
            r["sidewall_force_N"] = t.sidewall;
          }
          rows.push_back(r);
        }
      }
    }
  }
  if (o.format == "json") {
    std::cout << json{{"soil", soil.name},
                      {"model", o.model},
                      {"integration", o.integration},
                      {"lateral_shear", o.lateral_shear},
                      {"sidewall_scale", o.sidewall_scale},
                      {"lateral_shear_modulus_m", lateral_shear_modulus(soil)},
                      {"rows", rows}}
                     .dump(2)
              << "\n";
  }
}

}  // namespace

int run_terramechanics(const TerramechanicsOptions& o) {
  if (o.soil.empty()) throw UsageError("terramechanics: --soil is required (or use the surface / fit subcommands)");
  Soil soil = io::find_soil(o.soil, resource_subfolders("soils"));
  if (o.rft_scale > 0.0) soil.rft_scale = o.rft_scale;
  const Wheel wheel = wheel_of(o);
  const ModelOptions m = model_options(o);
  if (o.format != "csv" && o.format != "json") throw UsageError("--format must be csv or json");
  if (o.loads.empty() || o.slips.empty()) throw UsageError("give at least one --load and one --slip");
  if (!o.slip_angles_deg.empty() || has_lateral_force(m.kind)) {
    print_slip_angle_rows(o, soil, wheel, m);
    return kSuccess;
  }
  json rows = json::array();
  if (o.format == "csv") {
    std::cout << "load_N,slip,drawbar_pull_N,resistive_torque_Nm,sinkage_m,entry_angle_rad,status\n";
  }
  for (double load : o.loads) {
    for (double slip : o.slips) {
      const Traction t = evaluate(soil, wheel, load, slip, m);
      if (o.format == "csv") {
        std::cout << num(load) << "," << num(slip) << ","
                  << (t.ok() ? num(t.drawbar_pull) + "," + num(t.resistive_torque) + "," + num(t.sinkage) + "," +
                                   num(t.entry_angle)
                             : std::string(",,,"))
                  << "," << status_word(t.status) << "\n";
      } else {
        json r = {{"load_N", load}, {"slip", slip}, {"status", to_string(t.status)}};
        if (t.ok()) {
          r["drawbar_pull_N"] = t.drawbar_pull;
          r["resistive_torque_Nm"] = t.resistive_torque;
          r["sinkage_m"] = t.sinkage;
          r["entry_angle_rad"] = t.entry_angle;
        }
        rows.push_back(r);
      }
    }
  }
  if (o.format == "json") {
    std::cout << json{{"soil", soil.name}, {"model", o.model}, {"integration", o.integration}, {"rows", rows}}.dump(2)
              << "\n";
  }
  return kSuccess;
}

// The model on the surface grid at one slip angle (none: straight driving,
// evaluate()), and the Eq. 2.28 surfaces of DP, tau_R and, at a slip angle,
// F_y fitted to it: F_y(W, s, beta) as one surface per beta.
struct GridSurfaces {
  SurfaceFit drawbar, torque, lateral;
  std::size_t unsupported = 0;
};

GridSurfaces grid_surfaces(const SurfaceOptions& o, const Soil& soil, const Wheel& wheel, const ModelOptions& m,
                           std::optional<double> slip_angle_deg) {
  GridModel model{soil, wheel, m, slip_angle_deg ? lateral_options(o.model) : LateralOptions{}};
  const GridRange range{o.load_min, o.load_max, o.slip_min, o.slip_max, o.grid, o.grid};
  const bool show_progress = isatty(2);
  const ModelGrid g =
      model_grid(model, range, slip_angle_deg ? std::optional(*slip_angle_deg * M_PI / 180.0) : std::nullopt,
                 [show_progress](int i, int rows) {
                   if (show_progress) std::fprintf(stderr, "\rgrid %3d %%", (i + 1) * 100 / rows);
                 });
  if (show_progress) std::fprintf(stderr, "\r          \r");
  if (g.drawbar_pull.size() < 30) {
    throw DataError("fewer than 30 supported grid points: the soil cannot carry these loads");
  }
  GridSurfaces out;
  out.unsupported = g.unsupported;
  out.drawbar = fit_with(g.drawbar_pull, o.order);
  out.torque = fit_with(g.resistive_torque, o.order);
  if (slip_angle_deg) out.lateral = fit_with(g.lateral_force, o.order);
  return out;
}

// `terramechanics surface --slip-angle ...`: DP, tau_R and F_y surfaces over
// (W, s) at each slip angle (the slip-angle model, Ishigami 2007).
int run_slip_angle_surfaces(const SurfaceOptions& o, const Soil& soil, const Wheel& wheel, const ModelOptions& m) {
  json angles = json::array();
  if (!o.json) {
    std::printf("soil %s, wheel r = %g m, b = %g m, %s integration, slip-angle model (%s shear)\n", soil.name.c_str(),
                wheel.radius, wheel.width, o.model.integration.c_str(), o.model.lateral_shear.c_str());
  }
  for (double deg : o.model.slip_angles_deg) {
    const GridSurfaces g = grid_surfaces(o, soil, wheel, m, deg);
    if (o.json) {
      angles.push_back({{"slip_angle_deg", deg},
                        {"unsupported_points", g.unsupported},
                        {"drawbar_pull", surface_json(g.drawbar)},
                        {"resistive_torque", surface_json(g.torque)},
                        {"lateral_force", surface_json(g.lateral)}});
      continue;
    }
    std::printf("\nslip angle %g deg: grid %d x %d over W = %g..%g N, s = %g..%g; %zu points unsupported\n", deg,
                o.grid, o.grid, o.load_min, o.load_max, o.slip_min, o.slip_max, g.unsupported);
    print_surface("drawbar pull DP(W, s)", "N", g.drawbar);
    print_surface("resistive torque tau_R(W, s)", "N m", g.torque);
    print_surface("lateral force F_y(W, s)", "N", g.lateral);
  }
  if (o.json) {
    std::cout << json{{"soil", soil.name},
                      {"grid", o.grid},
                      {"load_range_N", {o.load_min, o.load_max}},
                      {"slip_range", {o.slip_min, o.slip_max}},
                      {"lateral_shear", o.model.lateral_shear},
                      {"slip_angles", angles}}
                     .dump(2)
              << "\n";
  }
  return kSuccess;
}

int run_terramechanics_surface(const SurfaceOptions& o) {
  const Soil soil = io::find_soil(o.model.soil, resource_subfolders("soils"));
  const Wheel wheel = wheel_of(o.model);
  ModelOptions m = model_options(o.model);
  if (o.grid < 2 || !(o.load_max > o.load_min) || !(o.slip_max > o.slip_min)) {
    throw UsageError("the grid needs at least 2 points per axis and non-empty ranges");
  }
  if (!o.model.slip_angles_deg.empty()) {
    if (m.kind == ModelKind::bekker) throw UsageError("--slip-angle needs --model wong or ishigami (not bekker)");
    m.kind = ModelKind::ishigami;
    return run_slip_angle_surfaces(o, soil, wheel, m);
  }
  const GridSurfaces g = grid_surfaces(o, soil, wheel, m, std::nullopt);
  const SurfaceFit& fdp = g.drawbar;
  const SurfaceFit& ftau = g.torque;
  const std::size_t unsupported = g.unsupported;
  if (o.json) {
    std::cout << json{{"soil", soil.name},
                      {"grid", o.grid},
                      {"load_range_N", {o.load_min, o.load_max}},
                      {"slip_range", {o.slip_min, o.slip_max}},
                      {"unsupported_points", unsupported},
                      {"drawbar_pull", surface_json(fdp)},
                      {"resistive_torque", surface_json(ftau)}}
                     .dump(2)
              << "\n";
  } else {
    std::printf("soil %s, wheel r = %g m, b = %g m, %s integration\n", soil.name.c_str(), wheel.radius, wheel.width,
                o.model.integration.c_str());
    std::printf(
        "grid %d x %d over W = %g..%g N, s = %g..%g; %zu points unsupported (entry angle would exceed 90 deg)\n",
        o.grid, o.grid, o.load_min, o.load_max, o.slip_min, o.slip_max, unsupported);
    print_surface("drawbar pull DP(W, s)", "N", fdp);
    print_surface("resistive torque tau_R(W, s)", "N m", ftau);
  }
  return kSuccess;
}

// The points a surface is fitted to: loads 0..1e6 N, slips in [-1, 1],
// values finite and below 1e6 (N or N m), at two loads and two slips at least.
void check_fit_points(const std::string& file, const io::NumericTable& t) {
  const auto& load = *t.find("load_N");
  const auto& slip = *t.find("slip");
  std::set<double> loads, slips;
  for (std::size_t i = 0; i < load.size(); ++i) {
    if (!std::isfinite(load[i]) || !std::isfinite(slip[i])) continue;
    const std::string row = "row " + std::to_string(i + 1);
    if (!(load[i] >= 0 && load[i] <= 1e6)) throw InputError(file, row + ": load_N must be 0..1e6 N");
    const auto* angle = t.find("slip_angle_deg");
    if (angle != nullptr && std::abs((*angle)[i]) > 90) {
      throw InputError(file, row + ": slip_angle_deg must be in [-90, 90]");
    }
    if (!(std::abs(slip[i]) <= 1)) throw InputError(file, row + ": slip must be in [-1, 1]");
    for (const char* column : {"drawbar_pull_N", "resistive_torque_Nm", "torque_Nm", "lateral_force_N"}) {
      const auto* v = t.find(column);
      if (v != nullptr && std::isfinite((*v)[i]) && !(std::abs((*v)[i]) <= 1e6)) {
        throw InputError(file, row + ": " + column + " must be within +-1e6");
      }
    }
    loads.insert(load[i]);
    slips.insert(slip[i]);
  }
  if (loads.size() < 2 || slips.size() < 2) {
    throw InputError(file, "the points span " + std::to_string(loads.size()) + " load(s) and " +
                               std::to_string(slips.size()) +
                               " slip(s): a surface DP(W, s) needs points at two loads and two slips at least");
  }
}

// Surfaces of each measured column over the given rows (all, or one slip
// angle's), the JSON of each, and the text when not --json. False when no
// column has a value there.
bool fit_columns(const FitOptions& o, const io::NumericTable& t, const std::vector<std::size_t>& rows, json& out) {
  const auto& load = *t.find("load_N");
  const auto& slip = *t.find("slip");
  bool any = false;
  for (const auto& [column, title, unit] :
       {std::tuple<std::string, std::string, const char*>{"drawbar_pull_N", "drawbar pull DP(W, s)", "N"},
        {"resistive_torque_Nm", "resistive torque tau_R(W, s)", "N m"},
        {"torque_Nm", "torque tau(W, s)", "N m"},
        {"lateral_force_N", "lateral force F_y(W, s)", "N"}}) {
    const auto* values = t.find(column);
    if (values == nullptr) continue;
    std::vector<SurfaceSample> samples;
    for (std::size_t i : rows) {
      if (std::isfinite((*values)[i]) && std::isfinite(load[i]) && std::isfinite(slip[i])) {
        samples.push_back({load[i], slip[i], (*values)[i]});
      }
    }
    if (samples.empty()) continue;
    any = true;
    const SurfaceFit fit = fit_with(samples, o.order);
    constexpr double kInf = std::numeric_limits<double>::infinity();
    double lmin = kInf, lmax = -kInf, smin = kInf, smax = -kInf;
    for (const auto& s : samples) {
      lmin = std::min(lmin, s.load);
      lmax = std::max(lmax, s.load);
      smin = std::min(smin, s.slip);
      smax = std::max(smax, s.slip);
    }
    if (!(lmax > lmin)) lmax = lmin + 1.0;
    if (!(smax > smin)) smax = smin + 1.0;
    const OccupancyGrid grid = OccupancyGrid::build(samples, lmin, lmax, smin, smax, o.grid_bins, o.grid_bins);
    if (o.json) {
      json j = surface_json(fit);
      j["points"] = samples.size();
      j["occupancy"] = {{"load_range_N", {lmin, lmax}},
                        {"slip_range", {smin, smax}},
                        {"bins", {o.grid_bins, o.grid_bins}},
                        {"counts", grid.counts},
                        {"coverage", grid.coverage()}};
      out[column] = j;
    } else {
      std::printf("%s from %zu points\n", title.c_str(), samples.size());
      print_surface(title, unit, fit);
      std::printf(
          "  occupancy grid (%d x %d cells, loads %g..%g N down, slips %g..%g across): %.0f %% of cells hold data\n",
          o.grid_bins, o.grid_bins, lmin, lmax, smin, smax, 100.0 * grid.coverage());
      for (int l = 0; l < o.grid_bins; ++l) {
        std::printf("    ");
        for (int s = 0; s < o.grid_bins; ++s) {
          const int c = grid.count(l, s);
          std::printf("%c", c == 0 ? '.' : c < 10 ? static_cast<char>('0' + c) : '#');
        }
        std::printf("\n");
      }
    }
  }
  return any;
}

// With a slip_angle_deg column: the surfaces of each slip angle apart
// (F_y(W, s, beta) as one surface per beta, as `surface --slip-angle`).
int run_terramechanics_fit(const FitOptions& o) {
  // Text in a measured column is an error, not a missing value (a column of "x" gave no surface silently).
  const io::NumericTable t = io::read_numeric_table(
      o.file, {"load_N", "slip"},
      {"slip_angle_deg", "drawbar_pull_N", "resistive_torque_Nm", "torque_Nm", "lateral_force_N"});
  check_fit_points(o.file, t);
  json out = {{"file", o.file}};
  const auto* angle = t.find("slip_angle_deg");
  const std::size_t n = t.find("load_N")->size();
  bool any = false;
  if (angle == nullptr) {
    std::vector<std::size_t> rows(n);
    for (std::size_t i = 0; i < n; ++i) rows[i] = i;
    any = about_file(o.file, [&] { return fit_columns(o, t, rows, out); });
  } else {
    std::set<double> angles;
    for (double a : *angle) {
      if (std::isfinite(a)) angles.insert(a);
    }
    out["slip_angles"] = json::array();
    for (double a : angles) {
      std::vector<std::size_t> rows;
      for (std::size_t i = 0; i < n; ++i) {
        if ((*angle)[i] == a) rows.push_back(i);
      }
      if (!o.json) std::printf("slip angle %g deg (%zu rows):\n", a, rows.size());
      json one = {{"slip_angle_deg", a}};
      const bool fitted = about_file(o.file, [&] {
        try {
          return fit_columns(o, t, rows, one);
        } catch (const DataError& e) {
          char angle_text[32];
          std::snprintf(angle_text, sizeof angle_text, "%g", a);
          throw DataError(std::string("slip angle ") + angle_text + " deg: " + e.what());
        }
      });
      if (fitted) {
        any = true;
        out["slip_angles"].push_back(one);
      }
    }
  }
  if (!any) {
    throw InputError(o.file, "no drawbar_pull_N, resistive_torque_Nm, torque_Nm or lateral_force_N values to fit");
  }
  if (o.json) std::cout << out.dump(2) << "\n";
  return kSuccess;
}

namespace {

// The wheel-soil model's options, shared by `terramechanics` (with the load
// and slip lists) and `terramechanics surface`. The parent command's options
// are checked in run_terramechanics, so that `terramechanics fit FILE` does not
// ask for them.
void add_model_options(CLI::App& cmd, TerramechanicsOptions& o, bool need_lists) {
  auto* soil = cmd.add_option("--soil", o.soil, "Soil NAME (resources/soils/NAME.json) or FILE");
  auto* radius = cmd.add_option("--radius", o.radius, "Wheel radius, m")->check(finite_in(1e-4, 10.0));
  auto* width = cmd.add_option("--width", o.width, "Wheel width, m")->check(finite_in(1e-4, 10.0));
  if (!need_lists) {
    soil->required();
    radius->required();
    width->required();
  }
  cmd.add_option("--grousers", o.grousers, "Number of grousers")->check(CLI::Range(0, 1000));
  cmd.add_option("--grouser-height", o.grouser_height, "Grouser height, m")->check(finite_in(0.0, 1.0));
  cmd.add_option("--grouser-thickness", o.grouser_thickness, "Grouser thickness, m (the rft model's mesh)")
      ->check(finite_in(0.0, 1.0));
  if (need_lists) {
    cmd.add_option("--load", o.loads, "Normal loads W, N (comma separated)")
        ->delimiter(',')
        ->check(finite_in(0.0, 1e6));
    cmd.add_option("--slip", o.slips, "Slips s in [-1, 1] (comma separated)")
        ->delimiter(',')
        ->check(finite_in(-1.0, 1.0));
    cmd.add_option("--format", o.format, "csv or json")->capture_default_str();
  }
  cmd.add_option("--slip-angle", o.slip_angles_deg,
                 need_lists
                     ? "Slip angles beta, deg in [-90, 90] (comma separated; adds the lateral force, Ishigami 2007)"
                     : "Slip angles beta, deg in [-90, 90]: DP, tau_R and F_y surfaces at each (Ishigami 2007)")
      ->delimiter(',')
      ->check(finite_in(-90.0, 90.0));
  cmd.add_option("--lateral-shear", o.lateral_shear,
                 "shared (one Mohr-Coulomb strength for tau_x and tau_y) | independent (Ishigami 2007 as printed)")
      ->capture_default_str();
  cmd.add_option("--slip-definition", o.slip_definition,
                 "longitudinal (s = 1 - v_x / (r w), Ishigami 2007) | travel (s = 1 - |v| / (r w)): how slip is read "
                 "at a slip angle")
      ->capture_default_str()
      ->check(CLI::IsMember({"longitudinal", "travel"}));
  cmd.add_option("--sidewall-scale", o.sidewall_scale, "scale of the sidewall bulldozing term (0: off)")
      ->capture_default_str()
      ->check(finite_in(0.0, 100.0));
  cmd.add_option("--model", o.model,
                 "bekker | wong | ishigami | rft, with +slip-sinkage, +grousers, +bulldozing, +slip-shear-modulus, "
                 "+rear-angle, +shear-peak (e.g. wong+slip-sinkage); rft with +grousers (height scale), +pile-up, "
                 "+depth-scale")
      ->capture_default_str();
  cmd.add_option("--integration", o.integration, "simpson | riemann")->capture_default_str();
  cmd.add_option("--riemann-points", o.riemann_points, "Points of the Riemann sum")
      ->capture_default_str()
      ->check(CLI::Range(2, 100000));
  cmd.add_option("--slip-sinkage-n1", o.slip_sinkage_n1, "n = n0 + n1 |s| (with +slip-sinkage)")
      ->capture_default_str()
      ->check(finite_in(0.0, 5.0));
  cmd.add_option("--grouser-effectiveness", o.grouser_effectiveness,
                 "shear radius r + lambda h (with +grousers); rft: a scale on the grousers' height")
      ->capture_default_str()
      ->check(finite_in(0.0, 2.0));
  cmd.add_option("--bulldozing-scale", o.bulldozing_scale, "scale of the bulldozing resistance (with +bulldozing)")
      ->capture_default_str()
      ->check(finite_in(0.0, 100.0));
  cmd.add_option("--soil-strength", o.soil_strength, "factor on c, tan(phi), kc, kphi")
      ->capture_default_str()
      ->check(finite_in(0.01, 100.0));
  cmd.add_option("--shear-modulus-slip", o.shear_modulus_slip, "K = K0 (1 + k_s s) (with +slip-shear-modulus)")
      ->capture_default_str()
      ->check(finite_in(-0.9, 20.0));
  cmd.add_option("--rear-angle-ratio", o.rear_angle_ratio, "theta_r = -kappa theta_0 (with +rear-angle)")
      ->capture_default_str()
      ->check(finite_in(0.0, 1.0));
  cmd.add_option("--shear-residual-ratio", o.shear_residual_ratio,
                 "K_r, residual over maximum shear stress of the peaked shear curve (with +shear-peak)")
      ->capture_default_str()
      ->check(finite_in(0.01, 1.0));
  cmd.add_option("--rft-scale", o.rft_scale, "zeta, N/m^3, the rft model's material scale (0: the soil's)")
      ->capture_default_str()
      ->check(finite_in(0.0, 1e9));
  cmd.add_option("--pile-up", o.rft_pileup,
                 "surface ahead of a pushing face raised by this fraction of the sinkage "
                 "(rft, with +pile-up)")
      ->capture_default_str()
      ->check(finite_in(0.0, 3.0));
  cmd.add_option("--depth-scale", o.rft_depth_scale, "zeta (1 + k d / r) (rft, with +depth-scale)")
      ->capture_default_str()
      ->check(finite_in(-0.9, 20.0));
  cmd.add_option("--shear-peak-displacement", o.shear_peak_displacement,
                 "K_w, m: shear displacement of the maximum shear stress (with +shear-peak; replaces K_s)")
      ->capture_default_str()
      ->check(finite_in(1e-4, 0.2));
}

}  // namespace

Commands make_terramechanics_commands() {
  Commands commands;
  commands.push_back(make_command<TerramechanicsOptions>(
      "terramechanics", "Drawbar pull, resistive torque, sinkage and entry angle of a rigid wheel",
      [](CLI::App& cmd, TerramechanicsOptions& o) { add_model_options(cmd, o, true); }, run_terramechanics));
  commands.push_back(make_command<SurfaceOptions>(
      "terramechanics surface",
      "Fit DP(W, s) and tau_R(W, s) polynomials (Eq. 2.28) to a model grid, as in seed 003 Appendix A",
      [](CLI::App& cmd, SurfaceOptions& o) {
        add_model_options(cmd, o.model, false);
        cmd.add_option("--load-min", o.load_min, "N")->capture_default_str()->check(finite_in(0.0, 1e6));
        cmd.add_option("--load-max", o.load_max, "N")->capture_default_str()->check(finite_in(0.0, 1e6));
        cmd.add_option("--slip-min", o.slip_min)->capture_default_str()->check(finite_in(-1.0, 1.0));
        cmd.add_option("--slip-max", o.slip_max)->capture_default_str()->check(finite_in(-1.0, 1.0));
        cmd.add_option("--grid", o.grid, "Grid points per axis")->capture_default_str()->check(CLI::Range(2, 2000));
        cmd.add_option("--order", o.order, "Polynomial order 1..6, or auto (cross-validated)")->capture_default_str();
        cmd.add_flag("--json", o.json, "Print JSON");
      },
      run_terramechanics_surface));
  commands.push_back(make_command<FitOptions>(
      "terramechanics fit",
      "Fit traction-surface polynomials to a CSV of points (load_N, slip, drawbar_pull_N / resistive_torque_Nm / "
      "lateral_force_N; per slip_angle_deg when given)",
      [](CLI::App& cmd, FitOptions& o) {
        cmd.add_option("FILE", o.file, "CSV of points")->required();
        cmd.add_option("--order", o.order, "Polynomial order 1..6, or auto (cross-validated)")->capture_default_str();
        cmd.add_option("--grid", o.grid_bins, "Occupancy grid bins per axis")
            ->capture_default_str()
            ->check(CLI::Range(1, 1000));
        cmd.add_flag("--json", o.json, "Print JSON");
      },
      run_terramechanics_fit));
  return commands;
}

}  // namespace roverlab::app

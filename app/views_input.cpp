#include "app/views_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "app/log_input.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/terramechanics/model.h"
#include "importers/rover_file.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"

namespace roverlab::app {

namespace {

bool looks_like_wheel_test_csv(const std::string& file) {
  if (std::filesystem::path(file).extension() != ".csv") return false;
  std::ifstream in(file);
  std::string header;
  while (std::getline(in, header)) {
    if (!header.empty() && header[0] != '#') break;
  }
  return header.find("load_N") != std::string::npos && header.find("slip") != std::string::npos;
}

}  // namespace

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
  const bool has_imu = in.log.find_stream("imu") != nullptr, has_wheels = in.log.find_stream("wheels") != nullptr;
  const bool has_estimate = in.log.find_stream("estimate/ins/pose") != nullptr;
  // The INS slip estimator needs a skid-steer log: wheel angles of four wheels.
  const bool skid_steer = has_wheels && in.log.stream("wheels").find_channel("angle_FL") != nullptr &&
                          in.log.stream("wheels").find_channel("angle_RR") != nullptr;
  if (o.run_estimator && has_imu && skid_steer && !has_estimate) {
    try {
      in.ins = estimation::run_ins_slip(in.log, estimation::InsSlipOptions{});
    } catch (const DataError& e) {
      throw InputError(file, e.what());
    }
    for (const auto& s : in.ins->estimates.streams()) in.log.add_stream(s);
    in.notes.push_back("ran the INS slip estimator (seed 002) on the log: estimate/ streams added");
  } else if (o.run_estimator && !has_estimate && in.log.find_stream("joints") == nullptr) {
    in.notes.push_back("no INS estimate: the log lacks an imu stream or a skid-steer wheels stream (angle_FL .. angle_RR)");
  }
  if (o.run_contact_estimator && in.log.find_stream("joints") != nullptr && has_imu && has_wheels &&
      in.log.find_stream("estimate/contact/wheels") == nullptr) {
    const std::string rover = rover_name_of(in.log);
    const io::RoverDescription d = io::find_rover(rover, resource_subfolders("rovers"));
    if (d.dh) {
      try {
        in.contact = estimation::run_contact_angle(in.log, *d.dh, view_contact_options());
      } catch (const DataError& e) {
        throw InputError(file, e.what());
      }
      for (const auto& s : in.contact->estimates.streams()) in.log.add_stream(s);
      in.notes.push_back("ran the contact-angle estimator (seed 000, model C+SS, EKF, cross-covariances reset) for rover " + rover);
    }
  }
  if (o.run_odometry_study && has_wheels && in.log.find_stream("gps") != nullptr) {
    try {
      in.odometry = analysis::study_odometry(in.log);
    } catch (const DataError& e) {
      in.notes.push_back(std::string("odometry study skipped: ") + e.what());
    }
  }
  return in;
}

std::string rover_name_of(const log::Log& lg) {
  return lg.metadata.rover_id.empty() ? "exomars_bb2" : lg.metadata.rover_id;
}

estimation::ContactAngleOptions view_contact_options() {
  estimation::ContactAngleOptions o;
  o.model = estimation::ContactModel::contact_side_slip;
  o.reset_cross_covariance = true;
  return o;
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

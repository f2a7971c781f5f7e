// `roverlab estimate ins-slip`: the error-state INS with pseudo-measurements
// and slip detection of seed 002 on a log, with its metrics against GPS or
// truth; `roverlab scenario skid-steer-slip`: the simulated log it is tested on.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/log_input.h"
#include "core/common/error.h"
#include "core/estimation/ins_slip.h"
#include "core/simulation/skid_steer_scenario.h"
#include "importers/hdf5_log.h"

namespace roverlab::app {

using nlohmann::json;
using namespace roverlab::estimation;

namespace {

json nullable(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json confusion_json(const ConfusionMatrix& c) {
  json j = {{"rows", "estimated"}, {"columns", "reference"}, {"classes", json::array()},
            {"counts", json::array()}, {"column_normalised", json::array()}};
  for (int k = 0; k < kSlipClasses; ++k) j["classes"].push_back(to_string(static_cast<SlipClass>(k)));
  for (int e = 0; e < kSlipClasses; ++e) {
    json counts = json::array(), fractions = json::array();
    for (int t = 0; t < kSlipClasses; ++t) {
      counts.push_back(c.counts[static_cast<std::size_t>(e)][static_cast<std::size_t>(t)]);
      fractions.push_back(nullable(c.fraction(e, t)));
    }
    j["counts"].push_back(counts);
    j["column_normalised"].push_back(fractions);
  }
  j["accuracy"] = nullable(c.accuracy());
  return j;
}

void print_confusion(const ConfusionMatrix& c) {
  std::printf("slip classes, column-normalised (%% of each reference class; rows: estimated):\n");
  std::printf("  %-10s", "");
  for (int t = 0; t < kSlipClasses; ++t) std::printf(" %8s", to_string(static_cast<SlipClass>(t)));
  std::printf("\n");
  for (int e = 0; e < kSlipClasses; ++e) {
    std::printf("  %-10s", to_string(static_cast<SlipClass>(e)));
    for (int t = 0; t < kSlipClasses; ++t) {
      const double f = c.fraction(e, t);
      if (std::isfinite(f)) {
        std::printf(" %7.1f%%", 100.0 * f);
      } else {
        std::printf(" %8s", "-");
      }
    }
    std::printf("\n");
  }
  std::printf("  %-10s", "# samples");
  for (int t = 0; t < kSlipClasses; ++t) std::printf(" %8ld", c.truth_total(t));
  std::printf("\n  overall accuracy %.1f %% of %ld samples\n", 100.0 * c.accuracy(), c.total());
}

}  // namespace

int run_estimate_ins_slip(const InsSlipCommandOptions& o) {
  const log::Log lg = load_input(o.file, o.mapping).log;
  InsSlipOptions options;
  options.zupt = !o.no_zupt;
  options.zaru = !o.no_zaru;
  options.nhc = !o.no_nhc;
  options.odometry_aiding = !o.no_odometry_aiding;
  options.odometry_sigma = o.odometry_sigma;
  options.smooth = !o.no_smoother;
  if (isatty(2)) {
    options.progress = [](double f) { std::fprintf(stderr, "\rins-slip %3d %%", static_cast<int>(100.0 * f)); };
  }
  InsSlipResult r;
  try {
    r = run_ins_slip(lg, options);
  } catch (const DataError& e) {
    throw InputError(o.file, e.what());
  }
  if (options.progress) std::fprintf(stderr, "\r              \r");
  if (o.output) {
    log::Log out = lg;
    for (const auto& s : r.estimates.streams()) out.add_stream(s);
    out.metadata.extra["estimator"] = r.estimates.metadata.extra["estimator"];
    io::write_hdf5_log(out, *o.output);
  }
  const InsSlipMetrics& m = r.metrics;
  const double deg = 180.0 / M_PI;
  if (o.json) {
    json j = {{"file", o.file},
              {"updates", {{"zupt", options.zupt}, {"zaru", options.zaru}, {"nhc", options.nhc},
                           {"odometry_aiding", options.odometry_aiding},
                           {"smoother", options.smooth}}},
              {"duration_s", m.duration},
              {"standstill_fraction", m.standstill_fraction},
              {"has_reference", m.has_reference}};
    if (m.has_reference) {
      j["distance_m"] = m.distance;
      j["ins"] = {{"final_position_error_m", m.final_position_error},
                  {"final_position_error_3d_m", m.final_position_error_3d},
                  {"position_rmse_m", m.position_rmse},
                  {"position_rmse_enu_m", {m.position_rmse_axes.east, m.position_rmse_axes.north, m.position_rmse_axes.up}},
                  {"velocity_rmse_mps", m.velocity_rmse},
                  {"heading_drift_rad", nullable(m.heading_drift)}};
      j["wheel_odometry"] = {{"final_position_error_m", r.odometry.final_position_error},
                             {"position_rmse_m", r.odometry.position_rmse}};
    }
    if (m.confusion.total() > 0) j["slip_confusion"] = confusion_json(m.confusion);
    if (o.output) j["output"] = *o.output;
    std::cout << j.dump(2) << "\n";
    return kSuccess;
  }

  std::printf("%s: %.1f s of IMU data, standstill %.0f %% of it\n", o.file.c_str(), m.duration,
              100.0 * m.standstill_fraction);
  std::printf("updates: ZUPT %s, ZARU %s, NHC %s, wheel-speed aiding %s; %s\n", options.zupt ? "on" : "off",
              options.zaru ? "on" : "off", options.nhc ? "on" : "off",
              options.odometry_aiding ? "on (slip judged by a second pass without it)" : "off",
              options.smooth ? "RTS-smoothed" : "forward filter only");
  if (m.has_reference) {
    std::printf("\nposition against GPS over %.1f m of track:\n", m.distance);
    std::printf("  %-28s %10s %10s   %s\n", "", "final (m)", "RMSE (m)", "RMSE east / north / up (m)");
    std::printf("  %-28s %10.2f %10.2f   %.2f / %.2f / %.2f\n", options.odometry_aiding ? "INS + pseudo-meas. + wheels" : "INS + pseudo-measurements", m.final_position_error,
                m.position_rmse, m.position_rmse_axes.east, m.position_rmse_axes.north, m.position_rmse_axes.up);
    std::printf("  %-28s %10.2f %10.2f\n", "wheel odometry", r.odometry.final_position_error, r.odometry.position_rmse);
    std::printf("velocity RMSE %.3f m/s; heading drift %.2f deg (last 5 s of driving)\n", m.velocity_rmse,
                m.heading_drift * deg);
  } else {
    std::printf("no GPS stream: no position metrics\n");
  }
  if (m.confusion.total() > 0) {
    std::printf("\n");
    print_confusion(m.confusion);
  }
  if (o.output) std::printf("\nwrote %s\n", o.output->c_str());
  return kSuccess;
}

int run_scenario_skid_steer(const SkidSteerScenarioOptions& o) {
  simulation::SkidSteerScenario scenario = simulation::default_slip_scenario(o.seed);
  apply_effect_options(o.effects, [&](const std::string& name, double value) { simulation::set_effect(scenario, name, value); });
  const log::Log lg = simulation::simulate_skid_steer(scenario);
  io::write_hdf5_log(lg, o.output);
  std::printf("wrote %s: %zu streams, %.1f s, seed %u\n", o.output.c_str(), lg.streams().size(),
              lg.stream("imu").duration(), o.seed);
  return kSuccess;
}

}  // namespace roverlab::app

// `roverlab discrepancy single-wheel`: what the baseline terramechanics model
// gets wrong on measured single-wheel points, the cause, and the gain.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include "app/commands.h"
#include "app/resources.h"
#include "app/log_input.h"
#include "core/analysis/odometry_discrepancy.h"
#include "core/analysis/single_wheel_discrepancy.h"
#include "core/common/error.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"

namespace roverlab::app {

using nlohmann::json;
using namespace roverlab::terramechanics;

namespace {

json nullable(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json stats_json(const std::vector<analysis::QuantityResiduals>& stats) {
  json j = json::object();
  for (const auto& s : stats) {
    j[to_string(s.quantity)] = {{"count", s.count}, {"rmse", s.rmse}, {"bias", s.bias},
                                {"slope_vs_slip", s.slope_vs_slip}, {"t_slip", s.t_slip},
                                {"slope_vs_load", s.slope_vs_load}, {"t_load", s.t_load},
                                {"unit", unit_of(s.quantity)}};
  }
  return j;
}

}  // namespace

int run_discrepancy_single_wheel(const SingleWheelDiscrepancyOptions& o) {
  const auto points = io::read_wheel_test_csv(o.file);
  const Soil soil = io::find_soil(o.soil, resource_subfolders("soils"));
  analysis::DiscrepancyOptions options;
  try {
    options.baseline.integration = parse_integration(o.integration);
  } catch (const DataError& e) {
    throw UsageError(e.what());
  }
  const analysis::DiscrepancyReport r = analysis::study_single_wheel(soil, points, options);

  if (o.json) {
    json j = {{"file", o.file}, {"soil", soil.name}, {"points", r.points},
              {"measurements", r.measurements}, {"unsupported", r.unsupported},
              {"baseline", {{"residuals", stats_json(r.baseline)}, {"score_sigma", r.baseline_score},
                            {"bic", r.baseline_bic}}},
              {"significant", r.significant},
              {"cause", r.significant ? json(r.candidates[static_cast<std::size_t>(r.best)].name) : json(nullptr)},
              {"what_is_wrong", r.what_is_wrong}, {"verdict", r.verdict}};
    j["partial"] = json::array();
    for (const auto& [q, index] : r.partial) {
      j["partial"].push_back({{"quantity", to_string(q)}, {"candidate", r.candidates[static_cast<std::size_t>(index)].name}});
    }
    j["candidates"] = json::array();
    for (const auto& c : r.candidates) {
      json cj = {{"name", c.name}, {"cause", c.cause}, {"applicable", c.applicable}};
      if (!c.applicable) {
        cj["not_applicable_because"] = c.not_applicable_because;
      } else {
        cj["parameters"] = json::array();
        for (const auto& p : c.fit.parameters) {
          cj["parameters"].push_back({{"name", to_string(p.parameter)}, {"value", p.value},
                                      {"sigma", nullable(p.sigma)}, {"at_bound", p.at_bound}});
        }
        cj["bic"] = c.bic;
        cj["delta_bic"] = c.delta_bic;
        cj["in_sample_residuals"] = stats_json(c.in_sample);
        cj["held_out_score_sigma"] = c.held_out_score;
        json ho = json::object(), base = json::object();
        for (std::size_t i = 0; i < r.quantities.size(); ++i) {
          ho[to_string(r.quantities[i])] = nullable(c.held_out_rmse[i]);
        }
        cj["held_out_rmse"] = ho;
      }
      j["candidates"].push_back(cj);
    }
    json base = json::object();
    for (std::size_t i = 0; i < r.quantities.size(); ++i) base[to_string(r.quantities[i])] = r.baseline_held_out_rmse[i];
    j["baseline"]["held_out_rmse"] = base;
    std::cout << j.dump(2) << "\n";
    return kSuccess;
  }

  std::printf("%s: %zu points, %zu measurements, soil %s, baseline Wong-Reece (%s)\n", o.file.c_str(), r.points,
              r.measurements, soil.name.c_str(), o.integration.c_str());
  if (r.unsupported > 0) std::printf("  %zu measurements at loads the model cannot carry (skipped)\n", r.unsupported);
  std::printf("\nbaseline residuals (predicted - measured):\n");
  std::printf("  %-13s %5s %12s %12s %16s %16s\n", "quantity", "n", "RMSE", "bias", "trend/slip (t)", "trend/100N (t)");
  for (const auto& s : r.baseline) {
    const double k = s.quantity == Quantity::sinkage ? 1000.0 : 1.0;
    const char* u = s.quantity == Quantity::sinkage ? "mm" : unit_of(s.quantity);
    std::printf("  %-13s %5zu %9.3f %-3s %8.3f %-3s %9.3f (%5.1f) %9.3f (%5.1f)\n", to_string(s.quantity), s.count,
                s.rmse * k, u, s.bias * k, u, s.slope_vs_slip * k, s.t_slip, s.slope_vs_load * k * 100.0, s.t_load);
  }
  std::printf("\ncandidate causes (each fitted with Ceres; held-out = leave-one-out):\n");
  std::printf("  %-14s %-24s %22s %10s %14s\n", "candidate", "parameter", "value +- 1 sigma", "delta BIC", "held-out sigma");
  std::printf("  %-14s %-24s %22s %10s %14.3f\n", "(baseline)", "-", "-", "0", r.baseline_score);
  for (const auto& c : r.candidates) {
    if (!c.applicable) {
      std::printf("  %-14s not applicable: %s\n", c.name.c_str(), c.not_applicable_because.c_str());
      continue;
    }
    for (std::size_t i = 0; i < c.fit.parameters.size(); ++i) {
      const auto& p = c.fit.parameters[i];
      char value[64];
      std::snprintf(value, sizeof value, "%.4g +- %.2g%s", p.value, p.sigma, p.at_bound ? " (bound)" : "");
      if (i == 0) {
        std::printf("  %-14s %-24s %22s %10.1f %14.3f\n", c.name.c_str(), to_string(p.parameter), value,
                    c.delta_bic, c.held_out_score);
      } else {
        std::printf("  %-14s %-24s %22s\n", "", to_string(p.parameter), value);
      }
    }
  }
  std::printf("\n%s\n%s\n", r.what_is_wrong.c_str(), r.verdict.c_str());
  return kSuccess;
}

}  // namespace roverlab::app

namespace roverlab::app {

int run_discrepancy_odometry(const OdometryDiscrepancyOptions& o) {
  const log::Log lg = load_input(o.file, o.mapping).log;
  analysis::OdometryStudyOptions options;
  options.fit_fraction = o.fit_fraction;
  analysis::OdometryDiscrepancyReport r;
  try {
    r = analysis::study_odometry(lg, options);
  } catch (const DataError& e) {
    throw InputError(o.file, e.what());
  }
  if (o.json) {
    json j = {{"file", o.file},
              {"distance_m", r.distance},
              {"fit_distance_m", r.fit_distance},
              {"split_time_s", r.split_time},
              {"reference_samples", {{"fit", r.fit_samples}, {"test", r.test_samples}}},
              {"baseline", {{"fit_rmse_m", r.baseline_fit_rmse}, {"held_out_rmse_m", r.baseline_held_out_rmse},
                            {"held_out_final_m", r.baseline_held_out_final}, {"distance_ratio", r.distance_ratio},
                            {"heading_error_rad", nullable(r.heading_error_end)},
                            {"along_track_rmse_m", nullable(r.along_track_rmse)},
                            {"cross_track_rmse_m", nullable(r.cross_track_rmse)}}},
              {"cause", r.best >= 0 ? json(r.candidates[static_cast<std::size_t>(r.best)].name) : json(nullptr)},
              {"what_is_wrong", r.what_is_wrong},
              {"verdict", r.verdict},
              {"candidates", json::array()}};
    for (const auto& c : r.candidates) {
      json cj = {{"name", c.name}, {"cause", c.cause}, {"parameters", json::array()},
                 {"fit_rmse_m", c.fit_rmse}, {"delta_bic", c.delta_bic}, {"held_out_rmse_m", c.held_out_rmse},
                 {"held_out_final_m", c.held_out_final}, {"significant", c.significant}};
      for (const auto& p : c.parameters) {
        cj["parameters"].push_back({{"name", p.name}, {"value", p.value}, {"sigma", nullable(p.sigma)}});
      }
      j["candidates"].push_back(cj);
    }
    std::cout << j.dump(2) << "\n";
    return kSuccess;
  }
  std::printf("%s: %.1f m of reference track; fit on the first %.1f m (to t = %.1f s), test on the rest\n\n",
              o.file.c_str(), r.distance, r.fit_distance, r.split_time);
  std::printf("%s\n\n", r.what_is_wrong.c_str());
  std::printf("  %-16s %-30s %9s %10s %13s %12s\n", "candidate", "fitted", "fit RMSE", "delta BIC", "held-out RMSE",
              "final error");
  std::printf("  %-16s %-30s %7.2f m %10s %11.2f m %10.2f m\n", "(baseline)", "nominal geometry", r.baseline_fit_rmse,
              "0", r.baseline_held_out_rmse, r.baseline_held_out_final);
  for (const auto& c : r.candidates) {
    std::string params;
    for (const auto& p : c.parameters) {
      char one[80];
      if (std::isfinite(p.sigma)) {
        std::snprintf(one, sizeof one, "%s%.4g+-%.2g", params.empty() ? "" : " ", p.value, p.sigma);
      } else if (p.name == "windows") {
        std::snprintf(one, sizeof one, "%s%d windows", params.empty() ? "" : " ", static_cast<int>(p.value));
      } else {
        std::snprintf(one, sizeof one, "%s%s %.3g", params.empty() ? "" : ", ", p.name.c_str(), p.value);
      }
      params += one;
    }
    if (params.size() > 30) params = params.substr(0, 29) + "~";
    std::printf("  %-16s %-30s %7.2f m %10.1f %11.2f m %10.2f m%s\n", c.name.c_str(), params.c_str(), c.fit_rmse,
                c.delta_bic, c.held_out_rmse, c.held_out_final, c.significant ? "" : "  (not significant)");
  }
  std::printf("\n%s\n", r.verdict.c_str());
  return kSuccess;
}

}  // namespace roverlab::app

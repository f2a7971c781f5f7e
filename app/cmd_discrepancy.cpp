// `roverlab discrepancy single-wheel`: what the baseline terramechanics model
// gets wrong on measured single-wheel points, the cause, and the gain.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <nlohmann/json.hpp>

#include <CLI/CLI.hpp>

#include "app/analysis.h"
#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/single_wheel/study.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"

namespace roverlab::app {

struct SingleWheelDiscrepancyOptions {
  std::string file;
  std::string soil;
  std::string integration = "simpson";
  std::string hold_out = "points";
  std::string slip_definition = "auto";
  std::string family = "auto";
  bool json = false;
};

using nlohmann::json;
using namespace roverlab::terramechanics;

namespace {

json stats_json(const std::vector<analysis::QuantityResiduals>& stats) {
  json j = json::object();
  for (const auto& s : stats) {
    j[to_string(s.quantity)] = {{"count", s.count},
                                {"rmse", s.rmse},
                                {"bias", s.bias},
                                {"slope_vs_slip", s.slope_vs_slip},
                                {"t_slip", s.t_slip},
                                {"t_bias", s.t_bias},
                                {"slope_vs_load", s.slope_vs_load},
                                {"t_load", s.t_load},
                                {"slope_vs_slip_angle_per_rad", s.slope_vs_slip_angle},
                                {"t_slip_angle", s.t_slip_angle},
                                {"unit", unit_of(s.quantity)}};
  }
  return j;
}

// The named steps of the forward selection, " + "-joined; null when none
// (a step only "also consistent with" the data, or at its bound, is none).
json cause_json(const analysis::DiscrepancyReport& r) {
  const std::string names = analysis::named_causes(r);
  return names.empty() ? json(nullptr) : json(names);
}

// The model families compared (issue 43): each one's baseline and final model held out.
json families_json(const analysis::DiscrepancyReport& r) {
  json out = json::array();
  for (const auto& f : r.families) {
    json fj = {{"family", f.family},
               {"held_out_score_sigma", finite_or_null(f.held_out_score)},
               {"held_out_method", f.held_out_method},
               {"final_model", f.final_model},
               {"final_held_out_score_sigma", finite_or_null(f.final_held_out_score)},
               {"final_studied_points", f.final_studied_points(r.points)}};
    json ho = json::object();
    for (std::size_t i = 0; i < r.quantities.size() && i < f.held_out_rmse.size(); ++i) {
      ho[to_string(r.quantities[i])] = finite_or_null(f.held_out_rmse[i]);
    }
    fj["held_out_rmse"] = ho;
    fj["parameters"] = json::array();
    for (const auto& p : f.parameters) {
      fj["parameters"].push_back({{"name", to_string(p.parameter)},
                                  {"value", p.value},
                                  {"sigma", finite_or_null(p.sigma)},
                                  {"at_bound", p.at_bound}});
    }
    out.push_back(fj);
  }
  return out;
}

// The study as a JSON document (`--json`).
json report_json(const std::string& file, const Soil& soil, const analysis::DiscrepancyReport& r) {
  json j = {
      {"file", file},
      {"soil", soil.name},
      {"baseline_model", r.baseline_model},
      {"slip_definition", r.slip_definition.empty() ? json(nullptr) : json(r.slip_definition)},
      {"slip_definition_reason", r.slip_definition_reason},
      {"points", r.points},
      {"measurements", r.measurements},
      {"held_out_method", r.held_out_method},
      {"step_screen_points", r.step_screen_points},
      {"unsupported", r.unsupported},
      {"baseline", {{"residuals", stats_json(r.baseline)}, {"score_sigma", r.baseline_score}, {"bic", r.baseline_bic}}},
      {"significant", r.significant},
      {"cause", cause_json(r)},
      {"what_is_wrong", r.what_is_wrong},
      {"verdict", r.verdict}};
  j["quantities"] = json::array();
  for (const auto& v : r.quantity_verdicts) {
    j["quantities"].push_back({{"quantity", to_string(v.quantity)},
                               {"significant", v.significant},
                               {"explained_by", v.explained_by.empty() ? json(nullptr) : json(v.explained_by)},
                               {"best_candidate", v.best_candidate},
                               {"held_out_rmse_before", finite_or_null(v.held_out_before)},
                               {"held_out_rmse_after", finite_or_null(v.held_out_after)},
                               {"sentence", v.sentence}});
  }
  j["partial"] = json::array();
  for (const auto& [q, index] : r.partial) {
    j["partial"].push_back(
        {{"quantity", to_string(q)}, {"candidate", r.candidates[static_cast<std::size_t>(index)].name}});
  }
  j["candidates"] = json::array();
  for (const auto& c : r.candidates) {
    json cj = {{"name", c.name}, {"cause", c.cause}, {"applicable", c.applicable}};
    if (!c.applicable) {
      cj["not_applicable_because"] = c.not_applicable_because;
    } else {
      cj["parameters"] = json::array();
      for (const auto& p : c.fit.parameters) {
        cj["parameters"].push_back({{"name", to_string(p.parameter)},
                                    {"value", p.value},
                                    {"sigma", finite_or_null(p.sigma)},
                                    {"at_bound", p.at_bound}});
      }
      cj["bic"] = c.bic;
      cj["delta_bic"] = c.delta_bic;
      cj["in_sample_residuals"] = stats_json(c.in_sample);
      cj["held_out_score_sigma"] = c.held_out_score;
      json ho = json::object(), base = json::object();
      for (std::size_t i = 0; i < r.quantities.size(); ++i) {
        ho[to_string(r.quantities[i])] = finite_or_null(c.held_out_rmse[i]);
      }
      cj["held_out_rmse"] = ho;
    }
    j["candidates"].push_back(cj);
  }
  // Forward selection: each step's model (the chain so far plus one cause).
  j["selection"] = json::array();
  for (const auto& c : r.selection) {
    json step = {{"model", c.name},
                 {"bic", c.bic},
                 {"delta_bic", c.delta_bic},
                 {"held_out_score_sigma", c.held_out_score},
                 {"gain_share", finite_or_null(c.gain_share)},
                 {"role", analysis::step_role_name(c.role)},
                 {"parameters", json::array()}};
    json ho = json::object();
    for (std::size_t i = 0; i < r.quantities.size() && i < c.held_out_rmse.size(); ++i) {
      ho[to_string(r.quantities[i])] = finite_or_null(c.held_out_rmse[i]);
    }
    step["held_out_rmse"] = ho;
    for (const auto& p : c.fit.parameters) {
      step["parameters"].push_back({{"name", to_string(p.parameter)},
                                    {"value", p.value},
                                    {"sigma", finite_or_null(p.sigma)},
                                    {"at_bound", p.at_bound}});
    }
    j["selection"].push_back(step);
  }
  if (r.best_pair) {
    j["best_pair"] = {
        {"model", r.best_pair->name},
        {"delta_bic", finite_or_null(r.best_pair->delta_bic)},
        {"held_out_score_sigma",
         r.best_pair->held_out_rmse.empty() ? json(nullptr) : finite_or_null(r.best_pair->held_out_score)}};
  }
  j["final_model"] = r.final_model;
  j["family_choice"] = r.family_choice;
  j["families"] = families_json(r);
  j["per_wheel"] = json::array();
  for (const auto& w : r.per_wheel) {
    j["per_wheel"].push_back({{"wheel", w.wheel},
                              {"quantity", to_string(w.quantity)},
                              {"count", w.count},
                              {"baseline_rmse", finite_or_null(w.baseline_rmse)},
                              {"held_out_rmse", finite_or_null(w.model_rmse)}});
  }
  json base = json::object();
  for (std::size_t i = 0; i < r.quantities.size(); ++i) base[to_string(r.quantities[i])] = r.baseline_held_out_rmse[i];
  j["baseline"]["held_out_rmse"] = base;
  return j;
}

}  // namespace

namespace {
void print_report(const std::string& path, const Soil& soil, const analysis::DiscrepancyReport& r,
                  const std::string& integration);
}  // namespace

int run_discrepancy_single_wheel(const SingleWheelDiscrepancyOptions& o) {
  const io::WheelTestFile file = io::read_wheel_test_file(o.file);
  for (const auto& warning : file.warnings) {
    std::fprintf(stderr, "warning: %s: %s\n", o.file.c_str(), printable(warning, 1000).c_str());
  }
  const auto& points = file.points;
  // The study's time grows with its points (about 0.1 s a point on 1,000-2,000 rows, docs/robustness.md).
  constexpr std::size_t kManyPoints = 5000;
  if (points.size() > kManyPoints) {
    std::fprintf(stderr,
                 "warning: %s: %zu points: the study takes about 0.1 s a point (%.0f min); a subset is faster\n",
                 o.file.c_str(), points.size(), 0.1 * static_cast<double>(points.size()) / 60.0);
  }
  const Soil soil = io::find_soil(o.soil, resource_subfolders("soils"));
  analysis::DiscrepancyOptions options;
  try {
    options.baseline.integration = parse_integration(o.integration);
    options.hold_out = analysis::parse_hold_out(o.hold_out);
    // The option, else the file's own statement (a travel_slip or longitudinal_slip column).
    const std::string stated = o.slip_definition != "auto" ? o.slip_definition : file.slip_definition;
    if (!stated.empty()) options.slip_definition = parse_slip_definition(stated);
    options.compare_families = o.family == "auto";
    if (o.family == "rft") options.baseline.kind = ModelKind::rft;
  } catch (const DataError& e) {
    throw UsageError(e.what());
  }
  analysis::DiscrepancyReport r = about_file(o.file, [&] {
    const ProgressLine progress("single-wheel study");
    options.progress = progress.callback();
    if (options.progress) options.progress(0.0);  // shown from the start, not after the first phase
    return analysis::study_single_wheel(soil, points, options);
  });
  if (o.slip_definition == "auto" && !file.slip_definition.empty() && !r.slip_definition.empty()) {
    r.slip_definition_reason = "stated by the file (its column " + file.slip_definition + "_slip)";
  }

  if (o.json) {
    json j = report_json(o.file, soil, r);
    // The file does not state its slip definition and the readings differ: the other one, complete.
    if (!r.other_reading.empty()) j["other_reading"] = report_json(o.file, soil, r.other_reading.front());
    std::cout << j.dump(2) << "\n";
    return kSuccess;
  }
  // Each reading's heading gives its final model's held-out score: the
  // reading whose model does not fit is not read as if it did.
  const auto heading = [](const analysis::DiscrepancyReport& reading) {
    std::printf("=== Read as %s slip (final model held out at %.2f sigma) ===\n", reading.slip_definition.c_str(),
                analysis::final_held_out_score(reading));
  };
  if (!r.other_reading.empty()) {
    std::printf("%s: %s.\n\n", o.file.c_str(), r.slip_definition_reason.c_str());
    heading(r);
  }
  print_report(o.file, soil, r, o.integration);
  for (const auto& other : r.other_reading) {
    std::printf("\n");
    heading(other);
    print_report(o.file, soil, other, o.integration);
  }
  return kSuccess;
}

namespace {

void print_report(const std::string& path, const Soil& soil, const analysis::DiscrepancyReport& r,
                  const std::string& integration) {
  std::printf("%s: %zu points, %zu measurements, soil %s, baseline %s (%s)\n", path.c_str(), r.points, r.measurements,
              soil.name.c_str(), r.baseline_model.c_str(), integration.c_str());
  if (!r.slip_definition.empty()) {
    std::printf("  slip at a slip angle read as %s slip (%s)\n", r.slip_definition.c_str(),
                r.slip_definition_reason.c_str());
  }
  if (!r.family_choice.empty()) std::printf("  %s\n", r.family_choice.c_str());
  for (const auto& f : r.families) {
    for (const auto& p : f.parameters) {
      std::printf("    %s: %s = %s\n", f.family.c_str(), to_string(p.parameter),
                  analysis::format_fitted(p.value, p.sigma, "1", p.at_bound).c_str());
    }
  }
  if (r.unsupported > 0) std::printf("  %zu measurements at loads the model cannot carry (skipped)\n", r.unsupported);
  std::printf("\nbaseline residuals (predicted - measured):\n");
  std::printf("  %-13s %5s %12s %12s %16s %16s\n", "quantity", "n", "RMSE", "bias", "trend/slip (t)", "trend/100N (t)");
  for (const auto& s : r.baseline) {
    const double k = s.quantity == Quantity::sinkage ? 1000.0 : 1.0;
    const char* u = s.quantity == Quantity::sinkage ? "mm" : unit_of(s.quantity);
    std::printf("  %-13s %5zu %9.3f %-3s %8.3f %-3s %9.3f (%5.1f) %9.3f (%5.1f)\n", to_string(s.quantity), s.count,
                s.rmse * k, u, s.bias * k, u, s.slope_vs_slip * k, s.t_slip, s.slope_vs_load * k * 100.0, s.t_load);
  }
  std::printf("\ncandidate causes (each fitted with Ceres; held-out = %s):\n", r.held_out_method.c_str());
  std::printf("  %-20s %-24s %22s %10s %14s\n", "candidate", "parameter", "value +- 1 sigma", "delta BIC",
              "held-out sigma");
  std::printf("  %-20s %-24s %22s %10s %14.3f\n", "(baseline)", "-", "-", "0", r.baseline_score);
  for (const auto& c : r.candidates) {
    if (!c.applicable) {
      std::printf("  %-20s not applicable: %s\n", c.name.c_str(), c.not_applicable_because.c_str());
      continue;
    }
    for (std::size_t i = 0; i < c.fit.parameters.size(); ++i) {
      const auto& p = c.fit.parameters[i];
      char value[64];
      if (p.at_bound) {  // the search stopped at a bound: a fact about the search, no sigma
        std::snprintf(value, sizeof value, "%.4g (at its bound)", p.value);
      } else if (std::isfinite(p.sigma)) {
        std::snprintf(value, sizeof value, "%.4g +- %.2g", p.value, p.sigma);
      } else {  // the data cannot pin it down: no sigma to show
        std::snprintf(value, sizeof value, "%.4g (undetermined)", p.value);
      }
      if (i == 0) {
        std::printf("  %-20s %-24s %22s %10s %14.3f\n", c.name.c_str(), to_string(p.parameter), value,
                    analysis::format_delta_bic(c.delta_bic).c_str(), c.held_out_score);
      } else {
        std::printf("  %-20s %-24s %22s\n", "", to_string(p.parameter), value);
      }
    }
  }
  std::printf("\nheld-out RMSE per quantity (%s):\n  %-20s", r.held_out_method.c_str(), "model");
  for (Quantity q : r.quantities) std::printf(" %16s", to_string(q));
  const auto rmse_row = [&](const std::string& name, const std::vector<double>& rmse) {
    std::printf("\n  %-20s", name.c_str());
    for (std::size_t i = 0; i < r.quantities.size() && i < rmse.size(); ++i) {
      const bool mm = r.quantities[i] == Quantity::sinkage;
      std::printf(" %12.3f %-3s", rmse[i] * (mm ? 1000.0 : 1.0), mm ? "mm" : unit_of(r.quantities[i]));
    }
  };
  rmse_row("(baseline)", r.baseline_held_out_rmse);
  for (const auto& c : r.candidates) {
    if (c.applicable) rmse_row(c.name, c.held_out_rmse);
  }
  std::printf("\n");
  if (!r.selection.empty()) {
    std::printf("\nforward selection (each step refits the chain with one more cause):\n");
    if (r.step_screen_points > 0) {
      std::printf(
          "  (each step's candidates ranked on a random subset of %zu of the %zu points, the best there "
          "refitted on all of them)\n",
          r.step_screen_points, r.points);
    }
    std::printf("  %-48s %12s %14s %7s  %s\n", "model", "delta BIC", "held-out sigma", "share", "role");
    for (const auto& c : r.selection) {
      std::printf("  %-48s %12s %14.3f %5.3g %%  %s\n", c.name.c_str(), analysis::format_delta_bic(c.delta_bic).c_str(),
                  c.held_out_score, 100.0 * c.gain_share, analysis::step_role_name(c.role));
    }
  } else if (r.best_pair && r.best_pair->applicable) {
    std::printf("\nforward selection: no step passes; the best pair, %s: delta BIC %s%s\n", r.best_pair->name.c_str(),
                analysis::format_delta_bic(r.best_pair->delta_bic).c_str(),
                r.best_pair->held_out_rmse.empty()
                    ? " (not held out: its BIC does not pass)"
                    : (", held-out " + std::to_string(r.best_pair->held_out_score) + " sigma").c_str());
  }
  std::printf("\nper wheel (baseline RMSE -> %s, held out):\n", r.final_model.c_str());
  for (const auto& w : r.per_wheel) {
    const double k = w.quantity == Quantity::sinkage ? 1000.0 : 1.0;
    const char* u = w.quantity == Quantity::sinkage ? "mm" : unit_of(w.quantity);
    std::printf("  %-20s %-14s %4zu %9.3f -> %9.3f %s\n", printable(w.wheel, 60).c_str(), to_string(w.quantity),
                w.count, w.baseline_rmse * k, w.model_rmse * k, u);
  }
  std::printf("\n%s\n%s\n", r.what_is_wrong.c_str(), r.verdict.c_str());
}

}  // namespace

Commands make_single_wheel_commands() {
  Commands commands;
  commands.push_back(make_command<SingleWheelDiscrepancyOptions>(
      "discrepancy single-wheel", "Baseline Wong-Reece against measured single-wheel points: residuals, cause, gain",
      [](CLI::App& cmd, SingleWheelDiscrepancyOptions& o) {
        cmd.add_option("FILE", o.file,
                       "CSV: radius_m, width_m, load_N, slip and drawbar_pull_N / torque_Nm / sinkage_m")
            ->required();
        cmd.add_option("--soil", o.soil, "Soil NAME (resources/soils/NAME.json) or FILE")->required();
        cmd.add_option("--integration", o.integration, "simpson | riemann")->capture_default_str();
        cmd.add_option(
               "--hold-out", o.hold_out,
               "points | wheel | slip: what a held-out fold is (points: leave-one-out up to 100 points, 10 folds "
               "above, 5 above 2000; every point of one wheel; of one slip)")
            ->capture_default_str();
        cmd.add_option("--slip-definition", o.slip_definition,
                       "auto | longitudinal (s = 1 - v_x / (r w), Ishigami 2007) | travel (s = 1 - |v| / (r w)): how "
                       "the file's slip is read at a slip angle; auto: as the file states it (a travel_slip or "
                       "longitudinal_slip column), else chosen from the data")
            ->capture_default_str()
            ->check(CLI::IsMember({"auto", "longitudinal", "travel"}));
        cmd.add_option("--family", o.family,
                       "wong (Wong-Reece / Ishigami) | rft (resistive force theory, its material scale fitted) | "
                       "auto (both as baselines, the one with the lower held-out error taken; the default)")
            ->capture_default_str()
            ->check(CLI::IsMember({"wong", "rft", "auto"}));
        cmd.add_flag("--json", o.json, "Print JSON");
      },
      run_discrepancy_single_wheel));
  return commands;
}

}  // namespace roverlab::app

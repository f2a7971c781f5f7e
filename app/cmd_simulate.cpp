// `roverlab simulate rocker-bogie`: the planar rocker-bogie dynamics of seed
// 003 chapter 4 over a wheel-centre path, written as a log with truth streams.
#include <chrono>
#include <cmath>
#include <cstdio>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "app/rover_scenario.h"
#include "core/common/error.h"
#include "core/simulation/effects.h"
#include "core/simulation/random_effects.h"
#include "core/simulation/rocker_bogie.h"
#include "importers/hdf5_log.h"
#include "importers/rover_file.h"
#include "importers/scenario_file.h"
#include "importers/soil_file.h"

namespace roverlab::app {

struct SimulateOptions {
  std::string scenario;  // NAME (resources/scenarios) or FILE
  unsigned seed = 1;
  std::vector<std::string> effects;  // NAME=VALUE
  std::optional<std::string> traction;
  std::optional<double> duration;
  std::string output;
};

int run_simulate_rocker_bogie(const SimulateOptions& o) {
  require_log_output(o.output, "--output");
  const io::ScenarioFile scenario = io::find_scenario(o.scenario, resource_subfolders("scenarios"));
  refuse_overwriting_input(scenario.file, o.output, "--output");
  analysis::RoverScenarioModel model = load_rover_scenario(scenario, o.traction);
  simulation::RockerBogieRun& run = model.run;
  const double duration = o.duration.value_or(run.duration);
  if (!(duration >= 0.1 && duration <= 100000)) throw UsageError("--duration must be in [0.1, 100000] s");
  run.duration = duration;
  run.seed = o.seed;
  std::vector<std::string> effects;
  for (const auto& e : o.effects) {
    if (e != "random") {
      effects.push_back(e);
      continue;
    }
    // Hidden effects drawn from the seed; recorded only in the truth metadata.
    const double distance = 0.7 * model.parameters.desired_speed * duration;
    for (const auto& [name, value] : simulation::random_effects(o.seed, duration, distance).effects) {
      simulation::set_effect(run.effects, name, value);
    }
  }
  apply_effect_options(
      effects, [&](const std::string& name, double value) { simulation::set_effect(run.effects, name, value); });
  const auto& params = model.parameters;
  const auto& g = model.geometry;
  const std::string traction = model.traction;
  const auto start = std::chrono::steady_clock::now();
  simulation::RockerBogieResult r;
  {
    const ProgressLine progress("simulating", ProgressLine::Style::bar);
    run.progress = progress.callback();
    r = about_file(model.file, [&] { return simulation::simulate_rocker_bogie(g, params, run); });
    r.log.metadata.extra["scenario"] = model.name;
    // The scenario itself: a study of this log models it, not a file that may have changed or a
    // bundled scenario of the same name.
    r.log.metadata.extra["scenario_json"] = scenario.document;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::write_hdf5_log(r.log, o.output);
  const auto& pose = r.log.stream("truth/pose");
  std::printf(
      "wrote %s: scenario %s, %.0f s on the %s path, soil %s, %s traction; %.2f m driven; largest constraint error "
      "%.2g m; %.2f s\n",
      o.output.c_str(), model.name.c_str(), duration, run.path.name.c_str(), run.soil.name.c_str(), traction.c_str(),
      pose.channel("x").values.back() - pose.channel("x").values.front(), r.max_constraint_error, wall);
  if (r.unsupported > 0)
    std::printf("note: %zu traction evaluations beyond what the soil carries (set to 0)\n", r.unsupported);
  const std::string stuck = simulation::stuck_note(r.log, params.desired_speed, duration);
  if (!stuck.empty()) std::printf("note: %s\n", stuck.c_str());
  return kSuccess;
}

struct EffectsOptions {
  bool json = false;
};

// The effect table (core/simulation/effects.h), for people and for scripts
// (scripts/discrepancy-suite reads the names from `effects --json`).
int run_effects(const EffectsOptions& o) {
  if (o.json) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& e : simulation::effect_table()) {
      a.push_back({{"name", e.name},
                   {"unit", e.unit},
                   {"what", e.what},
                   {"lower", e.lower},
                   {"upper", e.upper},
                   {"physical", e.physical},
                   {"pooled", e.pool_high > 0}});
    }
    std::printf("%s\n", a.dump(1).c_str());
    return kSuccess;
  }
  std::printf("%-20s %-6s %-9s %-22s %s\n", "effect", "unit", "kind", "range", "what");
  for (const auto& e : simulation::effect_table()) {
    char range[48];
    std::snprintf(range, sizeof range, "%g..%g", e.lower, e.upper);
    std::printf("%-20s %-6s %-9s %-22s %s%s\n", e.name, e.unit, e.physical ? "physical" : "sensor", range, e.what,
                e.pool_high > 0 ? "" : " (not drawn by --effect random)");
  }
  return kSuccess;
}

Commands make_simulate_commands() {
  Commands commands;
  commands.push_back(make_command<EffectsOptions>(
      "effects", "The effects `simulate --effect` can hide in a run: name, unit, range, physical or sensor",
      [](CLI::App& cmd, EffectsOptions& o) { cmd.add_flag("--json", o.json, "Print JSON"); }, run_effects));
  commands.push_back(make_command<SimulateOptions>(
      "simulate",
      "Planar rocker-bogie dynamics with terramechanics (seed 003 chapter 4): a scenario to a log with truth",
      [](CLI::App& cmd, SimulateOptions& o) {
        cmd.add_option("SCENARIO", o.scenario, "Scenario NAME (resources/scenarios) or FILE.json")->required();
        cmd.add_option("--seed", o.seed, "Sensor-noise seed")->capture_default_str();
        cmd.add_option(
            "--effect", o.effects,
            "Effect NAME=VALUE: " + simulation::effect_names() +
                "; or random (none, one or two hidden effects drawn from --seed, recorded only in truth/ metadata)");
        cmd.add_option("--traction", o.traction, "polynomial | wong-reece (default: the scenario's)");
        cmd.add_option("--duration", o.duration, "s (default: the scenario's)");
        cmd.add_option("--output,-o", o.output, "OUT.h5")->required();
      },
      run_simulate_rocker_bogie));
  return commands;
}

}  // namespace roverlab::app

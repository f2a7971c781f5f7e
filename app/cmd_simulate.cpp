// `roverlab simulate rocker-bogie`: the planar rocker-bogie dynamics of seed
// 003 chapter 4 over a wheel-centre path, written as a log with truth streams.
#include <chrono>
#include <cmath>
#include <cstdio>

#include <CLI/CLI.hpp>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
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
  const io::ScenarioFile sc = io::find_scenario(o.scenario, resource_subfolders("scenarios"));
  simulation::RockerBogieRun run;
  const std::string path = sc.path;
  if (path == "rolling") {
    run.path = simulation::rolling_path();
  } else if (path == "flat") {
    run.path = simulation::flat_path();
  } else if (path == "slope") {
    if (!(std::abs(sc.slope_deg) < 45)) throw InputError(sc.file, "slope_deg must be within +-45");
    run.path = simulation::slope_path(sc.slope_deg);
  } else if (path == "bump") {
    if (!(sc.bump_length > 0.05) || !(std::abs(sc.bump_height) < 0.5))
      throw InputError(sc.file, "bump_length_m > 0.05 and |bump_height_m| < 0.5 needed");
    run.path = simulation::bump_path(sc.bump_height, sc.bump_x, sc.bump_length);
  } else {
    throw InputError(sc.file, "path '" + path + "': expected rolling, flat, slope or bump");
  }
  const std::string traction = o.traction.value_or(sc.traction);
  if (traction == "polynomial") {
    run.traction = simulation::TractionSource::polynomial;
  } else if (traction == "wong-reece") {
    run.traction = simulation::TractionSource::wong_reece;
  } else {
    throw UsageError("traction " + traction + ": expected polynomial or wong-reece");
  }
  const double duration = o.duration.value_or(sc.duration);
  if (!(duration > 0 && duration <= 100000)) throw UsageError("--duration must be in (0, 100000] s");
  run.duration = duration;
  run.start_x = sc.start_x;
  run.seed = o.seed;
  about_file(sc.file, [&] {
    for (const auto& [k, v] : sc.effects) simulation::set_effect(run.effects, k, v);
  });
  apply_effect_options(
      o.effects, [&](const std::string& name, double value) { simulation::set_effect(run.effects, name, value); });
  simulation::RockerBogieParameters params;
  params.desired_speed = sc.desired_speed;
  run.soil = io::find_soil(sc.soil, resource_subfolders("soils"));
  const io::RoverDescription d = io::find_rover(sc.rover, resource_subfolders("rovers"));
  if (!d.planar) throw InputError(d.file, "rover '" + d.name + "' is not a planar rocker-bogie description");
  simulation::PlanarRockerBogieGeometry g;
  g.wheel_radius = d.planar->wheel_radius;
  g.rocker_to_wheel1 = {d.planar->rocker_to_wheel1[0], d.planar->rocker_to_wheel1[1]};
  g.rocker_to_bogie = {d.planar->rocker_to_bogie[0], d.planar->rocker_to_bogie[1]};
  g.bogie_to_wheel2 = {d.planar->bogie_to_wheel2[0], d.planar->bogie_to_wheel2[1]};
  g.bogie_to_wheel3 = {d.planar->bogie_to_wheel3[0], d.planar->bogie_to_wheel3[1]};
  const auto start = std::chrono::steady_clock::now();
  simulation::RockerBogieResult r;
  {
    const ProgressLine progress("simulating", ProgressLine::Style::bar);
    run.progress = progress.callback();
    r = about_file(sc.file, [&] { return simulation::simulate_rocker_bogie(g, params, run); });
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::write_hdf5_log(r.log, o.output);
  const auto& pose = r.log.stream("truth/pose");
  std::printf(
      "wrote %s: scenario %s, %.0f s on the %s path, soil %s, %s traction; %.2f m driven; largest constraint error "
      "%.2g m; %.2f s\n",
      o.output.c_str(), sc.name.c_str(), duration, run.path.name.c_str(), run.soil.name.c_str(), traction.c_str(),
      pose.channel("x").values.back() - pose.channel("x").values.front(), r.max_constraint_error, wall);
  if (r.unsupported > 0)
    std::printf("note: %zu traction evaluations beyond what the soil carries (set to 0)\n", r.unsupported);
  return kSuccess;
}

Commands make_simulate_commands() {
  Commands commands;
  commands.push_back(make_command<SimulateOptions>(
      "simulate",
      "Planar rocker-bogie dynamics with terramechanics (seed 003 chapter 4): a scenario to a log with truth",
      [](CLI::App& cmd, SimulateOptions& o) {
        cmd.add_option("SCENARIO", o.scenario, "Scenario NAME (resources/scenarios) or FILE.json")->required();
        cmd.add_option("--seed", o.seed, "Sensor-noise seed")->capture_default_str();
        cmd.add_option("--effect", o.effects,
                       "Effect NAME=VALUE: soil-strength, slip-sinkage, grousers, wheel-radius-scale, effect-start-x, "
                       "gyro-bias, accel-bias, force-offset, force-scale, encoder-dropout, imu-time-offset");
        cmd.add_option("--traction", o.traction, "polynomial | wong-reece (default: the scenario's)");
        cmd.add_option("--duration", o.duration, "s (default: the scenario's)");
        cmd.add_option("--output,-o", o.output, "OUT.h5")->required();
      },
      run_simulate_rocker_bogie));
  return commands;
}

}  // namespace roverlab::app

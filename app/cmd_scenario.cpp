// `roverlab scenario ...`: simulated logs with truth streams — the skid-steer
// drive the INS slip detector is tested on (seed 002) and the flying-rover
// runs of the contact-angle estimator (seed 000 sections 6.3-6.4).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <optional>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/simulation/flying_rover.h"
#include "core/simulation/skid_steer_scenario.h"
#include "importers/hdf5_log.h"
#include "importers/rover_file.h"

namespace roverlab::app {

namespace {

struct SkidSteerScenarioOptions {
  unsigned seed = 1;
  std::string drive = "default";     // or "loops"
  std::vector<std::string> effects;  // NAME=VALUE
  std::string output;
};

int run_scenario_skid_steer(const SkidSteerScenarioOptions& o) {
  require_log_output(o.output, "--output");
  simulation::SkidSteerScenario scenario =
      o.drive == "loops" ? simulation::loop_slip_scenario(o.seed) : simulation::default_slip_scenario(o.seed);
  apply_effect_options(o.effects,
                       [&](const std::string& name, double value) { simulation::set_effect(scenario, name, value); });
  const log::Log lg = simulation::simulate_skid_steer(scenario);
  io::write_hdf5_log(lg, o.output);
  std::printf("wrote %s: %zu streams, %.1f s, seed %u\n", o.output.c_str(), lg.streams().size(),
              lg.stream("imu").duration(), o.seed);
  return kSuccess;
}

struct FlyingRoverOptions {
  std::string scenario;
  std::string rover = kFlyingRoverDefaultRover;
  unsigned seed = 1;
  double rate = 1000.0;
  double slip_angle_deg = 0.0;
  double slip_angle_from = 0.0;       // s
  std::optional<double> turn_radius;  // m; none: straight
  std::string output;
};

int run_scenario_flying_rover(const FlyingRoverOptions& o) {
  require_log_output(o.output, "--output");
  const io::RoverDescription d = io::find_rover(o.rover, resource_subfolders("rovers"));
  if (!d.dh) throw InputError(d.file, "rover '" + d.name + "' is not described by a DH table (kind " + d.kind + ")");
  const kinematics::RoverModel& rover = *d.dh;
  simulation::FlyingRoverScenario s;
  try {
    s = simulation::flying_rover_scenario(o.scenario, rover);
  } catch (const DataError& e) {
    throw UsageError(e.what());
  }
  s.seed = o.seed;
  if (!(o.rate >= 10.0 && o.rate <= 10000.0)) throw UsageError("--rate must be 10..10000 Hz");
  s.rate = o.rate;
  s.slip_angle = o.slip_angle_deg * M_PI / 180.0;
  s.slip_angle_from = o.slip_angle_from;
  if (o.turn_radius) s.turn_radius = *o.turn_radius;
  try {
    simulation::check_steering_manoeuvre(s);
  } catch (const DataError& e) {
    const bool radius = o.turn_radius && !(std::abs(*o.turn_radius) >= 1.0);
    const bool from = !(o.slip_angle_from >= 0 && o.slip_angle_from < s.duration);
    throw UsageError(std::string(radius ? "--turn-radius: "
                                 : from ? "--slip-angle-from: "
                                        : "--slip-angle: ") +
                     e.what());
  }
  const log::Log lg = simulation::simulate_flying_rover(rover, s);
  io::write_hdf5_log(lg, o.output);
  std::printf("wrote %s: scenario %s, rover %s, %.0f s at %.0f Hz, seed %u", o.output.c_str(), o.scenario.c_str(),
              rover.name.c_str(), s.duration, s.rate, s.seed);
  if (std::isfinite(s.turn_radius)) {
    // 1e300 m prints as such, not as 301 digits.
    std::printf(std::abs(s.turn_radius) < 1e6 ? ", turning about %.2f m to the %s" : ", turning about %.6g m to the %s",
                std::abs(s.turn_radius), s.turn_radius > 0 ? "left" : "right");
  }
  if (s.slip_angle != 0.0) std::printf(", wheels sliding at %.2f deg", o.slip_angle_deg);
  if (s.slip_angle != 0.0 && s.slip_angle_from > 0) std::printf(" from %.1f s", s.slip_angle_from);
  std::printf("\n");
  return kSuccess;
}

// The help line of each of core's flying-rover scenarios; the scenarios
// themselves (and so the commands) are simulation::flying_rover_scenarios(),
// the list campaign files read too.
std::string flying_scenario_help(const std::string& name) {
  if (name == "fl-bogie-rotation")
    return "Flying ExoMars BB2, front-left bogie turning 0.06 rad/s for 10 s, 3 cm/s forward (seed 000 section 6.3)";
  if (name == "rear-bogie-rotation")
    return "Flying ExoMars BB2, rear bogie turning 0.06 rad/s for 10 s, 3 cm/s forward (seed 000 section 6.4)";
  if (name == "bump-crossing")
    return "Flying ExoMars BB2: bogie motion of the left wheels crossing an 8 cm bump, all wheels steering (RoverLab)";
  if (name == "flat-turn")
    return "Flying ExoMars BB2 on flat ground turning about a centre 1 m to its left at 3 cm/s, wheels steered along "
           "their travel; --slip-angle makes them slide (RoverLab, issue 33)";
  return "Flying-rover scenario " + name + " (core/simulation/flying_rover.h)";
}

}  // namespace

Commands make_scenario_commands() {
  Commands commands;
  commands.push_back(make_command<SkidSteerScenarioOptions>(
      "scenario skid-steer-slip",
      "Four-wheel skid-steer drive with slip episodes of every class, IMU, wheels, GPS (seed 002)",
      [](CLI::App& cmd, SkidSteerScenarioOptions& o) {
        cmd.add_option("--seed", o.seed, "Noise seed")->capture_default_str();
        cmd.add_option("--drive", o.drive,
                       "default: straight runs and gentle turns, 1 cm GPS; loops: two laps of a square with turns in "
                       "place, starting south-east, 3 m GPS noise")
            ->capture_default_str()
            ->check(CLI::IsMember({"default", "loops"}));
        cmd.add_option("--effect", o.effects,
                       "Hidden effect NAME=VALUE: left-radius-scale, right-radius-scale, radius-scale, "
                       "turning-track-factor, wheel-time-offset (s), slip (0: firm ground)");
        cmd.add_option("--output,-o", o.output, "OUT.h5")->required();
      },
      run_scenario_skid_steer));
  for (const auto& name : simulation::flying_rover_scenarios()) {
    FlyingRoverOptions defaults;
    defaults.scenario = name;
    commands.push_back(make_command<FlyingRoverOptions>(
        "scenario " + name, flying_scenario_help(name),
        [](CLI::App& cmd, FlyingRoverOptions& o) {
          cmd.add_option("--seed", o.seed, "Noise seed")->capture_default_str();
          cmd.add_option("--rate", o.rate, "Sample rate, Hz")->capture_default_str();
          cmd.add_option("--rover", o.rover, "Rover NAME or FILE")->capture_default_str();
          cmd.add_option("--turn-radius", o.turn_radius,
                         "Steering manoeuvre: the body turns about a centre M metres to its left (negative: right, "
                         "|M| >= 1), every wheel steered along its travel (Ackermann); default the scenario's: "
                         "straight, flat-turn 1 m");
          CLI::Option* slip_angle =
              cmd.add_option(
                     "--slip-angle", o.slip_angle_deg,
                     "Hidden lateral effect: every wheel slides at DEG to its heading (seed 000's side-slip angle, "
                     "positive: velocity left of the wheel plane; within +-45); straight, a crab across a side "
                     "slope")
                  ->capture_default_str();
          cmd.add_option("--slip-angle-from", o.slip_angle_from,
                         "The slip angle ramps in over 1 s from S seconds (0: there from the start)")
              ->capture_default_str()
              ->needs(slip_angle);  // without a slip angle it has no effect
          cmd.add_option("--output,-o", o.output, "OUT.h5")->required();
        },
        run_scenario_flying_rover, defaults));
  }
  return commands;
}

}  // namespace roverlab::app

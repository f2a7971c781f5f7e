#include "app/rover_scenario.h"

#include <cmath>
#include <utility>

#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "importers/rover_file.h"
#include "importers/scenario_file.h"
#include "importers/soil_file.h"

namespace roverlab::app {

namespace {

// Runs `find`; a resource that cannot be found becomes the scenario's error, its field named.
template <class Find>
auto in_scenario(const std::string& scenario_file, const char* field, Find&& find) -> decltype(find()) {
  try {
    return std::forward<Find>(find)();
  } catch (const InputError& e) {
    if (e.file() == scenario_file) throw;
    throw InputError(scenario_file, std::string("field '") + field + "': " + e.what());
  }
}

}  // namespace

analysis::RoverScenarioModel load_rover_scenario(const std::string& name_or_file,
                                                 const std::optional<std::string>& traction_option) {
  return load_rover_scenario(io::find_scenario(name_or_file, resource_subfolders("scenarios")), traction_option);
}

analysis::RoverScenarioModel load_logs_rover_scenario(const std::map<std::string, std::string>& metadata,
                                                      const std::string& file) {
  const auto recorded = metadata.find("scenario_json");
  if (recorded != metadata.end()) {
    return load_rover_scenario(io::parse_scenario(file + " (metadata scenario_json)", recorded->second));
  }
  const auto named = metadata.find("scenario");
  if (named == metadata.end() || named->second.empty()) {
    throw UsageError(file + ": the log names no scenario; give --scenario");
  }
  return load_rover_scenario(io::find_scenario_named(named->second, resource_subfolders("scenarios"), file));
}

nlohmann::json rover_scenario_content(const std::optional<std::string>& given,
                                      const std::map<std::string, std::string>& metadata, const std::string& file) {
  io::ScenarioFile sc;
  const auto recorded = metadata.find("scenario_json");
  const auto named = metadata.find("scenario");
  if (given) {
    sc = io::find_scenario(*given, resource_subfolders("scenarios"));
  } else if (recorded != metadata.end()) {
    sc = io::parse_scenario(file + " (metadata scenario_json)", recorded->second);
  } else if (named != metadata.end() && !named->second.empty()) {
    sc = io::find_scenario_named(named->second, resource_subfolders("scenarios"), file);
  } else {
    throw UsageError(file + ": the log names no scenario; give --scenario");
  }
  nlohmann::json content = nlohmann::json::parse(sc.document);
  content.erase("name");  // the words that name it, not what it is
  content.erase("description");
  return content;
}

analysis::RoverScenarioModel load_rover_scenario(const io::ScenarioFile& sc,
                                                 const std::optional<std::string>& traction_option) {
  analysis::RoverScenarioModel model;
  simulation::RockerBogieRun& run = model.run;
  const std::string path = sc.path;
  if (path == "rolling") {
    run.path = simulation::rolling_path(sc.rolling_amplitude);
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
  const std::string traction = traction_option.value_or(sc.traction);
  if (traction == "polynomial") {
    run.traction = simulation::TractionSource::polynomial;
  } else if (traction == "wong-reece") {
    run.traction = simulation::TractionSource::wong_reece;
  } else {
    throw UsageError("--traction " + traction + ": expected polynomial or wong-reece");
  }
  run.duration = sc.duration;
  run.start_x = sc.start_x;
  about_file(sc.file, [&] {
    for (const auto& [k, v] : sc.effects) simulation::set_effect(run.effects, k, v);
  });
  model.parameters.desired_speed = sc.desired_speed;
  // The soil and rover a scenario names are found, or the scenario is named with the problem.
  run.soil = in_scenario(sc.file, "soil", [&] { return io::find_soil(sc.soil, resource_subfolders("soils")); });
  const io::RoverDescription d =
      in_scenario(sc.file, "rover", [&] { return io::find_rover(sc.rover, resource_subfolders("rovers")); });
  if (!d.planar) throw InputError(d.file, "rover '" + d.name + "' is not a planar rocker-bogie description");
  simulation::PlanarRockerBogieGeometry& g = model.geometry;
  g.wheel_radius = d.planar->wheel_radius;
  g.rocker_to_wheel1 = {d.planar->rocker_to_wheel1[0], d.planar->rocker_to_wheel1[1]};
  g.rocker_to_bogie = {d.planar->rocker_to_bogie[0], d.planar->rocker_to_bogie[1]};
  g.bogie_to_wheel2 = {d.planar->bogie_to_wheel2[0], d.planar->bogie_to_wheel2[1]};
  g.bogie_to_wheel3 = {d.planar->bogie_to_wheel3[0], d.planar->bogie_to_wheel3[1]};
  model.name = sc.name;
  model.rover = d.name;
  model.file = sc.file;
  model.traction = traction;
  return model;
}

}  // namespace roverlab::app

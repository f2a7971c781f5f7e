#include "importers/scenario_file.h"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "importers/named_file.h"

namespace roverlab::io {

using nlohmann::json;

ScenarioFile load_scenario(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open scenario");
  json j;
  try {
    j = json::parse(in);
  } catch (const json::parse_error& e) {
    throw InputError(path, std::string("scenario is not valid JSON: ") + e.what());
  }
  if (!j.is_object() || j.value("format", std::string()) != "roverlab-scenario") {
    throw InputError(path, "not a RoverLab scenario ('format' must be \"roverlab-scenario\")");
  }
  ScenarioFile s;
  s.file = path;
  try {
    s.name = j.value("name", std::string());
    s.description = j.value("description", std::string());
    s.kind = j.at("kind").get<std::string>();
    s.rover = j.at("rover").get<std::string>();
    s.path = j.at("path").get<std::string>();
    s.soil = j.at("soil").get<std::string>();
    s.traction = j.value("traction", std::string("polynomial"));
    s.duration = j.at("duration_s").get<double>();
    s.start_x = j.value("start_x_m", 0.0);
    s.desired_speed = j.value("desired_speed_mps", 0.02);
    s.slope_deg = j.value("slope_deg", 0.0);
    s.bump_height = j.value("bump_height_m", 0.05);
    s.bump_x = j.value("bump_x_m", 1.0);
    s.bump_length = j.value("bump_length_m", 0.3);
    if (j.contains("effects")) {
      for (const auto& [k, v] : j.at("effects").items()) s.effects[k] = v.get<double>();
    }
  } catch (const json::exception& e) {
    throw InputError(path, std::string("scenario: ") + e.what());
  }
  if (s.kind != "rocker-bogie") throw InputError(path, "scenario kind '" + s.kind + "' is not rocker-bogie");
  if (!(s.duration > 0) || !std::isfinite(s.start_x) || !(s.desired_speed > 0)) {
    throw InputError(path, "duration_s and desired_speed_mps must be positive");
  }
  return s;
}

ScenarioFile find_scenario(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders) {
  return load_scenario(find_named_file(name_or_file, folders, "scenario"));
}

}  // namespace roverlab::io

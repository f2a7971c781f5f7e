#include "importers/scenario_file.h"

#include <cmath>

#include "importers/json_resource.h"
#include "importers/named_file.h"

namespace roverlab::io {

ScenarioFile load_scenario(const std::string& path) {
  const JsonResource file = read_json_resource(path, "scenario");
  const JsonNode j = file.root();
  require_format(j, "roverlab-scenario", "scenario");
  ScenarioFile s;
  s.file = path;
  s.name = optional_string(j, "name", "");
  s.description = optional_string(j, "description", "");
  s.kind = required_string(j, "kind");
  s.rover = required_string(j, "rover");
  s.path = required_string(j, "path");
  s.soil = required_string(j, "soil");
  s.traction = optional_string(j, "traction", "polynomial");
  s.duration = required_number(j, "duration_s");
  s.start_x = optional_number(j, "start_x_m", 0.0);
  s.desired_speed = optional_number(j, "desired_speed_mps", 0.02);
  s.slope_deg = optional_number(j, "slope_deg", 0.0);
  s.bump_height = optional_number(j, "bump_height_m", 0.05);
  s.bump_x = optional_number(j, "bump_x_m", 1.0);
  s.bump_length = optional_number(j, "bump_length_m", 0.3);
  if (j.has("effects")) {
    const JsonNode effects = required_object(j, "effects");
    for (const auto& item : effects.value().items()) s.effects[item.key()] = as_number(effects.child(item.key()));
  }
  if (s.kind != "rocker-bogie") j.fail("kind", "scenario kind '" + s.kind + "' is not rocker-bogie");
  if (!(s.duration > 0)) j.fail("duration_s", "must be positive");
  if (!(s.duration <= 100000)) j.fail("duration_s", "must be at most 100000 (s)");
  if (!(s.desired_speed > 0)) j.fail("desired_speed_mps", "must be positive");
  // A planetary rover drives at centimetres per second; 2 m/s is far beyond any.
  if (!(s.desired_speed <= 2)) j.fail("desired_speed_mps", "must be at most 2 (m/s)");
  // Far from the origin the path's doubles lose the millimetres the contact needs.
  if (!(std::abs(s.start_x) <= 1000)) j.fail("start_x_m", "must be within +-1000 (m)");
  return s;
}

ScenarioFile find_scenario(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders) {
  return load_scenario(find_named_file(name_or_file, folders, "scenario"));
}

}  // namespace roverlab::io

#pragma once
// Simulation scenarios as data (resources/scenarios/*.json, format
// "roverlab-scenario"): which rover, path, soil and traction model, for how
// long and how fast, and which effects are on.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace roverlab::io {

struct ScenarioFile {
  std::string file, name, description, kind, rover, path, soil, traction;
  double duration = 0, start_x = 0, desired_speed = 0.02;
  double slope_deg = 0, bump_height = 0.05, bump_x = 1.0, bump_length = 0.3;  // path "slope" / "bump"
  double rolling_amplitude = 0.12;        // path "rolling": Eq. 4.51's hills, seed 003
  std::map<std::string, double> effects;  // NAME -> value
  std::string document;                   // the scenario as compact JSON, recorded in the logs simulated from it
};

// Throws InputError naming the file and field: unknown fields (a misspelt
// key would be ignored), a name that is not plain, values out of range.
ScenarioFile load_scenario(const std::string& path);
ScenarioFile find_scenario(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders);
// A scenario recorded as JSON text (a log's metadata); `source` names it in errors.
ScenarioFile parse_scenario(const std::string& source, const std::string& text);
// A scenario named by data (a log's metadata): a plain name from `folders`,
// never a path; `source` names where the name came from.
ScenarioFile find_scenario_named(const std::string& name, const std::vector<std::filesystem::path>& folders,
                                 const std::string& source);
// Letters, digits, '_', '-' and '.', not starting with '.', at most 128 characters.
bool is_plain_name(const std::string& name);

}  // namespace roverlab::io

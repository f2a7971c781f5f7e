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
  std::map<std::string, double> effects;                                      // NAME -> value
};

// Throws InputError naming the file.
ScenarioFile load_scenario(const std::string& path);
ScenarioFile find_scenario(const std::string& name_or_file, const std::vector<std::filesystem::path>& folders);

}  // namespace roverlab::io

#pragma once
// A rocker-bogie scenario file (resources/scenarios) as the model of a run:
// rover geometry, Table 4.1 parameters, path, soil, traction and the
// scenario's own effects. Shared by `simulate` and `discrepancy rover`.

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "core/discrepancy/rover/study.h"
#include "importers/scenario_file.h"

namespace roverlab::app {

// Throws InputError naming the scenario, rover or soil file; UsageError for a bad traction name.
analysis::RoverScenarioModel load_rover_scenario(const std::string& name_or_file,
                                                 const std::optional<std::string>& traction = std::nullopt);
analysis::RoverScenarioModel load_rover_scenario(const io::ScenarioFile& scenario,
                                                 const std::optional<std::string>& traction = std::nullopt);

// The model a log was simulated from: the scenario recorded in its metadata
// (`scenario_json`, written by `simulate`), else the bundled scenario its
// metadata names (a plain name, never a path). Throws InputError naming `file`.
analysis::RoverScenarioModel load_logs_rover_scenario(const std::map<std::string, std::string>& metadata,
                                                      const std::string& file);

// What a scenario is, rather than the words that named it: the scenario
// `given` (a NAME or FILE.json) or else the one the log's metadata records or
// names, as its JSON content without its name and description. Two runs modelled on
// the same scenario, named or inferred, give the same value. Throws
// InputError (or UsageError when the log names none) as the loaders above.
nlohmann::json rover_scenario_content(const std::optional<std::string>& given,
                                      const std::map<std::string, std::string>& metadata, const std::string& file);

}  // namespace roverlab::app

#pragma once
// A rocker-bogie scenario file (resources/scenarios) as the model of a run:
// rover geometry, Table 4.1 parameters, path, soil, traction and the
// scenario's own effects. Shared by `simulate` and `discrepancy rover`.

#include <map>
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

}  // namespace roverlab::app

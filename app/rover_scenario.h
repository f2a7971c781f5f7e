#pragma once
// A rocker-bogie scenario file (resources/scenarios) as the model of a run:
// rover geometry, Table 4.1 parameters, path, soil, traction and the
// scenario's own effects. Shared by `simulate` and `discrepancy rover`.

#include <optional>
#include <string>

#include "core/analysis/rover_discrepancy.h"

namespace roverlab::app {

// Throws InputError naming the scenario, rover or soil file; UsageError for a bad traction name.
analysis::RoverScenarioModel load_rover_scenario(const std::string& name_or_file,
                                                 const std::optional<std::string>& traction = std::nullopt);

}  // namespace roverlab::app

#pragma once
// A run comparison (core/comparison) as the JSON document `compare --json`
// prints and the report's metrics.json holds, written from the typed value.

#include <string>

#include <nlohmann/json.hpp>

#include "core/comparison/compare.h"

namespace roverlab::app {

nlohmann::json comparison_json(const std::string& file, const comparison::RunComparison& comparison);

// "time", "motion" or "distance".
const char* alignment_name(comparison::AlignBy by);

}  // namespace roverlab::app

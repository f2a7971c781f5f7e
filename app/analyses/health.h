#pragma once
// An estimator's health (core/filters/filter_health.h) in its result
// document, its printed text and its report section: the same `health`
// object for `estimate X --json`, the report's metrics.json and the GUI.

#include <cstdio>
#include <nlohmann/json.hpp>

#include "app/analysis.h"
#include "core/filters/filter_health.h"

namespace roverlab::app {

// {outliers_rejected, missing_samples, measurements_missing, gaps: [{start,
// end}], updates, updates_rejected, resets, stopped, invalid_fraction,
// divergence_time, nis_out_of_band_fraction, status: "ok" | "degraded" |
// "diverged", message}.
nlohmann::json health_json(const estimation::HealthReport& health);
// "health: <status>: <message>", one line.
void print_health(const nlohmann::json& document, std::FILE* out);
// One paragraph in the report.
void report_health(const nlohmann::json& document, ReportSection& section);

}  // namespace roverlab::app

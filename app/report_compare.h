#pragma once
// The report's comparison section (`report A --compare B [--compare C]`): each
// run against the report's log as `roverlab compare` gives it (docs/compare.md),
// the channels that differ drawn over each other with their difference below
// (and the +-2 sigma noise band), and the map with every run's track. The
// report then draws the views that compare runs (cmd_report.cpp). metrics.json gets the comparison
// documents and the values drawn.

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "app/analysis.h"
#include "core/log/log.h"

namespace roverlab::app {

struct ComparedLog {
  std::string file;
  log::Log log;
};

// Appends the section to `section.html` and its document to metrics["comparison"].
// Throws InputError naming a run's file when it cannot be aligned with the baseline.
void write_comparison_section(ReportSection& section, nlohmann::json& metrics, const std::string& base_file,
                              const log::Log& base, const std::vector<ComparedLog>& runs);

}  // namespace roverlab::app

#pragma once
// The report of a lab test file (issue 44). A single-wheel test's opens with the
// single-wheel study's verdict, then describes the test (wheel, soil, rows,
// loads, slip angles), compares the baseline's and the final model's
// held-out errors, and draws the per-slip-angle panels and the residuals
// against slip angle with the study's final model. metrics.json gets
// "single_wheel": the test, the verdict, the final model and its bands.
// A plate test's shows its force against depth with the fitted Bekker, Reece
// and RFT relations and their parameters; metrics.json gets "plate_test".

#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "app/analysis.h"
#include "app/views_input.h"

namespace roverlab::app {

// A single-wheel file: runs the study on `in`'s points from soil `soil` (dry_sand when not given)
// and appends the section to `section.html`, its images (w x h pixels, each
// view's report height) into `folder` (the report's). Throws InputError naming
// the file when the study cannot run on it. A plate test file: fits its
// relations and draws them. Nothing for another file.
void write_lab_test_section(ReportSection& section, const std::filesystem::path& folder, nlohmann::json& metrics,
                            const ViewInput& in, const std::optional<std::string>& soil, int w, int h);

}  // namespace roverlab::app

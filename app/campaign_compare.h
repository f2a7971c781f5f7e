#pragma once
// The campaign report's comparisons (issue 45): every run's log
// (RUN_DIR/log.h5) against the campaign's baseline run's, as `roverlab
// compare BASELINE RUN` gives it (clocks as recorded), each written as a page
// OUT/compare-NAME.html that the campaign table links to.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace roverlab::app {

struct CampaignRunLog {
  std::string name;
  std::filesystem::path log;  // RUN_DIR/log.h5
};

// Per run (in order): {"baseline": NAME} for the baseline itself; else
// {"baseline", "page" (relative to out), "channels" (shared, compared),
// "differing" ["stream/channel", ...], "false_alarm"}, or {"baseline",
// "note": why not} when a log (the run's or the baseline's) is missing or the
// two cannot be aligned. Writes the pages atomically. Throws InputError naming
// the baseline's log when it is there but cannot be read.
nlohmann::json compare_with_baseline(const std::vector<CampaignRunLog>& runs, std::size_t baseline,
                                     const std::filesystem::path& out);

// True for a file name compare_with_baseline writes ("compare-NAME.html").
bool is_comparison_page(const std::string& file_name);

}  // namespace roverlab::app

#pragma once
// What the views need from a file named on the command line (or opened in
// the GUI): the log, with the results (and estimate streams) of the analyses
// asked for that can run on it; or the traction points of a single-wheel CSV.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <functional>
#include <nlohmann/json.hpp>

#include "app/analysis.h"
#include "core/log/log.h"
#include "core/terramechanics/plate_test.h"
#include "core/terramechanics/wheel_test.h"

namespace roverlab::app {

// One analysis's result as the views hold it (app/analysis.h), with the
// analysis (and its settings) that made it: its document is read through it.
struct AnalysisRun {
  std::shared_ptr<const Analysis> analysis;
  std::string name, title;
  nlohmann::json document;
};

struct ViewInput {
  std::string file;
  log::Log log;
  std::vector<AnalysisRun> analyses;                         // results of the analyses run here, in registry order
  std::vector<terramechanics::WheelTestPoint> wheel_points;  // single-wheel CSV input
  std::vector<terramechanics::PlateRecord> plate_records;    // plate test CSV input (depth_m, force_N)
  std::vector<std::string> notes;                            // what was computed or is missing, one line each
  bool is_wheel_test() const { return !wheel_points.empty(); }
  bool is_plate_test() const { return !plate_records.empty(); }
  // The result document of analysis `name`, nullptr when it has not run.
  const nlohmann::json* result(const std::string& name) const;
  // Adds (or replaces) a result and the streams the log does not have yet.
  void add(std::shared_ptr<const Analysis> analysis, AnalysisResult result);
  // log_fingerprint(log), computed once: the analyses add estimate/ streams
  // only, which it leaves out.
  const std::string& fingerprint() const;

 private:
  mutable std::optional<std::string> fingerprint_;
};

struct ViewInputOptions {
  // Analyses (by name) to run when they can run on the log and have not yet
  // (Analysis::runs_on_open); a result stored in the log with the same
  // measurements and settings is reused instead.
  std::vector<std::string> analyses;
  // Called on the log before any analysis runs (a view's own checks, e.g.
  // the --time range): throws to refuse early.
  std::function<void(const log::Log&)> check_log;
};

// The names of the registered analyses for which `keep` holds (every one
// when it is empty: what the report runs), in registry order.
std::vector<std::string> all_analysis_names(const std::function<bool(const Analysis&)>& keep = {});

// Adds the result of `analysis` stored in the log when its measurements and
// settings match (app/analysis.h: stored_result); false when there is none.
// Nothing is done when `in` already holds a result of that analysis.
bool reuse_stored_result(ViewInput& in, std::shared_ptr<const Analysis> analysis);

// Loads FILE (log formats, or a single-wheel CSV with load_N and slip
// columns). Throws InputError naming the file.
ViewInput load_view_input(const std::string& file, const std::optional<std::string>& mapping,
                          const ViewInputOptions& options = {});

// The rover a log names (its rover_id); the ExoMars BB2 when it names none.
std::string rover_name_of(const log::Log& log);

}  // namespace roverlab::app

#include "app/views_input.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <utility>

#include "app/command_support.h"
#include "app/log_input.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "importers/csv_text.h"
#include "importers/plate_test_csv.h"
#include "importers/wheel_test_csv.h"

namespace roverlab::app {

namespace {

// The CSV's header line (its first content line); empty when `file` is not a regular .csv file.
std::string csv_header(const std::string& file) {
  std::error_code ec;
  // Not a regular file: load_log says why (a pipe would block here).
  if (std::filesystem::path(file).extension() != ".csv" || !std::filesystem::is_regular_file(file, ec)) return {};
  std::ifstream in = io::csv::open_text_file(file);
  std::string header;
  int line_number = 0;
  if (!io::csv::next_content_line(in, header, line_number, file)) return {};
  return header;
}

bool looks_like_wheel_test_csv(const std::string& header) {
  return header.find("load_N") != std::string::npos && header.find("slip") != std::string::npos;
}

// A plate test (docs/plate-tests.md): depth_m and force_N columns.
bool looks_like_plate_test_csv(const std::string& header) {
  return header.find("depth_m") != std::string::npos && header.find("force_N") != std::string::npos;
}

}  // namespace

const nlohmann::json* ViewInput::result(const std::string& name) const {
  for (const auto& a : analyses) {
    if (a.name == name) return &a.document;
  }
  return nullptr;
}

const std::string& ViewInput::fingerprint() const {
  if (!fingerprint_) fingerprint_ = log_fingerprint(log);
  return *fingerprint_;
}

void ViewInput::add(std::shared_ptr<const Analysis> analysis, AnalysisResult r) {
  // An analysis run again (another model chosen in the GUI) replaces its streams.
  for (const auto& s : r.estimates.streams()) log.replace_stream(s);
  std::string name = analysis->name(), title = analysis->identity().title;
  AnalysisRun run{std::move(analysis), std::move(name), std::move(title), std::move(r.document)};
  for (auto& a : analyses) {
    if (a.name == run.name) {
      a = std::move(run);
      return;
    }
  }
  // Keep registry order, so the report and the GUI list results alike.
  const std::vector<std::string> order = all_analysis_names();
  const auto rank = [&](const std::string& n) { return std::find(order.begin(), order.end(), n) - order.begin(); };
  auto at = std::find_if(analyses.begin(), analyses.end(),
                         [&](const AnalysisRun& a) { return rank(a.name) > rank(run.name); });
  analyses.insert(at, std::move(run));
}

std::vector<std::string> all_analysis_names(const std::function<bool(const Analysis&)>& keep) {
  std::vector<std::string> names;
  for (const auto& a : all_analyses()) {
    if (!keep || keep(*a)) names.push_back(a->name());
  }
  return names;
}

bool reuse_stored_result(ViewInput& in, std::shared_ptr<const Analysis> analysis) {
  if (in.result(analysis->name()) != nullptr) return false;
  std::optional<nlohmann::json> stored = stored_result(*analysis, in.log, [&] { return in.fingerprint(); });
  if (!stored) return false;
  const std::string command = analysis->identity().command;
  in.add(std::move(analysis), AnalysisResult{{}, std::move(*stored)});
  in.notes.push_back("reused the stored result of " + command + " (same measurements and settings)");
  return true;
}

ViewInput load_view_input(const std::string& file, const std::optional<std::string>& mapping,
                          const ViewInputOptions& o) {
  ViewInput in;
  in.file = file;
  const std::string header = csv_header(file);
  if (looks_like_plate_test_csv(header)) {
    in.plate_records.push_back(io::read_plate_test_csv(file));
    in.notes.push_back("plate test samples: " + std::to_string(in.plate_records.front().depth.size()));
    return in;
  }
  if (looks_like_wheel_test_csv(header)) {
    io::WheelTestFile read = io::read_wheel_test_file(file);
    in.wheel_points = std::move(read.points);
    in.notes.push_back("single-wheel test points: " + std::to_string(in.wheel_points.size()));
    for (const auto& warning : read.warnings) in.notes.push_back(warning);
    return in;
  }
  in.log = load_input(file, mapping).log;
  if (o.check_log) o.check_log(in.log);
  for (const auto& name : o.analyses) {
    const std::shared_ptr<Analysis> a = make_analysis(name);
    if (!a) throw std::logic_error("no analysis named " + name);
    if (reuse_stored_result(in, a)) continue;
    const std::string missing = a->missing(in.log);
    if (!missing.empty()) {
      in.notes.push_back("not run: " + a->identity().command + " (the log has " + missing + ")");
      continue;
    }
    if (!a->runs_on_open(in.log)) continue;
    try {
      in.add(a, run_analysis(*a, {in.log, file, {}}));
    } catch (const InputError& e) {
      in.notes.push_back("not run: " + a->identity().command + " (" + e.problem() + ")");
      continue;
    }
    in.notes.push_back("ran " + a->identity().command + " on the log: " + a->identity().title);
  }
  return in;
}

std::string rover_name_of(const log::Log& lg) {
  return lg.metadata.rover_id.empty() ? "exomars_bb2" : lg.metadata.rover_id;
}

}  // namespace roverlab::app

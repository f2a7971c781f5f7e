#pragma once
// The analysis seam: an estimator or a study run over a log, as the command
// line (`estimate X`, `discrepancy X`), the GUI, the report and campaigns see
// it. Each analysis is one file in app/analyses/ defining
// `make_<name>_analysis()`, listed by one line in app/analyses/analyses.def.
// Its result document (JSON) is what `--json` prints, what the report's
// metrics.json holds under analyses/<name>, and what the GUI's Analysis tab
// shows: one result-to-JSON function per analysis serves all three.

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/log/log.h"

namespace CLI {
class App;
}

namespace roverlab::app {

struct AnalysisInput {
  const log::Log& log;
  std::string file;                      // named in errors
  std::function<void(double)> progress;  // fraction done; may be empty; may throw to cancel
};

struct AnalysisResult {     // NOLINT(bugprone-exception-escape): std::map's move in LogMetadata, not thrown in practice
  log::Log estimates;       // streams to add to the log (estimate/<name>/...) and metadata.extra entries
  nlohmann::json document;  // the result
};

// A part of the HTML report: an HTML fragment and CSV files beside index.html.
class ReportSection {
 public:
  explicit ReportSection(std::filesystem::path folder) : folder_(std::move(folder)) {}
  std::ostringstream html;
  void write_csv(const std::string& name, const std::string& text) const;  // atomically, into the folder
  // The files written into the folder so far (write_csv's and those noted by wrote()).
  void wrote(const std::string& name) const { written_.push_back(name); }
  const std::vector<std::string>& written() const { return written_; }
  static std::string escape(const std::string& text);
  // printf-formatted number; an en dash for NaN, infinity and JSON null.
  static std::string number(double value, const char* format = "%.3g");
  static std::string number(const nlohmann::json& value, const char* format = "%.3g");

 private:
  std::filesystem::path folder_;
  mutable std::vector<std::string> written_;
};

// A column of the campaign table (`roverlab campaign report`): a number
// (or, for a verdict, a string) in the analysis's result document; an array
// (per wheel) is shown by its mean. Wall-clock figures are never key metrics:
// a campaign run twice gives the same table.
struct KeyMetric {
  std::string key;       // column name in the CSV and JSON
  std::string title;     // column heading in the HTML
  std::string pointer;   // JSON pointer inside the result document
  bool verdict = false;  // a string, not a number
};

class Analysis {
 public:
  virtual ~Analysis() = default;
  virtual std::string name() const = 0;      // key of its result: "ins-slip"
  virtual std::string command() const = 0;   // "estimate ins-slip"
  virtual std::string title() const = 0;     // heading in the report and the GUI
  virtual std::string help() const = 0;      // one line for --help
  virtual std::string log_help() const = 0;  // what the LOG argument must hold
  // Whether it adds streams to the log (and so takes -o OUT.h5).
  virtual bool adds_streams() const { return true; }
  // Empty when the analysis can run on `log`, else what the log lacks.
  virtual std::string missing(const log::Log& log) const = 0;
  // Whether the GUI and the report run it on this log by themselves.
  virtual bool runs_on_open(const log::Log& log) const { return missing(log).empty(); }
  // Options bound to members. Their defaults are the command line's; the GUI
  // and the report call use_view_defaults() first.
  virtual void declare(CLI::App& cmd) { (void)cmd; }
  virtual void use_view_defaults() {}
  // Throws UsageError for option values that make no sense, before any log is read.
  virtual void check_options() const {}
  // Throws DataError for what the log lacks, UsageError for bad options.
  virtual AnalysisResult run(const AnalysisInput& input) = 0;
  // The result as text for the command line.
  virtual void print(const nlohmann::json& document, std::FILE* out) const = 0;
  // The result in the HTML report.
  virtual void report(const nlohmann::json& document, ReportSection& section) const = 0;
  // Its columns in a campaign's table of runs.
  virtual std::vector<KeyMetric> key_metrics() const { return {}; }
  // Its answer in a sentence or two, for the top of the report: by default
  // its key metrics ("INS final error (m) 0.42; ..."); a study gives its verdict.
  virtual std::string summary(const nlohmann::json& document) const;
};

using Analyses = std::vector<std::unique_ptr<Analysis>>;

// What `analysis.print(document, ...)` writes, as a string (the GUI shows it).
std::string printed(const Analysis& analysis, const nlohmann::json& document);

// Every registered analysis, in analyses.def order.
Analyses all_analyses();
// One by name; nullptr when there is none of that name.
std::unique_ptr<Analysis> make_analysis(const std::string& name);

// null for NaN and infinities (JSON has neither).
inline nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace roverlab::app

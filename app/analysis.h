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
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/log/log.h"

namespace CLI {
class App;
}
namespace roverlab::views {
struct TractionSurfaceData;
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

struct ResultTable;

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
  // Appends `table` (the very one Presentation::tables() gives the GUI) as an HTML
  // table: its title as the caption, its headings, row names and cells as
  // they are; numbers right-aligned, words left; the row a result picks in
  // bold, a cell's shade as a tint; its legend in a line under it.
  void table(const ResultTable& table);

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
  // The cause a study names, which a campaign scores against the effects
  // injected into its simulated runs (Presentation::expected_cause).
  bool cause = false;
};

// The value of `metric` in a result document: the number, the mean of a
// per-wheel array (null when one of its entries is not a number), the string
// of a verdict; null when absent. The campaign table and the report's
// summary read key metrics through it.
nlohmann::json key_metric_value(const nlohmann::json& document, const KeyMetric& metric);

// A table of a result as the GUI's Analysis pane shows it (the slip-class
// confusion, a study's candidates). Built from the result document by the
// analysis that wrote it, so no other code reads the document's keys.
struct ResultTable {
  struct Cell {
    std::string text;
    double shade = 0.0;  // 0..1: how strongly the cell is tinted (a fraction)
    // Bold has one meaning in every table: the row the result picks (the
    // cause a study names), nothing else; the legend says so.
    bool bold = false;
  };
  std::string title;                    // "What the wheel odometry gets wrong: candidate causes"
  std::vector<std::string> columns;     // headings, with units
  std::vector<std::string> row_names;   // empty: rows have no heading
  std::vector<std::vector<Cell>> rows;  // rows[i].size() == columns.size()
  std::string legend;                   // one line under the table: what bold, the tint and the order mean
};

// A chart of log channels an analysis asks the report to draw with the
// channel plots (the rover study: where the simulation disagrees most),
// built by the analysis from its own result document.
struct ReportPlot {
  std::string file;          // "disagreement.png", in the report's folder
  std::string heading;       // the figure's caption
  std::string channel_spec;  // the channels drawn, as `render --channels` takes them
  int rows = 1;              // its height in chart heights
  std::string note;          // one plain-text line under it
};

// How an analysis's result is shown: as text, in the HTML report, in the
// GUI's tables and views, at the top of the report and in a campaign's table.
// Each member reads only the result document the analysis wrote (and, for
// report_plots, the log), never the analysis's options.
class Presentation {
 public:
  virtual ~Presentation() = default;
  // The result as text for the command line.
  virtual void print(const nlohmann::json& document, std::FILE* out) const = 0;
  // The result in the HTML report.
  virtual void report(const nlohmann::json& document, ReportSection& section) const = 0;
  // The tables of its result the GUI shows; none by default.
  virtual std::vector<ResultTable> tables(const nlohmann::json& document) const {
    (void)document;
    return {};
  }
  // The charts of the log it asks the report to draw; none by default.
  virtual std::vector<ReportPlot> report_plots(const nlohmann::json& document, const log::Log& log) const {
    (void)document, (void)log;
    return {};
  }
  // True when its results hold traction surfaces (the traction-surface view
  // draws them); traction_surface() then fills `out` from the document:
  // drawbar pull or resistive torque. False when this document holds none.
  virtual bool draws_traction_surfaces() const { return false; }
  virtual bool traction_surface(const nlohmann::json& document, bool drawbar_pull,
                                views::TractionSurfaceData& out) const {
    (void)document, (void)drawbar_pull, (void)out;
    return false;
  }
  // Its columns in a campaign's table of runs.
  virtual std::vector<KeyMetric> key_metrics() const { return {}; }
  // Its answer in a sentence or two, for the top of the report: by default
  // its key metrics ("INS final error (m) 0.42; ..."); a study gives its verdict.
  virtual std::string summary(const nlohmann::json& document) const;
  // The cause its `cause` key metric should name for a simulated run with
  // these injected effects ({"radius-scale": 1.03, ...}); empty: not scored.
  virtual std::string expected_cause(const nlohmann::json& effects) const {
    (void)effects;
    return {};
  }
};

// One option the GUI's Analysis menu offers as a choice (the contact-angle
// model): its flag, the values, the menu's title.
struct AnalysisChoice {
  std::string option, menu;         // "--model", "Contact-angle &model"
  std::vector<std::string> values;  // the first is the default
};

// Who an analysis is: fixed words, given when it is made.
struct AnalysisIdentity {
  std::string name;      // key of its result: "ins-slip"
  std::string command;   // "estimate ins-slip"
  std::string title;     // heading in the report and the GUI
  std::string help;      // one line for --help
  std::string log_help;  // what the LOG argument must hold
  // The names (prefixes) of the estimate streams it adds to the log: a view
  // that draws none of them does not run it (views::View::estimates_drawn());
  // none: it adds no streams (and takes no -o OUT.h5).
  std::vector<std::string> estimate_streams;
  std::optional<AnalysisChoice> choice;  // offered in the GUI's Analysis menu; none by default
};

// An estimator or a study over a log, in three parts: what it needs (the
// log's streams: missing(), runs_on_open()), what it computes (its options,
// configuration and run(), giving the result document) and how that document
// is shown (presentation()). Its identity is data.
class Analysis {
 public:
  Analysis(AnalysisIdentity identity, std::unique_ptr<const Presentation> presentation)
      : identity_(std::move(identity)), presentation_(std::move(presentation)) {}
  virtual ~Analysis() = default;

  const AnalysisIdentity& identity() const { return identity_; }
  const std::string& name() const { return identity_.name; }
  // Whether it adds streams to the log (and so takes -o OUT.h5).
  bool adds_streams() const { return !identity_.estimate_streams.empty(); }

  // What it needs. Empty when the analysis can run on `log`, else what the log lacks.
  virtual std::string missing(const log::Log& log) const = 0;
  // Whether the GUI and the report run it on this log by themselves.
  virtual bool runs_on_open(const log::Log& log) const { return missing(log).empty(); }

  // What it computes. Options bound to members. Their defaults are the best
  // the data support (docs/validation/) and the same on every entry point:
  // the command line, the GUI, `render`, the report and campaigns; opting
  // out is a flag.
  virtual void declare(CLI::App& cmd) { (void)cmd; }
  // The settings it runs with (its options' values), as run_analysis() puts
  // them in the result document under "configuration".
  virtual nlohmann::json configuration() const = 0;
  // The settings as they resolve on `log`: what its result depends on, with a
  // setting that names something (a scenario) replaced by what it names (the
  // scenario's content), so that a name given and the same one the log
  // records compare equal. A stored result is reused when these match.
  // Throws InputError when a name cannot be resolved.
  virtual nlohmann::json resolved_configuration(const log::Log& log) const {
    (void)log;
    return configuration();
  }
  // Throws UsageError for option values that make no sense, before any log is read.
  virtual void check_options() const {}
  // Throws DataError for what the log lacks, UsageError for bad options.
  virtual AnalysisResult run(const AnalysisInput& input) = 0;

  // How its result document is shown.
  const Presentation& presentation() const { return *presentation_; }

 private:
  AnalysisIdentity identity_;
  std::unique_ptr<const Presentation> presentation_;
};

using Analyses = std::vector<std::unique_ptr<Analysis>>;

// Runs `analysis` on `input.log` the one way every entry point does: the
// result document gains "configuration" (Analysis::configuration()) and
// "input" (the fingerprint of the log's measured streams, log_fingerprint(),
// the program that ran it, program_identity(), and the settings resolved on
// the log, Analysis::resolved_configuration()).
// A DataError becomes an InputError naming input.file.
AnalysisResult run_analysis(Analysis& analysis, const AnalysisInput& input);

// RoverLab's version and the GNU build id of the running program: a result
// stored by another build (another candidate pool, another fix) is not reused.
std::string program_identity();

// A hash of the log's rover id, the scenario it records (metadata "scenario",
// "scenario_json") and its streams outside estimate/ (names, channels, times,
// values): two logs with the same measurements share it.
std::string log_fingerprint(const log::Log& log);

// The result of `analysis` stored in `log` (estimate X -o OUT.h5) when it was
// made from these measurements with these settings, compared as resolved on
// the log (Analysis::resolved_configuration()), by this program
// (program_identity()), nests at most io::kMaxJsonNesting deep and is of the
// shape the analysis reads (its print, summary, tables and key metrics make
// no type error); nullopt otherwise (the analysis runs again; also when a
// setting cannot be resolved).
// `fingerprint` gives log_fingerprint(log) (asked only when a result is stored).
std::optional<nlohmann::json> stored_result(const Analysis& analysis, const log::Log& log,
                                            const std::function<std::string()>& fingerprint = {});
// Stores `document` in `estimates` (its metadata's results), to be written
// with the log.
void store_result(const Analysis& analysis, const nlohmann::json& document, log::Log& estimates);

// The fields of a result document that differ between two runs of the same
// configuration on the same log (wall-clock times, the output file, the program that ran it), removed.
nlohmann::json without_run_details(nlohmann::json document);

// What `analysis.presentation().print(document, ...)` writes, then the settings line, as a
// string (the GUI shows it).
std::string printed(const Analysis& analysis, const nlohmann::json& document);
// The document's "configuration" as one line: "settings: model auto, filter
// ekf, ..." (empty when it has none). The command line, the report and the
// GUI print it under the result.
std::string configuration_text(const nlohmann::json& document);

// Every registered analysis, in analyses.def order.
Analyses all_analyses();
// One by name; nullptr when there is none of that name.
std::unique_ptr<Analysis> make_analysis(const std::string& name);

// null for NaN and infinities (JSON has neither).
inline nlohmann::json finite_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace roverlab::app

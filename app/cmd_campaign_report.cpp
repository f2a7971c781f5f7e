// `roverlab campaign report RUN_DIR... -o OUT`: the campaign report. Reads
// each run's run.json (provenance, written by workflows/Snakefile) and
// report/metrics.json (`roverlab report`), and writes OUT/index.html (a table
// of every run with its key metrics and verdicts, links to the per-run
// reports, a histogram per key metric, the named-vs-injected confusion table
// of the simulated runs), OUT/campaign.csv and OUT/campaign.json.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "app/analysis.h"
#include "app/campaign_compare.h"
#include "app/command.h"
#include "app/commands.h"
#include "core/common/error.h"
#include "importers/atomic_file.h"
#include "importers/json_resource.h"

namespace roverlab::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct CampaignReportOptions {
  std::vector<std::string> runs;
  std::string output;
  std::optional<std::string> baseline;  // the run the others are compared with (default: the first)
};

// The table's columns: every registered analysis's key metrics
// (Presentation::key_metrics), in analyses.def order.
struct KeyColumn {
  std::string key, title, analysis, pointer;
  bool verdict = false;
};

const std::vector<KeyColumn>& key_columns() {
  static const std::vector<KeyColumn> columns = [] {
    std::vector<KeyColumn> out;
    for (const auto& analysis : all_analyses()) {
      for (const auto& m : analysis->presentation().key_metrics()) {
        out.push_back({m.key, m.title, analysis->name(), m.pointer, m.verdict});
      }
    }
    return out;
  }();
  return columns;
}

// The cause the odometry study should name for a run's injected effects:
// the candidate that stands for its one effect (slip=0, firm ground, aside),
// "none" on firm ground without an effect; empty when no single answer is
// right (several effects, or the default slip episodes alone, which look
// like a smaller wheel radius).
json read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open (is the run finished?)");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (io::json_nesting(text) > io::kMaxJsonNesting) {
    throw InputError(path.string(), "nests deeper than " + std::to_string(io::kMaxJsonNesting) + " levels");
  }
  try {
    return json::parse(text);
  } catch (const json::exception& e) {
    throw InputError(path.string(), std::string("not valid JSON: ") + e.what());
  }
}

json metric_value(const json& analyses, const KeyColumn& m) {
  const KeyMetric metric{m.key, m.title, m.pointer, m.verdict};
  return analyses.contains(m.analysis) ? key_metric_value(analyses.at(m.analysis), metric) : json(nullptr);
}

std::string effects_text(const json& effects) {
  std::string text;
  for (const auto& [name, value] : effects.items()) {
    char b[96];
    std::snprintf(b, sizeof b, "%s%s=%.10g", text.empty() ? "" : " ", name.c_str(), value.get<double>());
    text += b;
  }
  return text.empty() ? "none" : text;
}

std::string csv_cell(const json& v) {
  if (v.is_null()) return "";
  if (v.is_number()) return ReportSection::number(v.get<double>(), "%.10g");
  std::string s = v.is_string() ? v.get<std::string>() : v.dump();
  // A text cell a spreadsheet would run as a formula is kept as text.
  if (!s.empty() && std::string("=+-@\t\r").find(s.front()) != std::string::npos) s.insert(0, "'");
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (const char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// The field `key` of a run document, checked to be of the type the report
// reads it as (`fallback` when absent); a wrong type names the file and field.
json run_field(const json& doc, const fs::path& file, const char* key, const json& fallback,
               bool (*is_type)(const json&), const char* type) {
  if (!doc.contains(key) || (doc.at(key).is_null() && fallback.is_null())) return fallback;
  const json& v = doc.at(key);
  if (!is_type(v)) throw InputError(file.string(), std::string("field '") + key + "' must be " + type);
  return v;
}

bool is_text(const json& v) { return v.is_string(); }
bool is_object(const json& v) { return v.is_object(); }
// A seed as campaigns write it: a whole number from 0 to 2^53.
bool is_seed(const json& v) {
  if (v.is_number_unsigned()) return v.get<std::uint64_t>() <= (std::uint64_t{1} << 53U);
  if (v.is_number_integer()) return v.get<std::int64_t>() >= 0;
  return false;
}
bool is_effects(const json& v) {
  if (!v.is_object()) return false;
  return std::all_of(v.begin(), v.end(), [](const json& e) { return e.is_number() && std::isfinite(e.get<double>()); });
}

// One run: its provenance and key metrics.
json read_run(const fs::path& dir, const fs::path& out) {
  const fs::path run_file = dir / "run.json", metrics_file = dir / "report" / "metrics.json";
  const json run = read_json(run_file);
  if (!run.is_object() || run.value("format", json()) != "roverlab-campaign-run") {
    throw InputError(run_file.string(), "not a RoverLab campaign run ('format' must be roverlab-campaign-run)");
  }
  const json metrics = read_json(metrics_file);
  if (!metrics.is_object()) throw InputError(metrics_file.string(), "not a RoverLab report's metrics (not an object)");
  const json analyses = run_field(metrics, metrics_file, "analyses", json::object(), is_object, "an object");
  for (const auto& [name, doc] : analyses.items()) {
    if (!doc.is_object()) throw InputError(metrics_file.string(), "analysis '" + name + "' must be an object");
  }
  json row = {
      {"name", run_field(run, run_file, "name", dir.filename().string(), is_text, "a string")},
      {"kind", run_field(run, run_file, "kind", "", is_text, "a string")},
      {"scenario", run_field(run, run_file, "scenario", nullptr, is_text, "a string")},
      {"seed", run_field(run, run_file, "seed", nullptr, is_seed, "a whole number from 0 to 2^53")},
      {"effects", run_field(run, run_file, "effects", json::object(), is_effects, "an object of finite numbers")},
      {"roverlab_version", run_field(run, run_file, "roverlab_version", "", is_text, "a string")},
      {"analyses", json::array()},
      {"report", fs::proximate(dir / "report" / "index.html", out).generic_string()},
      {"metrics", json::object()}};
  for (const auto& [name, doc] : analyses.items()) row["analyses"].push_back(name);
  for (const auto& m : key_columns()) row["metrics"][m.key] = metric_value(analyses, m);
  return row;
}

// A histogram of one metric over the runs, as an SVG file.
// The values are finite; their range may not be (1.7e308 - -1.7e308), so
// the bins are found from half the values.
std::string histogram_svg(const std::string& title, const std::vector<double>& values) {
  const double lo = *std::min_element(values.begin(), values.end());
  const double hi = *std::max_element(values.begin(), values.end());
  constexpr int kBins = 12;
  const double half_range = 0.5 * hi - 0.5 * lo;
  std::vector<int> counts(kBins, 0);
  for (const double v : values) {
    const double at = half_range > 0.0 ? (0.5 * v - 0.5 * lo) / half_range : 0.5;  // 0..1
    const int b = std::clamp(static_cast<int>(std::clamp(at, 0.0, 1.0) * kBins), 0, kBins - 1);
    ++counts[static_cast<std::size_t>(b)];
  }
  const int most = *std::max_element(counts.begin(), counts.end());
  constexpr double kW = 360, kH = 200, kLeft = 30, kBottom = 170, kPlotH = 140, kBarW = (kW - kLeft - 10) / kBins;
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kW << "\" height=\"" << kH
    << "\" font-family=\"sans-serif\" font-size=\"11\">\n<title>" << ReportSection::escape(title) << "</title>\n"
    << "<text x=\"" << kLeft << "\" y=\"14\">" << ReportSection::escape(title) << " (" << values.size()
    << " runs)</text>\n";
  for (int b = 0; b < kBins; ++b) {
    const double h = most > 0 ? kPlotH * counts[static_cast<std::size_t>(b)] / most : 0;
    s << "<rect x=\"" << kLeft + b * kBarW << "\" y=\"" << kBottom - h << "\" width=\"" << kBarW - 1 << "\" height=\""
      << h << "\" fill=\"#58c\"><title>" << counts[static_cast<std::size_t>(b)] << "</title></rect>\n";
  }
  s << "<line x1=\"" << kLeft << "\" y1=\"" << kBottom << "\" x2=\"" << kW - 10 << "\" y2=\"" << kBottom
    << "\" stroke=\"#333\"/>\n<text x=\"" << kLeft << "\" y=\"" << kBottom + 15 << "\">"
    << ReportSection::number(lo, "%.4g") << "</text>\n<text x=\"" << kW - 10 << "\" y=\"" << kBottom + 15
    << "\" text-anchor=\"end\">" << ReportSection::number(hi, "%.4g") << "</text>\n<text x=\"4\" y=\""
    << kBottom - kPlotH + 4 << "\">" << most << "</text>\n</svg>\n";
  return s.str();
}

// The first analysis (registry order) with a cause key metric, and that metric.
std::pair<std::unique_ptr<Analysis>, KeyMetric> cause_metric() {
  for (auto& a : all_analyses()) {
    for (const KeyMetric& m : a->presentation().key_metrics()) {
      if (m.cause) return {std::move(a), m};
    }
  }
  return {nullptr, KeyMetric{}};
}

// Named cause (a study's cause key metric) against the injected effects,
// over the simulated runs the study ran on.
json confusion_table(const json& runs) {
  const auto [study, metric] = cause_metric();
  if (!study) return {{"injected", json::array()}};
  std::map<std::string, std::map<std::string, int>> counts;
  std::map<std::string, std::string> expected;
  std::set<std::string> columns;
  int scored = 0, as_expected = 0;
  for (const auto& r : runs) {
    const json& analyses = r.at("analyses");
    if (r.at("kind") == "log" || std::find(analyses.begin(), analyses.end(), study->name()) == analyses.end()) continue;
    const json& cause = r.at("metrics").at(metric.key);
    const std::string injected = effects_text(r.at("effects"));
    const std::string named = cause.is_string() ? cause.get<std::string>() : "none";
    ++counts[injected][named];
    columns.insert(named);
    expected[injected] = study->presentation().expected_cause(r.at("effects"));
    if (!expected[injected].empty()) {
      ++scored;
      if (expected[injected] == named) ++as_expected;
    }
  }
  json t = {{"study", study->identity().title}, {"rows", "injected effects"}, {"columns", "named cause"},
            {"injected", json::array()},        {"named", columns},           {"counts", json::array()},
            {"expected", json::array()},        {"scored_runs", scored},      {"named_as_expected", as_expected}};
  for (const auto& [injected, row] : counts) {
    t["injected"].push_back(injected);
    json line = json::array();
    for (const auto& c : columns) line.push_back(row.count(c) > 0 ? row.at(c) : 0);
    t["counts"].push_back(line);
    t["expected"].push_back(expected.at(injected).empty() ? json(nullptr) : json(expected.at(injected)));
  }
  return t;
}

class CampaignReportWriter {
 public:
  CampaignReportWriter(fs::path out, json runs) : out_(std::move(out)), runs_(std::move(runs)) {}

  void write() {
    head();
    table();
    distributions();
    confusion();
    html_ << "<p class=\"note\">Generated by roverlab campaign report. Full precision: campaign.csv, "
             "campaign.json.</p>\n</body></html>\n";
    json doc = {{"format", "roverlab-campaign-report"},
                {"version", 1},
                {"runs", runs_},
                {"columns", json::array()},
                {"summary", summary_},
                {"confusion", confusion_}};
    for (const auto& m : key_columns())
      doc["columns"].push_back({{"key", m.key}, {"title", m.title}, {"analysis", m.analysis}});
    io::write_text_atomically((out_ / "campaign.json").string(), doc.dump(1) + "\n");
    io::write_text_atomically((out_ / "campaign.csv").string(), csv());
    io::write_text_atomically((out_ / "index.html").string(), html_.str());
  }

 private:
  static std::string esc(const std::string& s) { return ReportSection::escape(s); }

  void head() {
    html_
        << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>RoverLab campaign report</title>\n"
        << "<style>body{font-family:sans-serif;max-width:1400px;margin:2em auto;padding:0 1.5em;box-sizing:border-box;"
        << "color:#222}.wide{overflow-x:auto;max-width:100%}"
        << "table{border-collapse:collapse;margin:1em 0;font-size:90%}td,th{border:1px solid #bbb;padding:3px 6px;"
        << "text-align:right}th{background:#eef}td.t{text-align:left}.note{color:#555}img{margin:4px}</style>"
        << "</head><body>\n<h1>RoverLab campaign report</h1>\n<p>" << runs_.size() << " runs";
    std::set<std::string> versions;
    for (const auto& r : runs_) versions.insert(r.at("roverlab_version").get<std::string>());
    for (const auto& v : versions) html_ << ", RoverLab " << esc(v);
    html_ << ".</p>\n";
  }

  void table() {
    // In a box that scrolls sideways: a column per key metric of every analysis is wider than a page.
    html_ << "<h2>Runs</h2>\n<div class=\"wide\"><table "
             "id=\"runs\"><tr><th>run</th><th>kind</th><th>scenario</th><th>seed</th>"
             "<th>injected effects</th>";
    if (!runs_.empty() && runs_.front().contains("comparison")) {  // beside the run, before the metrics
      html_ << "<th>differs from the baseline run ("
            << esc(runs_.front().at("comparison").at("baseline").get<std::string>()) << ")</th>";
    }
    for (const auto& m : key_columns()) html_ << "<th>" << esc(m.title) << "</th>";
    html_ << "</tr>\n";
    for (const auto& r : runs_) {
      const std::string name = r.at("name").get<std::string>();
      html_ << "<tr id=\"run-" << esc(name) << "\"><td class=\"t\"><a href=\"" << esc(r.at("report").get<std::string>())
            << "\">" << esc(name) << "</a></td><td class=\"t\">" << esc(r.at("kind").get<std::string>())
            << "</td><td class=\"t\">" << (r.at("scenario").is_string() ? esc(r.at("scenario").get<std::string>()) : "")
            << "</td><td>" << (r.at("seed").is_number() ? std::to_string(r.at("seed").get<std::uint64_t>()) : "")
            << "</td><td class=\"t\">" << esc(effects_text(r.at("effects"))) << "</td>";
      if (r.contains("comparison")) html_ << comparison_cell(r.at("comparison"));
      for (const auto& m : key_columns()) html_ << cell(r.at("metrics").at(m.key));
      html_ << "</tr>\n";
    }
    html_ << "</table></div>\n";
  }

  // The run against the baseline: a link to its comparison page, and the channels that differ.
  static std::string comparison_cell(const json& c) {
    if (c.contains("note")) return "<td class=\"t note\">" + esc(c.at("note").get<std::string>()) + "</td>";
    if (!c.contains("page")) return "<td class=\"t\">(the baseline)</td>";
    const json& differing = c.at("differing");
    std::string text = std::to_string(differing.size()) + " of " + std::to_string(c.at("channels").get<std::size_t>());
    for (std::size_t k = 0; k < differing.size(); ++k) text += (k ? ", " : ": ") + differing[k].get<std::string>();
    return "<td class=\"t\" style=\"min-width:24em\"><a class=\"comparison\" href=\"" +
           esc(c.at("page").get<std::string>()) + "\">" + esc(text) + "</a></td>";
  }

  // A metric cell as the HTML shows it: 4 significant digits, an en dash when absent.
  static std::string cell(const json& v) {
    if (v.is_string()) return "<td class=\"t\">" + esc(v.get<std::string>()) + "</td>";
    return "<td>" + ReportSection::number(v, "%.4g") + "</td>";
  }

  void distributions() {
    html_ << "<h2>Distributions over the runs</h2>\n";
    summary_ = json::object();
    for (const auto& m : key_columns()) {
      if (m.verdict) continue;
      std::vector<double> values;
      for (const auto& r : runs_) {
        const json& v = r.at("metrics").at(m.key);
        if (v.is_number() && std::isfinite(v.get<double>())) values.push_back(v.get<double>());
      }
      if (values.empty()) continue;
      double sum = 0;
      for (const double v : values) sum += v;
      summary_[m.key] = {{"runs", values.size()},
                         {"mean", sum / static_cast<double>(values.size())},
                         {"min", *std::min_element(values.begin(), values.end())},
                         {"max", *std::max_element(values.begin(), values.end())}};
      const std::string file = std::string("hist_") + m.key + ".svg";
      io::write_text_atomically((out_ / file).string(), histogram_svg(m.title, values));
      html_ << "<img src=\"" << file << "\" alt=\"" << esc(m.title) << "\">\n";
    }
    if (summary_.empty()) html_ << "<p class=\"note\">No run has a key metric.</p>\n";
  }

  void confusion() {
    confusion_ = confusion_table(runs_);
    if (confusion_.at("injected").empty()) return;
    html_ << "<h2>Named cause against injected effect</h2>\n<p>Simulated runs "
          << esc(confusion_.at("study").get<std::string>())
          << " ran on: "
             "rows are the effects injected into the simulation, columns the cause the study named.</p>\n"
             "<div class=\"wide\"><table id=\"confusion\"><tr><th>injected</th><th>expected</th>";
    for (const auto& c : confusion_.at("named")) html_ << "<th>" << esc(c.get<std::string>()) << "</th>";
    html_ << "</tr>\n";
    for (std::size_t i = 0; i < confusion_.at("injected").size(); ++i) {
      const json& expected = confusion_.at("expected").at(i);
      html_ << "<tr><td class=\"t\">" << esc(confusion_.at("injected").at(i).get<std::string>())
            << "</td><td class=\"t\">" << (expected.is_string() ? esc(expected.get<std::string>()) : "") << "</td>";
      std::size_t j = 0;
      for (const auto& c : confusion_.at("named")) {
        const bool hit = expected.is_string() && expected == c;
        html_ << "<td" << (hit ? " style=\"font-weight:bold\"" : "") << ">" << confusion_.at("counts").at(i).at(j++)
              << "</td>";
      }
      html_ << "</tr>\n";
    }
    html_ << "</table></div>\n<p class=\"legend\">Bold: the cell where the named cause is the expected one "
             "(the same meaning as in the studies' tables: bold is the cause named).</p>\n<p>"
          << confusion_.at("named_as_expected").get<int>() << " of " << confusion_.at("scored_runs").get<int>()
          << " runs whose injected effect has one right answer (column \"expected\") had it named. Without "
             "slip=0 the drive has slip episodes, whose steady slip looks like a smaller wheel radius.</p>\n";
  }

  std::string csv() const {
    std::string text = "name,kind,scenario,seed,effects";
    for (const auto& m : key_columns()) text += std::string(",") + m.key;
    text += ",report\n";
    for (const auto& r : runs_) {
      text += csv_cell(r.at("name")) + "," + csv_cell(r.at("kind")) + "," + csv_cell(r.at("scenario")) + "," +
              csv_cell(r.at("seed")) + "," + csv_cell(effects_text(r.at("effects")));
      for (const auto& m : key_columns()) text += "," + csv_cell(r.at("metrics").at(m.key));
      text += "," + csv_cell(r.at("report")) + "\n";
    }
    return text;
  }

  fs::path out_;
  json runs_;
  json summary_ = json::object();
  json confusion_ = json::object();
  std::ostringstream html_;
};

// A campaign report goes into a new or empty folder, or over a previous
// campaign report; never over the user's files or a run's own report.
void check_campaign_report_folder(const std::string& output) {
  if (output.empty()) throw UsageError("--output: the report folder's name is empty");
  const fs::path dir(output);
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) throw InputError(output, "exists and is not a folder");
  // Only a campaign report's own files may be there (Snakemake removes the
  // index, the CSV and the JSON before it writes them again; the histograms stay).
  bool ours = true;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const bool histogram = name.rfind("hist_", 0) == 0 && entry.path().extension() == ".svg";
    ours = ours && entry.is_regular_file() &&
           (name == "index.html" || name == "campaign.csv" || name == "campaign.json" || histogram ||
            is_comparison_page(name));
  }
  std::ifstream index(dir / "index.html");
  const std::string text((std::istreambuf_iterator<char>(index)), std::istreambuf_iterator<char>());
  if (ours && (!index.is_open() || text.find("<h1>RoverLab campaign report</h1>") != std::string::npos)) return;
  throw UsageError("--output " + output +
                   ": the folder holds other files than a RoverLab campaign report; choose a new or empty folder");
}

int run_campaign_report(const CampaignReportOptions& o) {
  check_campaign_report_folder(o.output);
  const fs::path out(o.output);
  // Every run is read before the folder is made: a bad run leaves nothing behind.
  json runs = json::array();
  std::set<std::string> names;
  for (const auto& dir : o.runs) {
    json row = read_run(dir, out);
    if (!names.insert(row.at("name").get<std::string>()).second) {
      throw UsageError("run " + row.at("name").get<std::string>() + " is given twice");
    }
    runs.push_back(std::move(row));
  }
  std::vector<CampaignRunLog> logs;
  std::size_t baseline = 0;
  for (std::size_t k = 0; k < o.runs.size(); ++k) {
    logs.push_back({runs[k].at("name").get<std::string>(), fs::path(o.runs[k]) / "log.h5"});
    if (o.baseline && logs.back().name == *o.baseline) baseline = k;
  }
  if (o.baseline && logs[baseline].name != *o.baseline)
    throw UsageError("--baseline " + *o.baseline + ": no run of that name");
  std::error_code ec;
  fs::create_directories(out, ec);
  if (ec || !fs::is_directory(out)) {
    throw InputError(o.output, "cannot create the report folder" + (ec ? ": " + ec.message() : std::string()));
  }
  if (logs.size() > 1) {  // each run against the baseline run, linked from its row
    const json compared = compare_with_baseline(logs, baseline, out);
    for (std::size_t k = 0; k < logs.size(); ++k) runs[k]["comparison"] = compared[k];
  }
  CampaignReportWriter(out, std::move(runs)).write();
  std::printf("wrote %s: %zu runs\n", (out / "index.html").c_str(), o.runs.size());
  return kSuccess;
}

}  // namespace

Commands make_campaign_report_commands() {
  Commands commands;
  commands.push_back(make_command<CampaignReportOptions>(
      "campaign report",
      "The campaign report of finished runs: a table of key metrics and verdicts, histograms, named-vs-injected "
      "causes; HTML, CSV and JSON",
      [](CLI::App& cmd, CampaignReportOptions& o) {
        cmd.add_option("RUN_DIRS", o.runs, "Run folders (runs/NAME: run.json and report/metrics.json)")->required();
        cmd.add_option("--output,-o", o.output, "Report folder (created if missing)")->required();
        cmd.add_option("--baseline", o.baseline,
                       "The run NAME every other run's log is compared with (default: the first run given)");
      },
      run_campaign_report));
  return commands;
}

}  // namespace roverlab::app

// `roverlab report`: an HTML page for a log — the views as PNG, the result of
// every registered analysis that can run on it (the same JSON document as
// `estimate X --json`, in metrics.json under analyses/<name>), the traction
// surfaces — with CSV and JSON beside it.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <vector>

#include "app/analysis.h"
#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/log_input.h"
#include "app/render_view.h"
#include "app/report_compare.h"
#include "app/report_lab_test.h"
#include "app/report_pdf.h"
#include "app/resources.h"
#include "app/views_input.h"
#include "core/common/error.h"
#include "core/log/run_overview.h"
#include "importers/atomic_file.h"
#include "importers/json_resource.h"
#include "importers/mapping.h"
#include "importers/soil_file.h"

#include "app/view_data.h"
#include "core/estimation/ins_slip/streams.h"
#include "views/timeseries_chart.h"
#include "views/view.h"
#include "views/x_display.h"

#ifndef ROVERLAB_VERSION
#define ROVERLAB_VERSION "unknown"
#endif

namespace roverlab::app {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct ReportOptions {
  std::string file;
  std::optional<std::string> mapping;
  std::optional<std::string> soil;
  std::string quantity = "drawbar-pull";
  std::string size = "1280x800";
  std::string output;
  bool pdf = false;
  std::vector<std::string> compare;  // runs compared with the log (report_compare.h)
};

class ReportWriter {
 public:
  ReportWriter(const ReportOptions& o, const ViewInput& in, int w, int h, const std::vector<ComparedLog>& compared)
      : o_(o), in_(in), dir_(o.output), section_(dir_), w_(w), h_(h), compared_(compared) {}

  void write() {
    head();
    write_lab_test_section(section_, dir_, metrics_, in_, o_.soil, w_, h_);  // a single-wheel or plate test's
    summary();
    if (!in_.is_wheel_test() && !in_.is_plate_test()) {
      streams();
      views();
    }
    if (!compared_.empty()) {
      write_comparison_section(section_, metrics_, o_.file, in_.log, compared_);
      compared_views();
    }
    analyses();
    if (in_.is_wheel_test() || o_.soil || has_surfaces()) {
      for (const char* q : {"drawbar-pull", "torque"}) traction_surface(q);
    }
    made_with();
    html() << "</body></html>\n";
    const std::vector<std::string> previous = previous_files();
    section_.wrote("metrics.json");
    section_.wrote("provenance.json");
    section_.wrote("index.html");
    if (o_.pdf) section_.wrote("report.pdf");
    metrics_["files"] = section_.written();
    io::write_text_atomically((dir_ / "metrics.json").string(), metrics_.dump(2) + "\n");
    io::write_text_atomically((dir_ / "provenance.json").string(), provenance_.dump(2) + "\n");
    io::write_text_atomically((dir_ / "index.html").string(), html().str());
    remove_stale(previous);
  }

 private:
  std::ostringstream& html() { return section_.html; }
  bool has_surfaces() const {
    return std::any_of(in_.analyses.begin(), in_.analyses.end(),
                       [](const AnalysisRun& run) { return run.analysis->presentation().draws_traction_surfaces(); });
  }
  static std::string esc(const std::string& s) { return ReportSection::escape(s); }
  static std::string num(double v, const char* f) { return ReportSection::number(v, f); }

  void head() {
    metrics_ = {{"file", o_.file}, {"notes", in_.notes}, {"analyses", json::object()}};
    html()
        << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>RoverLab report: "
        << esc(fs::path(o_.file).filename().string()) << "</title>\n<style>"
        << "body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
        << "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:4px 8px;text-align:right}"
        << "th{background:#eef}caption{text-align:left;font-weight:bold;padding:0.3em 0}.result "
           "th{text-align:center}img{max-width:100%;border:1px solid #ccc}.note{color:#555}li{margin:0.4em "
           "0}.notes{color:#555;font-size:90%}.notes li{margin:0.1em 0}"
           // Printed (--pdf, A4): the page's width, no heading alone at a page's foot, no picture cut in two.
           "@page{size:A4;margin:14mm}@media print{body{max-width:none;margin:0;font-size:10pt}"
           "h2{break-after:avoid}img,svg,tr{break-inside:avoid}table{font-size:8.5pt}}</style></head><body>\n"
        << "<h1>RoverLab report</h1>\n<p>" << esc(o_.file) << "</p>\n";
  }

  // The answers first: each analysis's summary (Presentation::summary), then what
  // was not run and why.
  void summary() {
    html() << "<h2>Summary</h2>\n";
    if (!in_.is_wheel_test() && !in_.is_plate_test()) run_overview();  // a lab test is described by its own section
    html() << "<ul>\n";
    json lines = json::array();
    for (const auto& run : in_.analyses) {
      const Analysis* a = run.analysis.get();
      const std::string text = a->presentation().summary(run.document);
      if (text.empty()) continue;
      html() << "<li><b>" << esc(a->identity().title) << "</b>: " << esc(text) << "</li>\n";
      lines.push_back({{"analysis", run.name}, {"summary", text}});
    }
    html() << "</ul>\n";
    // What ran and what did not, one short line each (issue 32: the first screen holds the answers).
    html() << "<ul class=\"notes\">\n";
    for (const auto& n : in_.notes) html() << "<li>" << esc(n) << "</li>\n";
    html() << "</ul>\n";
    metrics_["summary"] = lines;
  }

  // The run in one line: the rover, how long, how far (and along which pose
  // source), where (the first GPS fix, else the local frame).
  void run_overview() {
    const analysis::RunOverview r = analysis::overview_of(in_.log, estimation::ins_streams::kPoseSources);
    std::string where = "local frame (no GPS fix)";
    if (r.has_gps_fix) {
      char at[96];
      std::snprintf(at, sizeof at, "%.5f&deg; %s, %.5f&deg; %s", std::abs(r.start_latitude_deg),
                    r.start_latitude_deg < 0 ? "S" : "N", std::abs(r.start_longitude_deg),
                    r.start_longitude_deg < 0 ? "W" : "E");
      where = std::string("starting at ") + at + " (first GPS fix)";
    }
    const std::string distance = r.distance_source.empty()
                                     ? std::string("distance unknown (no pose source)")
                                     : num(r.distance_m, "%.3g") + " m travelled along the " + esc(r.distance_method) +
                                           " (stream " + esc(r.distance_source) + ")";
    html() << "<p class=\"run\"><b>The run</b>: rover " << esc(r.rover.empty() ? "unnamed" : r.rover) << "; "
           << num(r.duration_s, "%.3g") << " s; " << distance << "; " << (r.has_gps_fix ? where : esc(where))
           << ".</p>\n";
    metrics_["run"] = {
        {"rover", r.rover},
        {"duration_s", r.duration_s},
        {"distance_m", finite_or_null(r.distance_m)},
        {"distance_source", r.distance_source},
        {"distance_method", r.distance_method},
        {"start", r.has_gps_fix ? json{{"latitude_deg", r.start_latitude_deg}, {"longitude_deg", r.start_longitude_deg}}
                                : json("local frame")}};
  }

  // The files the report was made from, with their SHA-256: the log, and the mapping and soil files named.
  json input_files() const {
    std::vector<std::pair<std::string, std::string>> files = {{"log", o_.file}};
    if (o_.mapping) files.emplace_back("mapping", io::find_mapping(*o_.mapping, resource_subfolders("mappings")));
    std::error_code ec;
    if (o_.soil && fs::is_regular_file(*o_.soil, ec)) files.emplace_back("soil", *o_.soil);
    for (const auto& f : o_.compare) files.emplace_back("compared run", f);
    json out = json::array();
    for (const auto& [role, path] : files) {
      const auto bytes = fs::file_size(path, ec);
      out.push_back({{"role", role},
                     {"path", path},
                     {"bytes", ec ? json(nullptr) : json(bytes)},
                     {"sha256", sha256_of_file(path)}});
    }
    return out;
  }

  // Every analysis's settings and what it ran on (its document's "configuration" and "input").
  json analysis_provenance() {
    json out = json::object();
    html() << "<table><tr><th>analysis</th><th>settings</th><th>measurements (fingerprint)</th></tr>\n";
    for (const auto& run : in_.analyses) {
      const json configuration = run.document.value("configuration", json::object());
      const json input = run.document.value("input", json::object());
      std::string settings = configuration_text(run.document);  // "settings: a 1, b 2\n"
      if (settings.rfind("settings: ", 0) == 0) settings.erase(0, 10);
      while (!settings.empty() && settings.back() == '\n') settings.pop_back();
      html() << "<tr><td style=\"text-align:left\">" << esc(run.name) << "</td><td style=\"text-align:left\">"
             << esc(settings.empty() ? "(no options)" : settings) << "</td><td style=\"text-align:left\"><code>"
             << esc(input.value("fingerprint", std::string())) << "</code></td></tr>\n";
      out[run.name] = {{"configuration", configuration}, {"input", input}};
    }
    html() << "</table>\n";
    return out;
  }

  // How the report was made: the command as run and the command that makes it
  // again, the program (version and build), when, the input files with their
  // SHA-256, and each analysis's settings.
  void made_with() {
    // Every word quoted for the shell: a log named "$(touch x).h5" must not run anything when pasted.
    std::string command = "roverlab report " + shell_word(o_.file);
    if (o_.mapping) command += " --mapping " + shell_word(*o_.mapping);
    if (o_.soil) command += " --soil " + shell_word(*o_.soil);
    for (const auto& f : o_.compare) command += " --compare " + shell_word(f);
    command += " --size " + shell_word(o_.size) + (o_.pdf ? " --pdf" : "") + " -o " + shell_word(o_.output);
    const std::time_t now = std::time(nullptr);
    char when[32] = "";
    std::tm utc{};
    if (gmtime_r(&now, &utc) != nullptr) std::strftime(when, sizeof when, "%Y-%m-%d %H:%M:%S UTC", &utc);
    std::string invoked;
    for (const auto& a : command_arguments()) invoked += (invoked.empty() ? "" : " ") + shell_word(a);
    const json inputs = input_files();
    html() << "<h2>How this report was made</h2>\n<table class=\"provenance\">"
           << "<tr><th>command run</th><td style=\"text-align:left\"><code>" << esc(invoked) << "</code></td></tr>\n"
           << "<tr><th>to make it again</th><td style=\"text-align:left\"><code>" << esc(command)
           << "</code></td></tr>\n"
           << "<tr><th>RoverLab</th><td style=\"text-align:left\">" << esc(program_identity()) << "</td></tr>\n"
           << "<tr><th>written</th><td style=\"text-align:left\">" << when << "</td></tr>\n";
    for (const auto& f : inputs) {
      html() << "<tr><th>" << esc(f.at("role").get<std::string>()) << "</th><td style=\"text-align:left\">"
             << esc(f.at("path").get<std::string>())
             << (f.at("bytes").is_number() ? " (" + std::to_string(f.at("bytes").get<std::uintmax_t>()) + " bytes)"
                                           : std::string())
             << "<br>SHA-256 <code>" << esc(f.at("sha256").get<std::string>()) << "</code></td></tr>\n";
    }
    html() << "</table>\n";
    const json analyses = analysis_provenance();
    // Not the time, nor the files' checksums (an HDF5 log written twice differs in its bytes): the same log
    // and options give the same metrics.json (campaigns compare them). The whole record: provenance.json.
    metrics_["made_with"] = {{"command", command}, {"version", ROVERLAB_VERSION}, {"program", program_identity()}};
    provenance_ = {
        {"command", command}, {"command_run", invoked}, {"version", ROVERLAB_VERSION}, {"program", program_identity()},
        {"written", when},    {"inputs", inputs},       {"analyses", analyses}};
  }

  // The files a previous report in the folder wrote (its metrics.json's "files").
  std::vector<std::string> previous_files() const {
    std::vector<std::string> files;
    std::ifstream in(dir_ / "metrics.json");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const json old = io::parse_bounded_json(text);
    if (!old.is_object() || !old.contains("files") || !old.at("files").is_array()) return files;
    for (const auto& f : old.at("files")) {
      if (f.is_string()) files.push_back(f.get<std::string>());
    }
    return files;
  }

  // A name a report writes: its four fixed files, and images and tables named
  // [a-z0-9_-]+ with .png or .csv. metrics.json's list is data: a name in it
  // that is not of these (a user's thesis.tex) is never removed.
  static bool report_file_name(const std::string& name) {
    for (const char* fixed : {"index.html", "metrics.json", "provenance.json", "report.pdf"}) {
      if (name == fixed) return true;
    }
    const std::size_t dot = name.rfind('.');
    if (dot == std::string::npos || dot == 0) return false;
    const std::string ext = name.substr(dot);
    return (ext == ".png" || ext == ".csv") &&
           std::all_of(name.begin(), name.begin() + static_cast<long>(dot),
                       [](char c) { return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-'; });
  }

  // A previous report's files that this one did not write again (another
  // log's surfaces and tables) are removed: the folder holds one report.
  // Only names a report writes (report_file_name) are removed, never a path.
  void remove_stale(const std::vector<std::string>& previous) const {
    const std::vector<std::string>& now = section_.written();
    for (const auto& name : previous) {
      if (!report_file_name(name) || std::find(now.begin(), now.end(), name) != now.end()) continue;
      std::error_code ec;
      if (fs::is_regular_file(dir_ / name, ec)) fs::remove(dir_ / name, ec);
    }
  }

  // A word as a POSIX shell reads it back: quoted when it holds anything but [A-Za-z0-9_./=:,+-].
  static std::string shell_word(const std::string& w) {
    const bool plain = !w.empty() && std::all_of(w.begin(), w.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("_./=:,+-", c) != nullptr;
    });
    if (plain) return w;
    std::string q = "'";
    for (char c : w) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
  }

  void image(const std::string& name, const std::string& title, const Rendered& r) {
    save_png(r.image, (dir_ / name).string());
    section_.wrote(name);
    html() << "<h2>" << title << "</h2>\n<img src=\"" << name << "\" alt=\"" << title << "\">\n";
    for (const auto& n : r.notes) html() << "<p class=\"note\">" << esc(n) << "</p>\n";
  }

  void streams() {
    html() << "<h2>Streams</h2>\n<table><tr><th>stream</th><th>samples</th><th>rate (Hz)</th><th>duration (s)</th>"
              "<th>channels</th></tr>\n";
    json streams = json::array();
    for (const auto& s : in_.log.streams()) {
      html() << "<tr><td style=\"text-align:left\">" << esc(s.name()) << "</td><td>" << s.size() << "</td><td>"
             << num(s.mean_rate_hz(), "%.1f") << "</td><td>" << num(s.duration(), "%.2f") << "</td><td>"
             << s.channels().size() << "</td></tr>\n";
      streams.push_back({{"name", s.name()}, {"samples", s.size()}, {"rate_hz", s.mean_rate_hz()}});
    }
    html() << "</table>\n";
    metrics_["streams"] = streams;
  }

  // Every registered view the log can feed (the traction surfaces come with
  // their fits below), in registry order; the INS slip beside its reference
  // after the plots.
  void views() {
    for (const auto& view : views::all_views()) {
      if (view->uses_surface_data() || view->plots_channel_pair() || view->compares_runs() || view->uses_lab_figures())
        continue;
      const int h = static_cast<int>(h_ * view->report_height());
      Rendered r;
      try {
        r = render_view(in_, *view, ViewOptions{}, w_, h);
      } catch (const InputError& e) {
        html() << "<p class=\"note\">No " << view->name() << " view: " << esc(e.problem()) << "</p>\n";
        continue;
      }
      std::string file = view->name();
      std::replace(file.begin(), file.end(), '-', '_');
      image(file + ".png", view->heading(), r);
      if (view->uses_channels()) {
        analysis_plots(*view, h);
        slip_plot(*view, h);
      }
    }
  }

  // The views that draw the compared runs against the log (every track with a marker on each, the ghost
  // rover, the overlays of all runs in one picture), at the views' own time.
  void compared_views() {
    ViewOptions o;
    for (const auto& c : compared_) o.compared.emplace_back(fs::path(c.file).stem().string(), &c.log);
    for (const auto& view : views::all_views()) {
      if (!view->compares_runs()) continue;
      Rendered r;
      try {
        r = render_view(in_, *view, o, w_, static_cast<int>(h_ * view->report_height()));
      } catch (const InputError& e) {
        html() << "<p class=\"note\">No " << view->name() << " view: " << esc(e.problem()) << "</p>\n";
        continue;
      } catch (const DataError& e) {
        html() << "<p class=\"note\">No " << view->name() << " view: " << esc(e.what()) << "</p>\n";
        continue;
      }
      std::string file = view->name();
      std::replace(file.begin(), file.end(), '-', '_');
      image(file + ".png", view->heading(), r);
    }
  }

  // The charts each analysis asks for (Presentation::report_plots), drawn by the
  // channel-plot view.
  void analysis_plots(const views::View& plots, int h) {
    for (const AnalysisRun& run : in_.analyses) {
      for (const ReportPlot& p : run.analysis->presentation().report_plots(run.document, in_.log)) {
        ViewOptions o;
        o.channel_spec = p.channel_spec;
        image(p.file, p.heading, render_view(in_, plots, o, w_, h * p.rows));
        html() << "<p class=\"note\">" << esc(p.note) << "</p>\n";
      }
    }
  }

  void slip_plot(const views::View& plots, int h) {
    const log::Stream* slip = in_.log.find_stream(estimation::ins_streams::kSlip);
    if (slip == nullptr || slip->find_channel("reference_slip") == nullptr) return;
    // Not twice: the default plot may be this very pair (views::default_channels).
    for (const auto& c : views::default_channels(in_.log)) {
      if (c.stream == estimation::ins_streams::kSlip && c.channel == "reference_slip") return;
    }
    ViewOptions o;
    o.channel_spec = std::string(estimation::ins_streams::kSlip) + ":slip_ratio," + estimation::ins_streams::kSlip +
                     ":reference_slip";
    image("slip.png", "Slip ratio: INS estimate and reference", render_view(in_, plots, o, w_, h));
  }

  void analyses() {
    for (const auto& run : in_.analyses) {
      run.analysis->presentation().report(run.document, section_);
      if (const std::string settings = configuration_text(run.document); !settings.empty())
        html() << "<p class=\"note\">" << esc(settings) << "</p>\n";
      metrics_["analyses"][run.name] = run.document;
    }
  }

  void traction_surface(const std::string& quantity) {
    terramechanics::SurfaceFit fit;
    views::TractionSurfaceData d;
    try {
      d = traction_surface_of(in_, quantity, o_.soil, &fit);
    } catch (const InputError& e) {
      html() << "<p class=\"note\">No " << quantity << " surface: " << esc(e.problem()) << "</p>\n";
      return;
    }
    image("surface_" + quantity + ".png", "Traction surface: " + d.quantity, render_traction_surface(d, w_, h_));
    html() << "<table><tr><th>term</th><th>coefficient</th></tr>\n";
    std::string csv = "k_slip,l_load,coefficient\n";
    json coeffs = json::array();
    const auto& c = fit.surface.coefficients();
    for (std::size_t i = 0; i < c.size(); ++i) {
      const auto [k, l] = terramechanics::PolynomialSurface::exponents(i);
      html() << "<tr><td>s^" << k << " W^" << l << "</td><td>" << num(c[i], "%.6g") << "</td></tr>\n";
      csv += std::to_string(k) + "," + std::to_string(l) + "," + num(c[i], "%.10g") + "\n";
      coeffs.push_back(c[i]);
    }
    html() << "</table>\n<p>Fit RMSE " << num(fit.error.rmse, "%.4g") << " " << d.unit << ", order "
           << fit.surface.order() << ".</p>\n";
    section_.write_csv("surface_" + quantity + ".csv", csv);
    metrics_["traction_surface_" + quantity] = {
        {"order", fit.surface.order()}, {"coefficients", coeffs}, {"fit_rmse", fit.error.rmse}};
  }

  const ReportOptions& o_;
  const ViewInput& in_;
  fs::path dir_;
  ReportSection section_;
  int w_, h_;
  const std::vector<ComparedLog>& compared_;
  json metrics_;
  json provenance_;  // how the report was made, with the input files' SHA-256 (provenance.json)
};

// A report goes into a new or empty folder, or over a previous report; never
// over a folder of the user's other files (their index.html would be lost).
void check_report_folder(const std::string& output) {
  const fs::path dir(output);
  std::error_code ec;
  if (output.empty()) throw UsageError("--output: the report folder's name is empty");
  if (!fs::exists(dir, ec)) return;
  if (!fs::is_directory(dir, ec)) throw InputError(output, "exists and is not a folder");
  if (fs::is_empty(dir, ec)) return;
  std::ifstream index(dir / "index.html");
  std::string text((std::istreambuf_iterator<char>(index)), std::istreambuf_iterator<char>());
  if (text.find("<h1>RoverLab report</h1>") != std::string::npos) return;
  throw UsageError("--output " + output +
                   ": the folder holds other files and no RoverLab report; "
                   "choose a new or empty folder");
}

int run_report(const ReportOptions& o) {
  const auto [w, h] = parse_size(o.size);
  check_report_folder(o.output);
  if (o.pdf) (void)report_pdf_printer();
  // An unknown soil is an error, not a silently missing section.
  if (o.soil) (void)io::find_soil(*o.soil, resource_subfolders("soils"));
  ViewInputOptions vo;
  vo.analyses = all_analysis_names();
  std::vector<ComparedLog> compared;
  for (const auto& f : o.compare) compared.push_back({f, load_input(f, o.mapping).log});
  const ViewInput in = load_view_input(o.file, o.mapping, vo);
  if (!compared.empty() && in.is_wheel_test()) throw UsageError("--compare compares logs, not a single-wheel test");
  const fs::path dir(o.output);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) {
    throw InputError(o.output, "cannot create the report folder" + (ec ? ": " + ec.message() : std::string()));
  }
  views::ensure_display();
  ReportWriter(o, in, w, h, compared).write();
  std::printf("wrote %s\n", (dir / "index.html").string().c_str());
  if (o.pdf) {
    print_report_pdf((dir / "index.html").string(), (dir / "report.pdf").string());
    std::printf("wrote %s\n", (dir / "report.pdf").string().c_str());
  }
  return kSuccess;
}

}  // namespace

Commands make_report_commands() {
  Commands commands;
  commands.push_back(make_command<ReportOptions>(
      "report", "Write an HTML report (views as PNG, metric tables, CSV and JSON) for a log into a folder",
      [](CLI::App& cmd, ReportOptions& o) {
        cmd.add_option("FILE", o.file, "Log (HDF5, .mat with --mapping, CSV) or single-wheel CSV")->required();
        cmd.add_option("--mapping,-m", o.mapping, "Mapping NAME or FILE for .mat/HDF5 input");
        cmd.add_option("--soil", o.soil, "Add the traction surfaces of soil NAME|FILE");
        cmd.add_option("--size", o.size, "WxH pixels of the 3D views")->capture_default_str();
        cmd.add_option("--output,-o", o.output, "Report folder (created if missing)")->required();
        cmd.add_flag("--pdf", o.pdf, "Also print the report to DIR/report.pdf (A4, through headless Chromium)");
        cmd.add_option("--compare", o.compare,
                       "Another run's log compared with FILE (repeatable): overlays, differences, every track");
      },
      run_report));
  return commands;
}

}  // namespace roverlab::app

// `discrepancy rover`: what the planar rocker-bogie simulation gets wrong on
// a rover log, the cause or causes, the extended model and its held-out gain.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/analysis.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/report_plot.h"
#include "app/rover_scenario.h"
#include "core/common/error.h"
#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/rover/streams.h"
#include "core/discrepancy/rover/study.h"

namespace roverlab::app {

namespace {

using nlohmann::json;

json parameters_json(const std::vector<analysis::RoverParameterFit>& ps) {
  json a = json::array();
  for (const auto& p : ps) {
    a.push_back({{"effect", p.effect},
                 {"unit", p.unit},
                 {"value", p.value},
                 {"sigma", finite_or_null(p.sigma)},
                 {"at_bound", p.at_bound}});
  }
  return a;
}

// "effect value +- sigma" for each parameter; a screened candidate's values
// are its one Gauss-Newton step's, with no sigma: "~value".
std::string rover_parameters_text(const json& ps, bool screened = false) {
  std::string t;
  for (const auto& p : ps) {
    const json& sigma = p.at("sigma");
    const double value = p.at("value").get<double>();
    std::string v;
    if (screened) {
      char buf[48];
      std::snprintf(buf, sizeof buf, "~%.4g", value);
      v = buf + std::string(p.at("unit").get<std::string>() == "1" ? "" : " " + p.at("unit").get<std::string>());
    } else {
      v = roverlab::analysis::format_fitted(value, sigma.is_number() ? sigma.get<double>() : NAN,
                                            p.at("unit").get<std::string>(), p.value("at_bound", false));
    }
    t += (t.empty() ? "" : ", ") + p.at("effect").get<std::string>() + " " + v;
  }
  return t;
}

// RMS of the finite values of v; NaN when there are none.
double rms(const std::vector<double>& v) {
  double sum = 0;
  std::size_t n = 0;
  for (const double x : v) {
    if (!std::isfinite(x)) continue;
    sum += x * x;
    ++n;
  }
  return n ? std::sqrt(sum / static_cast<double>(n)) : NAN;
}

// The residual before and after the named causes, overlaid, against time and
// against slip; log y: before a cause is named it can be thousands of sigmas.
void rover_residual_plots(const json& j, const std::vector<double>& t, const std::vector<double>& slip,
                          const std::vector<double>& before, const std::vector<double>& after, ReportSection& s) {
  const std::string causes = j.at("causes_text").get<std::string>();
  const std::vector<PlotSeries> series = {{"nominal model", "#888888", before},
                                          {causes == "none" ? "no cause named" : "with " + causes, "#1f77b4", after}};
  PlotSpec by_time{"Residual against time, before and after the causes", "time (s)",
                   "residual, RMS over channels (noise sigmas)", series};
  by_time.log_y = true;
  by_time.css_class = "plot residual-plot";
  for (auto& one : by_time.series) one.x = t;
  PlotSpec by_slip = by_time;
  by_slip.title = "Residual against slip";
  by_slip.x_title = "mean wheel slip (1)";
  for (auto& one : by_slip.series) {
    one.x = slip;
    one.points = true;
  }
  s.html << "<p>Residual (RMS over the channels, each in its noise sigmas; log scale): nominal model grey, with the "
            "named causes blue; RMS over the run "
         << ReportSection::number(rms(before), "%.3g") << " before, " << ReportSection::number(rms(after), "%.3g")
         << " after.</p>\n"
         << plot_svg(by_time) << plot_svg(by_slip) << "\n";
}

constexpr char kRoverTitle[] = "What the rover simulation gets wrong";

// How its result is shown.
class RoverDiscrepancyPresentation : public Presentation {
 public:
  void print(const json& j, std::FILE* out) const override;
  void report(const json& j, ReportSection& section) const override;
  std::vector<ResultTable> tables(const json& j) const override;
  std::vector<ReportPlot> report_plots(const json& j, const log::Log& lg) const override;
  std::string summary(const json& j) const override {
    const json& regime = j.at("slip_regime");
    const std::string what = j.at("what_is_wrong").get<std::string>() + " " + j.at("verdict").get<std::string>();
    // A stuck rover's regime already leads what_is_wrong.
    return regime.at("stuck").get<bool>() ? what : regime.at("text").get<std::string>() + " " + what;
  }
  std::vector<KeyMetric> key_metrics() const override {
    return {{"rover_held_out_before", "rover held-out error before (sigmas)", "/baseline/held_out"},
            {"rover_held_out_after", "rover held-out error after (sigmas)", "/held_out_after"},
            {"rover_causes", "named causes (rover)", "/causes_text", true}};
  }
};

class RoverDiscrepancyAnalysis : public Analysis {
 public:
  RoverDiscrepancyAnalysis()
      : Analysis({"rover-discrepancy",
                  "discrepancy rover",
                  kRoverTitle,
                  "Planar rocker-bogie log against its scenario's simulation: residuals, the cause or causes, the gain",
                  "Planar rocker-bogie log (joints, imu, velocimeter, forces, commands), e.g. from roverlab simulate",
                  {analysis::rover_streams::kPrefix},
                  std::nullopt},
                 std::make_unique<RoverDiscrepancyPresentation>()) {}

  std::string missing(const log::Log& lg) const override {
    for (const char* s : {"joints", "imu", "velocimeter", "forces", "commands"}) {
      if (lg.find_stream(s) == nullptr) return std::string("no ") + s + " stream";
    }
    if (!scenario_ && lg.metadata.extra.count("scenario") == 0 && lg.metadata.extra.count("scenario_json") == 0) {
      return "the log names no scenario: give --scenario";
    }
    return "";
  }
  void declare(CLI::App& cmd) override {
    cmd.add_option("--scenario", scenario_,
                   "Scenario NAME or FILE.json: the model of the run (default: the one the log names)");
    cmd.add_option("--block", block_, "s, length of the alternating fit/test blocks")
        ->capture_default_str()
        ->check(finite_in(0.2, 1000.0));
  }
  json configuration() const override {
    return {{"scenario", scenario_ ? json(*scenario_) : json(nullptr)}, {"block_s", block_}};
  }
  // The scenario's content, whether --scenario named it or the log records it.
  json resolved_configuration(const log::Log& lg) const override {
    return {{"scenario", rover_scenario_content(scenario_, lg.metadata.extra, "the log")}, {"block_s", block_}};
  }
  void check_options() const override {
    if (scenario_ && scenario_->empty()) throw UsageError("--scenario: the scenario's name is empty");
  }
  AnalysisResult run(const AnalysisInput& in) override;

 private:
  static json document(const std::string& file, const analysis::RoverDiscrepancyReport& r);
  std::optional<std::string> scenario_;
  double block_ = 1.0;
};

// A scenario on another path (flat, rolling, slope, bump, with their sizes) than the one the
// log records cannot be this run's model: refused before minutes of fitting.
void refuse_another_run(const AnalysisInput& in, const analysis::RoverScenarioModel& model) {
  const auto& meta = in.log.metadata.extra;
  if (meta.count("scenario_json") == 0 && meta.count("scenario") == 0) return;
  analysis::RoverScenarioModel recorded;
  try {
    recorded = load_logs_rover_scenario(meta, in.file);
  } catch (const std::exception&) {
    return;  // the log's own record is not usable; the scenario given is the model
  }
  if (recorded.run.path.name != model.run.path.name) {
    throw InputError(in.file, "the log was simulated on the " + recorded.run.path.name + " path (scenario " +
                                  recorded.name + "); scenario " + model.name + " drives the " + model.run.path.name +
                                  " path and cannot be this run's model");
  }
  // On the same path, what no candidate cause changes (issue 34, N6): the
  // rover and its wheel radius, the speed set point, where the run starts on
  // a path that is not flat. (The duration is the log's own.)
  char text[200] = "";
  const auto differs = [](double a, double b) { return std::abs(a - b) > 1e-9 * std::max(1.0, std::abs(a)); };
  if (recorded.rover != model.rover) {
    std::snprintf(text, sizeof text, "rover %s, not %s", recorded.rover.c_str(), model.rover.c_str());
  } else if (differs(recorded.geometry.wheel_radius, model.geometry.wheel_radius)) {
    std::snprintf(text, sizeof text, "wheel radius %g m, not %g m", recorded.geometry.wheel_radius,
                  model.geometry.wheel_radius);
  } else if (differs(recorded.parameters.desired_speed, model.parameters.desired_speed)) {
    std::snprintf(text, sizeof text, "desired speed %g m/s, not %g m/s", recorded.parameters.desired_speed,
                  model.parameters.desired_speed);
  } else if (recorded.run.path.name.rfind("flat", 0) != 0 && differs(recorded.run.start_x, model.run.start_x)) {
    std::snprintf(text, sizeof text, "start at x = %g m, not %g m", recorded.run.start_x, model.run.start_x);
  } else {
    return;
  }
  throw InputError(in.file, "the log was simulated with scenario " + recorded.name + " (" + text + "); scenario " +
                                model.name + " cannot be this run's model");
}

// Each measured channel minus the simulation, nominal and with the named
// causes: estimate/rover_discrepancy/residual_nominal/<stream> and
// .../residual_with_causes/<stream>, channels named as the measured ones, on
// the measured time stamps (the report plots where they disagree most).
void add_residual_streams(const log::Log& lg, const analysis::RoverDiscrepancyReport& r, log::Log& out) {
  std::vector<log::Stream> streams;
  const auto stream_of = [&](const std::string& name, const std::vector<double>& time) -> log::Stream& {
    auto it = std::find_if(streams.begin(), streams.end(), [&](const log::Stream& s) { return s.name() == name; });
    if (it != streams.end()) return *it;
    return streams.emplace_back(name, time);
  };
  for (const auto& c : r.channels) {
    const log::Stream* measured = lg.find_stream(c.stream);
    const log::Channel* values = measured != nullptr ? measured->find_channel(c.channel) : nullptr;
    if (values == nullptr || c.time != measured->time() || c.predicted_before.size() != c.time.size() ||
        c.predicted_after.size() != c.time.size())
      continue;
    std::vector<double> before(c.time.size()), after(c.time.size());
    for (std::size_t k = 0; k < c.time.size(); ++k) {
      before[k] = values->values[k] - c.predicted_before[k];
      after[k] = values->values[k] - c.predicted_after[k];
    }
    stream_of(analysis::rover_streams::kResidualNominal + c.stream, c.time)
        .add_channel(c.channel, c.unit, before, "measured minus the nominal simulation");
    stream_of(analysis::rover_streams::kResidualWithCauses + c.stream, c.time)
        .add_channel(c.channel, c.unit, after, "measured minus the simulation with the named causes");
  }
  for (auto& s : streams) out.add_stream(std::move(s));
}

AnalysisResult RoverDiscrepancyAnalysis::run(const AnalysisInput& in) {
  // The scenario the user gives, else the one recorded in (or named by) the log: data, never a path.
  const analysis::RoverScenarioModel model =
      scenario_ ? load_rover_scenario(*scenario_) : load_logs_rover_scenario(in.log.metadata.extra, in.file);
  if (scenario_) refuse_another_run(in, model);
  analysis::RoverStudyOptions options;
  options.block = block_;
  options.progress = in.progress;
  const analysis::RoverDiscrepancyReport r =
      about_file(in.file, [&] { return analysis::study_rover(in.log, model, options); });
  AnalysisResult out;
  out.document = document(in.file, r);
  log::Stream st(analysis::rover_streams::kResiduals, r.time);
  st.add_channel("before", "1", r.residual_before, "RMS over channels of the residual in noise sigmas, nominal model");
  st.add_channel("after", "1", r.residual_after, "the same with the named causes");
  st.add_channel("slip", "1", r.slip, "mean wheel slip from encoders and velocimeter");
  out.estimates.add_stream(std::move(st));
  add_residual_streams(in.log, r, out.estimates);
  return out;
}

json RoverDiscrepancyAnalysis::document(const std::string& file, const analysis::RoverDiscrepancyReport& r) {
  json j = {{"file", file},
            {"scenario", r.scenario},
            {"drive", r.drive},
            {"held_out_method", r.held_out_method},
            {"duration_s", r.duration},
            {"residuals", {{"fit", r.fit_residuals}, {"test", r.test_residuals}}},
            {"baseline",
             {{"bic", r.baseline_bic}, {"held_out", r.baseline_held_out}, {"test_minus_two_log_l", r.baseline_test}}},
            {"held_out_after", r.final_held_out},
            {"test_minus_two_log_l_after", r.final_test},
            {"incomplete", r.incomplete},
            {"simulations", r.simulations},
            {"what_is_wrong", r.what_is_wrong},
            {"verdict", r.verdict},
            {"slip_regime",
             {{"text", r.slip_regime.text},
              {"mean_slip", finite_or_null(r.slip_regime.mean_slip)},
              {"distance_m", r.slip_regime.distance},
              {"rolled_out_m", r.slip_regime.rolled_out},
              {"stuck", r.slip_regime.stuck}}}};
  json ch = json::array();
  for (const auto& c : r.channels) {
    ch.push_back({{"stream", c.stream},
                  {"channel", c.channel},
                  {"unit", c.unit},
                  {"sigma", c.sigma},
                  {"rmse", c.rmse},
                  {"bias", c.bias},
                  {"drift_per_100s", finite_or_null(c.drift)},
                  {"t_drift", finite_or_null(c.t_drift)},
                  {"slope_vs_slip", finite_or_null(c.slope_vs_slip)},
                  {"t_slip", finite_or_null(c.t_slip)},
                  {"slope_vs_position", finite_or_null(c.slope_vs_position)},
                  {"t_position", finite_or_null(c.t_position)},
                  {"slope_vs_load", finite_or_null(c.slope_vs_load)},
                  {"t_load", finite_or_null(c.t_load)},
                  {"held_out_rmse_before", finite_or_null(c.held_out_rmse_before)},
                  {"held_out_rmse_after", finite_or_null(c.held_out_rmse_after)},
                  {"held_out_sigmas_before", finite_or_null(c.held_out_sigmas_before)},
                  {"held_out_sigmas_after", finite_or_null(c.held_out_sigmas_after)}});
  }
  j["channels"] = ch;
  json checks = json::array();
  for (const auto& c : r.checks) {
    checks.push_back({{"name", c.name},
                      {"value", finite_or_null(c.value)},
                      {"expected", finite_or_null(c.expected)},
                      {"sigma", finite_or_null(c.sigma)},
                      {"unit", c.unit},
                      {"consistent", c.consistent},
                      {"verdict", c.verdict}});
  }
  j["checks"] = checks;
  json cands = json::array();
  for (const auto& c : r.candidates) {
    cands.push_back({{"name", c.name},
                     {"cause", c.cause},
                     {"parameters", parameters_json(c.parameters)},
                     {"minus_two_log_l", c.minus_two_log_l},
                     {"delta_bic", c.delta_bic},
                     {"held_out", c.held_out},
                     {"significant", c.significant},
                     {"simulations", c.simulations},
                     {"screened", c.screened}});
  }
  j["candidates"] = cands;
  // Every step of the final model with its role; "causes" only the named ones.
  json sel = json::array();
  std::string causes;
  j["causes"] = json::array();
  for (const auto& s : r.selection) {
    sel.push_back({{"name", s.name},
                   {"cause", s.cause},
                   {"parameters", parameters_json(s.parameters)},
                   {"delta_bic", s.delta_bic},
                   {"held_out", s.held_out},
                   {"held_out_without", finite_or_null(s.held_out_without)},
                   {"test_minus_two_log_l_without", finite_or_null(s.test_without)},
                   {"gain_share", finite_or_null(s.gain_share)},
                   {"channel_share", finite_or_null(s.channel_share)},
                   {"role", analysis::step_role_name(s.role)}});
    if (s.role != analysis::StepRole::cause) continue;
    causes += (causes.empty() ? "" : " + ") + s.name;
    j["causes"].push_back(s.name);
  }
  j["selection"] = sel;
  j["causes_text"] = causes.empty() ? "none" : causes;
  // The residual before and after, decimated to at most 600 samples, for the report's plots.
  json plot = {{"time", json::array()}, {"before", json::array()}, {"after", json::array()}, {"slip", json::array()}};
  const std::size_t stride = std::max<std::size_t>(1, r.time.size() / 600);
  for (std::size_t k = 0; k < r.time.size(); k += stride) {
    plot["time"].push_back(r.time[k]);
    plot["before"].push_back(finite_or_null(r.residual_before[k]));
    plot["after"].push_back(finite_or_null(r.residual_after[k]));
    plot["slip"].push_back(finite_or_null(r.slip[k]));
  }
  j["plot"] = plot;
  return j;
}

void RoverDiscrepancyPresentation::print(const json& j, std::FILE* out) const {
  std::fprintf(out, "%s against scenario %s (%.0f s); %s\n%s\n\n", j.at("file").get<std::string>().c_str(),
               j.at("scenario").get<std::string>().c_str(), j.at("duration_s").get<double>(),
               j.at("held_out_method").get<std::string>().c_str(), j.at("drive").get<std::string>().c_str());
  std::fprintf(out, "  %-28s %11s %11s %11s %13s %9s %15s\n", "channel", "noise", "RMSE", "bias", "drift/100 s",
               "t drift", "held-out after");
  for (const auto& c : j.at("channels")) {
    std::fprintf(out, "  %-28s %11.3g %11.3g %11.3g %13s %9s %15s %s\n",
                 (c.at("stream").get<std::string>() + "/" + c.at("channel").get<std::string>()).c_str(),
                 c.at("sigma").get<double>(), c.at("rmse").get<double>(), c.at("bias").get<double>(),
                 ReportSection::number(c.at("drift_per_100s")).c_str(), ReportSection::number(c.at("t_drift")).c_str(),
                 ReportSection::number(c.at("held_out_rmse_after")).c_str(), c.at("unit").get<std::string>().c_str());
  }
  // A stuck rover's regime leads what_is_wrong below.
  if (!j.at("slip_regime").at("stuck").get<bool>())
    std::fprintf(out, "\n%s\n", j.at("slip_regime").at("text").get<std::string>().c_str());
  std::fprintf(out, "\nChecks among the sensors, and against the model's slip and traction surfaces:\n");
  for (const auto& c : j.at("checks")) {
    const json& sigma = c.at("sigma");
    std::fprintf(out, "  %s: %s (expected %s +- %s %s): %s\n", c.at("name").get<std::string>().c_str(),
                 ReportSection::number(c.at("value"), "%.4g").c_str(),
                 ReportSection::number(c.at("expected"), "%.4g").c_str(),
                 ReportSection::number(sigma.is_number() ? json(3 * sigma.get<double>()) : sigma, "%.2g").c_str(),
                 c.at("unit").get<std::string>().c_str(), c.at("verdict").get<std::string>().c_str());
  }
  std::fprintf(out, "\n%s\n\n  %-22s %-44s %10s %9s\n", j.at("what_is_wrong").get<std::string>().c_str(), "candidate",
               "fitted", "delta BIC", "held-out");
  std::fprintf(out, "  %-22s %-44s %10s %9.3g\n", "(nominal)", "", "0", j.at("baseline").at("held_out").get<double>());
  bool undetermined = false;
  for (const auto& c : j.at("candidates")) {
    std::string p = rover_parameters_text(c.at("parameters"), c.at("screened").get<bool>());
    // The column is narrow: "(not determined by the data)" as "(undetermined)", said below the table.
    for (std::size_t at; p.size() > 44 && (at = p.find(" (not determined by the data)")) != std::string::npos;) {
      p.replace(at, 29, " (undetermined)");
      undetermined = true;
    }
    if (p.size() > 44) p = p.substr(0, 43) + "~";
    std::fprintf(out, "  %-22s %-44s %10s %9.3g%s\n", c.at("name").get<std::string>().c_str(), p.c_str(),
                 roverlab::analysis::format_delta_bic(c.at("delta_bic").get<double>()).c_str(),
                 c.at("held_out").get<double>(),
                 c.at("significant").get<bool>() ? ""
                 : c.at("screened").get<bool>()  ? "  (screened out)"
                                                 : "  (not significant)");
  }
  if (undetermined) {
    std::fprintf(out,
                 "  (undetermined: the likelihood is flat or not at a minimum along that parameter, so the data do "
                 "not give it a +-1 sigma)\n");
  }
  std::fprintf(out, "\n%s\n", j.at("verdict").get<std::string>().c_str());
}

// A candidate's standing in words: named as the cause, significant, not significant, screened out.
std::string candidate_status(const json& c, const std::vector<std::string>& named) {
  if (std::find(named.begin(), named.end(), c.at("name").get<std::string>()) != named.end()) return "named cause";
  if (c.at("screened").get<bool>()) return "screened out";
  return c.at("significant").get<bool>() ? "significant, not named" : "not significant";
}

std::vector<ResultTable> RoverDiscrepancyPresentation::tables(const json& j) const {
  const auto n = [](const json& v, const char* f) { return ReportSection::number(v, f); };
  ResultTable candidates;
  candidates.title = "What the simulation gets wrong: candidate causes, by evidence";
  candidates.columns = {"candidate", "fitted (+-1 sigma)", "delta BIC", "held-out residual (noise sigmas)", "status"};
  candidates.rows.push_back({{"(nominal)"}, {""}, {"0"}, {n(j.at("baseline").at("held_out"), "%.3g")}, {""}});
  std::vector<std::string> named;  // the causes the verdict names
  for (const auto& c : j.at("causes")) named.push_back(c.get<std::string>());
  // By evidence: the lowest delta BIC (the most the data favour) first.
  std::vector<const json*> order;
  for (const auto& c : j.at("candidates")) order.push_back(&c);
  const auto evidence = [](const json* c) {
    const json& d = c->at("delta_bic");
    return d.is_number() && std::isfinite(d.get<double>()) ? d.get<double>() : HUGE_VAL;
  };
  std::stable_sort(order.begin(), order.end(), [&](const json* a, const json* b) { return evidence(a) < evidence(b); });
  for (const json* cp : order) {
    const json& c = *cp;
    std::vector<ResultTable::Cell> row{{c.at("name").get<std::string>()},
                                       {rover_parameters_text(c.at("parameters"), c.at("screened").get<bool>())},
                                       {roverlab::analysis::format_delta_bic(c.at("delta_bic").get<double>())},
                                       {n(c.at("held_out"), "%.3g")},
                                       {candidate_status(c, named)}};
    const bool picked = std::find(named.begin(), named.end(), c.at("name").get<std::string>()) != named.end();
    for (auto& cell : row) cell.bold = picked;
    candidates.rows.push_back(std::move(row));
  }
  candidates.legend = "Bold: the cause the study names (" +
                      (named.empty() ? std::string("none named") : j.at("causes_text").get<std::string>()) +
                      "), and nothing else; status says which others are significant. Rows by evidence: the lowest "
                      "delta BIC (the most the data favour) first.";
  ResultTable checks;
  checks.title = "Checks among the sensors and against the model";
  checks.columns = {"check", "value", "expected", "unit", "agrees", "verdict"};
  // Bold is kept for a named cause: a check the data contradict says "no" in its own column.
  for (const auto& c : j.at("checks")) {
    checks.rows.push_back({{c.at("name").get<std::string>()},
                           {n(c.at("value"), "%.4g")},
                           {n(c.at("expected"), "%.4g")},
                           {c.at("unit").get<std::string>()},
                           {c.at("consistent").get<bool>() ? "yes" : "no"},
                           {c.at("verdict").get<std::string>()}});
  }
  checks.legend = "No bold here (bold marks a named cause); agrees: no where the data contradict the check.";
  return {candidates, checks};
}

void RoverDiscrepancyPresentation::report(const json& j, ReportSection& s) const {
  const auto n = [](const json& v, const char* f) { return ReportSection::number(v, f); };
  s.html << "<h2>" << kRoverTitle << "</h2>\n<p>" << ReportSection::escape(j.at("what_is_wrong").get<std::string>())
         << "</p>\n<p>"
         << ReportSection::escape(j.at("slip_regime").at("stuck").get<bool>()
                                      ? std::string()
                                      : j.at("slip_regime").at("text").get<std::string>())
         << "</p>\n<p><b>" << ReportSection::escape(j.at("verdict").get<std::string>()) << "</b></p>\n<p>"
         << ReportSection::escape(j.at("drive").get<std::string>()) << "; "
         << ReportSection::escape(j.at("held_out_method").get<std::string>()) << ".</p>\n"
         << "<table><tr><th>channel</th><th>unit</th><th>noise</th><th>RMSE</th><th>bias</th><th>drift / 100 s</th>"
            "<th>t (slip)</th><th>t (position)</th><th>t (load)</th><th>held-out before</th><th>held-out "
            "after</th></tr>\n";
  std::string csv =
      "stream,channel,unit,sigma,rmse,bias,drift_per_100s,t_drift,t_slip,t_position,t_load,held_out_before,held_out_"
      "after\n";
  for (const auto& c : j.at("channels")) {
    s.html << "<tr><td style=\"text-align:left\">"
           << ReportSection::escape(c.at("stream").get<std::string>() + "/" + c.at("channel").get<std::string>())
           << "</td><td>" << ReportSection::escape(c.at("unit").get<std::string>()) << "</td><td>"
           << n(c.at("sigma"), "%.3g") << "</td><td>" << n(c.at("rmse"), "%.3g") << "</td><td>"
           << n(c.at("bias"), "%.3g") << "</td><td>" << n(c.at("drift_per_100s"), "%.3g") << "</td><td>"
           << n(c.at("t_slip"), "%.3g") << "</td><td>" << n(c.at("t_position"), "%.3g") << "</td><td>"
           << n(c.at("t_load"), "%.3g") << "</td><td>" << n(c.at("held_out_rmse_before"), "%.3g") << "</td><td>"
           << n(c.at("held_out_rmse_after"), "%.3g") << "</td></tr>\n";
    csv += c.at("stream").get<std::string>() + "," + c.at("channel").get<std::string>() + "," +
           c.at("unit").get<std::string>();
    for (const char* k : {"sigma", "rmse", "bias", "drift_per_100s", "t_drift", "t_slip", "t_position", "t_load",
                          "held_out_rmse_before", "held_out_rmse_after"}) {
      csv += "," + n(c.at(k), "%.6g");
    }
    csv += "\n";
  }
  s.html << "</table>\n";
  for (const ResultTable& t : tables(j)) s.table(t);
  const auto series = [&](const char* key) {
    std::vector<double> v;
    for (const auto& x : j.at("plot").at(key)) v.push_back(x.is_number() ? x.get<double>() : NAN);
    return v;
  };
  rover_residual_plots(j, series("time"), series("slip"), series("before"), series("after"), s);
  s.write_csv("rover_discrepancy_channels.csv", csv);
}

}  // namespace

// The two channels where the simulation disagrees most with the measurement
// (RMSE in noise sigmas): measured minus simulated, nominal and with the
// named causes, for the channels whose residual streams the log holds.
std::vector<ReportPlot> RoverDiscrepancyPresentation::report_plots(const json& j, const log::Log& lg) const {
  if (!j.contains("channels")) return {};
  std::vector<std::pair<double, std::string>> ranked;
  for (const auto& c : j.at("channels")) {
    const std::string stream = c.at("stream").get<std::string>(), channel = c.at("channel").get<std::string>();
    const log::Stream* residual = lg.find_stream(analysis::rover_streams::kResidualNominal + stream);
    if (residual == nullptr || residual->find_channel(channel) == nullptr) continue;
    const double sigmas = c.at("rmse").get<double>() / std::max(c.at("sigma").get<double>(), 1e-300);
    ranked.emplace_back(sigmas, stream + ":" + channel);
  }
  if (ranked.empty()) return {};
  std::sort(ranked.begin(), ranked.end(), std::greater<>());
  ReportPlot p;
  p.file = "disagreement.png";
  p.heading = "Where the simulation disagrees most: measured minus simulated, nominal and with the causes";
  p.rows = static_cast<int>(std::min<std::size_t>(ranked.size(), 2));
  std::string names;
  for (std::size_t k = 0; k < ranked.size() && k < 2; ++k) {
    const std::string& measured = ranked[k].second;
    p.channel_spec += std::string(k ? "," : "") + analysis::rover_streams::kResidualNominal + measured + "," +
                      analysis::rover_streams::kResidualWithCauses + measured;
    names +=
        (k ? " and " : "") + measured + " (RMSE " + ReportSection::number(ranked[k].first, "%.3g") + " noise sigmas)";
  }
  p.note = "The channels with the largest RMSE in noise sigmas: " + names + ".";
  return {p};
}

std::unique_ptr<Analysis> make_rover_discrepancy_analysis() { return std::make_unique<RoverDiscrepancyAnalysis>(); }

}  // namespace roverlab::app

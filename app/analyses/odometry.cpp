// `discrepancy odometry`: what skid-steer wheel odometry gets wrong against the
// GPS track, the cause among the candidates, the fitted correction and its
// held-out gain.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>

#include "app/analysis.h"
#include "app/command_support.h"
#include "app/report_plot.h"
#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/odometry/study.h"

namespace roverlab::app {

namespace {

using nlohmann::json;

constexpr char kOdometryTitle[] = "What the wheel odometry gets wrong";

// How its result is shown.
class OdometryPresentation : public Presentation {
 public:
  void print(const json& j, std::FILE* out) const override;
  std::string summary(const json& j) const override { return j.at("verdict").get<std::string>(); }
  std::vector<KeyMetric> key_metrics() const override {
    return {{"odometry_held_out_rmse_m", "odometry held-out RMSE (m)", "/baseline/held_out_rmse_m"},
            {"odometry_cause", "named cause (odometry)", "/cause", true, true}};
  }
  std::string expected_cause(const json& effects) const override;
  void report(const json& j, ReportSection& section) const override;
  std::vector<ResultTable> tables(const json& j) const override;
};

class OdometryAnalysis : public Analysis {
 public:
  OdometryAnalysis()
      : Analysis({"odometry",
                  "discrepancy odometry",
                  kOdometryTitle,
                  "Wheel-odometry dead reckoning against the GPS track: cause of the disagreement, fitted correction, "
                  "gain",
                  "Log with wheels and gps streams",
                  {},  // it adds no streams
                  std::nullopt},
                 std::make_unique<OdometryPresentation>()) {}

  std::string missing(const log::Log& lg) const override {
    if (lg.find_stream("wheels") == nullptr) return "no wheels stream";
    if (lg.find_stream("gps") == nullptr) return "no gps stream";
    return "";
  }
  void declare(CLI::App& cmd) override {
    cmd.add_option("--fit-fraction", fit_fraction_, "Share of the drive (by distance) used to fit; the rest tests")
        ->capture_default_str()
        ->check(finite_in(0.1, 0.9));
  }
  json configuration() const override { return {{"fit_fraction", fit_fraction_}}; }
  AnalysisResult run(const AnalysisInput& in) override {
    analysis::OdometryStudyOptions options;
    options.fit_fraction = fit_fraction_;
    if (in.progress) in.progress(0.0);
    const analysis::OdometryDiscrepancyReport r = analysis::study_odometry(in.log, options);
    if (in.progress) in.progress(1.0);
    AnalysisResult out;
    out.document = document(in.file, r);
    return out;
  }

 private:
  static json document(const std::string& file, const analysis::OdometryDiscrepancyReport& r);
  static json candidate_json(const analysis::OdometryCandidate& c);
  double fit_fraction_ = 0.5;
};

// The cause the study should name for a simulated run with these injected effects.
std::string OdometryPresentation::expected_cause(const json& effects) const {
  std::vector<std::string> others;
  for (const auto& [name, value] : effects.items()) {
    if (name != "slip") others.push_back(name);
  }
  const bool firm = effects.contains("slip") && effects.at("slip") == 0;
  if (others.empty()) return firm ? "none" : "";
  if (others.size() > 1) return "";
  const std::string& effect = others.front();
  if (effect == "left-radius-scale" || effect == "right-radius-scale") return "per-side scale";
  if (effect == "radius-scale") return "radius scale";
  if (effect == "turning-track-factor") return "turning track";
  if (effect == "wheel-time-offset") return "time offset";
  return "";
}

json OdometryAnalysis::document(const std::string& file, const analysis::OdometryDiscrepancyReport& r) {
  json j = {{"file", file},
            {"distance_m", r.distance},
            {"fit_distance_m", r.fit_distance},
            {"split_time_s", r.split_time},
            {"reference_samples", {{"fit", r.fit_samples}, {"test", r.test_samples}}},
            {"baseline",
             {{"fit_rmse_m", r.baseline_fit_rmse},
              {"held_out_rmse_m", r.baseline_held_out_rmse},
              {"held_out_final_m", r.baseline_held_out_final},
              {"distance_ratio", r.distance_ratio},
              {"heading_error_rad", finite_or_null(r.heading_error_end)},
              {"along_track_rmse_m", finite_or_null(r.along_track_rmse)},
              {"cross_track_rmse_m", finite_or_null(r.cross_track_rmse)}}},
            {"cause", r.best >= 0 ? json(r.candidates[static_cast<std::size_t>(r.best)].name) : json(nullptr)},
            {"what_is_wrong", r.what_is_wrong},
            {"verdict", r.verdict},
            {"candidates", json::array()}};
  for (const auto& c : r.candidates) j["candidates"].push_back(candidate_json(c));
  // Forward selection: each step the chain so far, refitted together.
  j["selection"] = json::array();
  for (const auto& c : r.selection) j["selection"].push_back(candidate_json(c));
  j["rejected_step"] = r.rejected_step ? candidate_json(*r.rejected_step) : json(nullptr);
  // The track error before and after the named cause, at most 600 samples, for the report's plots.
  const analysis::OdometryResiduals& res = r.residuals;
  json plot = {{"time_s", json::array()},
               {"before_m", json::array()},
               {"after_m", json::array()},
               {"slip", json::array()},
               {"held_out_rms_before_m", res.rms_before},
               {"held_out_rms_after_m", finite_or_null(res.rms_after)}};
  const std::size_t stride = std::max<std::size_t>(1, (res.time.size() + 599) / 600);
  for (std::size_t k = 0; k < res.time.size(); k += stride) {
    plot["time_s"].push_back(res.time[k]);
    plot["before_m"].push_back(finite_or_null(res.before[k]));
    plot["after_m"].push_back(finite_or_null(res.after[k]));
    plot["slip"].push_back(finite_or_null(res.slip[k]));
  }
  j["residuals"] = plot;
  return j;
}

json OdometryAnalysis::candidate_json(const analysis::OdometryCandidate& c) {
  json cj = {{"name", c.name},
             {"cause", c.cause},
             {"parameters", json::array()},
             {"fit_rmse_m", c.fit_rmse},
             {"delta_bic", c.delta_bic},
             {"held_out_rmse_m", c.held_out_rmse},
             {"held_out_final_m", c.held_out_final},
             {"significant", c.significant},
             {"at_bound", c.at_bound},
             {"gain_share", finite_or_null(c.gain_share)},
             {"role", analysis::step_role_name(c.role)}};
  for (const auto& p : c.parameters) {
    cj["parameters"].push_back(
        {{"name", p.name}, {"value", p.value}, {"sigma", finite_or_null(p.sigma)}, {"at_bound", p.at_bound}});
  }
  return cj;
}

// "0.9981+-0.0012", "3 windows", "name 0.5": the fitted parameters in a line.
std::string parameters_text(const json& parameters) {
  std::string text;
  for (const auto& p : parameters) {
    char one[80];
    const std::string name = p.at("name").get<std::string>();
    const double value = p.at("value").get<double>();
    if (p.value("at_bound", false)) {
      std::snprintf(one, sizeof one, "%s%s %.4g (at its bound)", text.empty() ? "" : ", ", name.c_str(), value);
    } else if (p.at("sigma").is_number()) {
      std::snprintf(one, sizeof one, "%s%.4g+-%.2g", text.empty() ? "" : " ", value, p.at("sigma").get<double>());
    } else if (name == "windows") {
      std::snprintf(one, sizeof one, "%s%d windows", text.empty() ? "" : " ", static_cast<int>(value));
    } else {
      std::snprintf(one, sizeof one, "%s%s %.3g", text.empty() ? "" : ", ", name.c_str(), value);
    }
    text += one;
  }
  return text;
}

// "track_factor 4.778 +- 1.4", "5 windows, median_slip 0.0618": each fitted parameter named, for the tables.
std::string parameters_named(const json& parameters) {
  std::string text;
  for (const auto& p : parameters) {
    const std::string name = p.at("name").get<std::string>();
    const double value = p.at("value").get<double>();
    std::string one;
    if (p.value("at_bound", false)) {
      one = name + " " + roverlab::analysis::format_fitted(value, NAN, "1", true);
    } else if (p.at("sigma").is_number()) {
      one = name + " " + roverlab::analysis::format_estimate(value, p.at("sigma").get<double>(), "1");
    } else if (name == "windows") {
      one = std::to_string(static_cast<int>(value)) + " windows";
    } else {
      one = name + " " + ReportSection::number(value, "%.3g");
    }
    text += (text.empty() ? "" : ", ") + one;
  }
  return text;
}

void OdometryPresentation::print(const json& j, std::FILE* out) const {
  const auto num = [&](const json& v) { return v.get<double>(); };
  const json& b = j.at("baseline");
  std::fprintf(out, "%s: %.1f m of reference track; fit on the first %.1f m (to t = %.1f s), test on the rest\n\n",
               j.at("file").get<std::string>().c_str(), num(j.at("distance_m")), num(j.at("fit_distance_m")),
               num(j.at("split_time_s")));
  std::fprintf(out, "%s\n\n", j.at("what_is_wrong").get<std::string>().c_str());
  std::fprintf(out, "  %-16s %-30s %9s %10s %13s %12s\n", "candidate", "fitted", "fit RMSE", "delta BIC",
               "held-out RMSE", "final error");
  std::fprintf(out, "  %-16s %-30s %7.2f m %10s %11.2f m %10.2f m\n", "(baseline)", "nominal geometry",
               num(b.at("fit_rmse_m")), "0", num(b.at("held_out_rmse_m")), num(b.at("held_out_final_m")));
  for (const auto& c : j.at("candidates")) {
    std::string params = parameters_text(c.at("parameters"));
    if (params.size() > 30) params = params.substr(0, 29) + "~";
    std::fprintf(out, "  %-16s %-30s %7.2f m %10.1f %11.2f m %10.2f m%s\n", c.at("name").get<std::string>().c_str(),
                 params.c_str(), num(c.at("fit_rmse_m")), num(c.at("delta_bic")), num(c.at("held_out_rmse_m")),
                 num(c.at("held_out_final_m")), c.at("significant").get<bool>() ? "" : "  (not significant)");
  }
  const json& chain = j.at("selection");
  if (chain.size() >= 2) {
    std::fprintf(out, "\nforward selection (each step refitted with the ones before):\n");
    for (const auto& c : chain) {
      std::fprintf(out, "  %-40s delta BIC %9.1f   held-out RMSE %6.2f m   final %6.2f m   share %s (%s)\n",
                   c.at("name").get<std::string>().c_str(), num(c.at("delta_bic")), num(c.at("held_out_rmse_m")),
                   num(c.at("held_out_final_m")), ReportSection::number(c.at("gain_share"), "%.3g").c_str(),
                   c.at("role").get<std::string>().c_str());
    }
  }
  std::fprintf(out, "\n%s\n", j.at("verdict").get<std::string>().c_str());
}

// Candidates by evidence: the lowest delta BIC (the most the data favour) first, after the nominal geometry.
std::vector<const json*> by_evidence(const json& candidates) {
  std::vector<const json*> order;
  for (const auto& c : candidates) order.push_back(&c);
  const auto key = [](const json* c) {
    const json& d = c->at("delta_bic");
    return d.is_number() && std::isfinite(d.get<double>()) ? d.get<double>() : HUGE_VAL;
  };
  std::stable_sort(order.begin(), order.end(), [&](const json* a, const json* b) { return key(a) < key(b); });
  return order;
}

std::vector<ResultTable> OdometryPresentation::tables(const json& j) const {
  ResultTable t;
  t.title = "What the wheel odometry gets wrong: candidate causes, by evidence";
  t.columns = {"candidate", "fitted (+-1 sigma)", "fit RMSE (m)",
               "delta BIC", "held-out RMSE (m)",  "held-out final (m)"};
  const auto n = [](const json& v, const char* f) { return ReportSection::number(v, f); };
  const json& b = j.at("baseline");
  t.rows.push_back({{"(nominal geometry)"},
                    {""},
                    {n(b.at("fit_rmse_m"), "%.2f")},
                    {"0"},
                    {n(b.at("held_out_rmse_m"), "%.2f")},
                    {n(b.at("held_out_final_m"), "%.2f")}});
  for (const json* cp : by_evidence(j.at("candidates"))) {
    const json& c = *cp;
    const bool picked = c.at("name") == j.at("cause");
    std::vector<ResultTable::Cell> row{
        {c.at("name").get<std::string>()},
        {parameters_named(c.at("parameters"))},
        {n(c.at("fit_rmse_m"), "%.2f")},
        {c.at("delta_bic").is_number() ? roverlab::analysis::format_delta_bic(c.at("delta_bic").get<double>())
                                       : n(c.at("delta_bic"), "%.1f")},
        {n(c.at("held_out_rmse_m"), "%.2f")},
        {n(c.at("held_out_final_m"), "%.2f")}};
    for (auto& cell : row) cell.bold = picked;
    t.rows.push_back(std::move(row));
  }
  t.legend = "Bold: the cause the study names (" +
             (j.at("cause").is_string() ? j.at("cause").get<std::string>() : std::string("none named")) +
             "), and nothing else. Rows by evidence: the lowest delta BIC (the most the data favour) first.";
  return {t};
}

std::vector<double> numbers(const json& a) {
  std::vector<double> v;
  v.reserve(a.size());
  for (const auto& x : a) v.push_back(x.is_number() ? x.get<double>() : NAN);
  return v;
}

// The track error before and after the named cause, overlaid, against time
// (the dashed line: the held-out part starts, dead-reckoned afresh) and slip.
void residual_plots(const json& j, ReportSection& s) {
  if (!j.contains("residuals")) return;
  const json& r = j.at("residuals");
  std::vector<double> t = numbers(r.at("time_s")), before = numbers(r.at("before_m")), after = numbers(r.at("after_m"));
  const std::vector<double> slip = numbers(r.at("slip"));
  const double split = j.at("split_time_s").get<double>();
  const std::string cause = j.at("cause").is_string() ? j.at("cause").get<std::string>() : std::string();
  std::vector<PlotSeries> series = {{"nominal geometry", "#888888", before}};
  if (!cause.empty()) series.emplace_back("with " + cause, "#1f77b4", after);
  PlotSpec by_time{"Track error against GPS, before and after the cause", "time (s)", "position error (m)", series};
  // The line breaks where the held-out part starts afresh.
  const auto at = static_cast<std::ptrdiff_t>(std::upper_bound(t.begin(), t.end(), split) - t.begin());
  t.insert(t.begin() + at, split);
  for (auto& one : by_time.series) {
    one.x = t;
    one.y.insert(one.y.begin() + at, NAN);
  }
  by_time.marker_x = split;
  by_time.marker_label = "held out";
  by_time.css_class = "plot residual-plot";
  PlotSpec by_slip{"Track error against slip", "slip (1 - GPS speed / wheel speed)", "position error (m)", series};
  for (auto& one : by_slip.series) {
    one.x = slip;
    one.points = true;
  }
  by_slip.css_class = "plot residual-plot";
  s.html << "<p>Track error (horizontal distance to the GPS fix), nominal geometry grey"
         << (cause.empty() ? std::string(" (no cause named)") : ", with the named cause blue") << "; held-out RMS "
         << ReportSection::number(r.at("held_out_rms_before_m"), "%.2f") << " m"
         << (cause.empty() ? std::string()
                           : " before, " + ReportSection::number(r.at("held_out_rms_after_m"), "%.2f") + " m after")
         << ". Each part is dead-reckoned from its own start; slip where the wheels roll at 0.05 m/s or more.</p>\n"
         << plot_svg(by_time) << plot_svg(by_slip) << "\n";
}

void OdometryPresentation::report(const json& j, ReportSection& s) const {
  const auto n = [](const json& v, const char* f) { return ReportSection::number(v, f); };
  s.html << "<h2>" << kOdometryTitle << "</h2>\n<p>" << ReportSection::escape(j.at("what_is_wrong").get<std::string>())
         << "</p>\n";
  for (const ResultTable& t : tables(j)) s.table(t);
  std::string csv = "candidate,fit_rmse_m,delta_bic,held_out_rmse_m,held_out_final_m,significant\n";
  for (const auto& c : j.at("candidates")) {
    csv += c.at("name").get<std::string>() + "," + n(c.at("fit_rmse_m"), "%.6g") + "," + n(c.at("delta_bic"), "%.6g") +
           "," + n(c.at("held_out_rmse_m"), "%.6g") + "," + n(c.at("held_out_final_m"), "%.6g") + "," +
           (c.at("significant").get<bool>() ? "1" : "0") + "\n";
  }
  s.html << "<p><b>" << ReportSection::escape(j.at("verdict").get<std::string>()) << "</b></p>\n";
  residual_plots(j, s);
  s.write_csv("odometry_candidates.csv", csv);
}

}  // namespace

std::unique_ptr<Analysis> make_odometry_analysis() { return std::make_unique<OdometryAnalysis>(); }

}  // namespace roverlab::app

// `estimate contact-angle`: contact angles, side slip, slip and velocity of a
// six-wheel DH rover with an EKF or UKF (seed 000), RMS errors in the layout of
// Tables 6.2-6.5 when the log has truth.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include "app/analyses/health.h"
#include "app/analysis.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/estimation/contact_angle/contact_angle.h"
#include "core/estimation/contact_angle/model_selection.h"
#include "core/estimation/contact_angle/streams.h"
#include "importers/rover_file.h"

namespace roverlab::app {

namespace {

using nlohmann::json;
constexpr double kDeg = 180.0 / M_PI;

kinematics::RoverModel dh_rover(const io::RoverDescription& d) {
  if (!d.dh) throw InputError(d.file, "rover '" + d.name + "' is not described by a DH table (kind " + d.kind + ")");
  return *d.dh;
}

json degrees(const std::vector<double>& radians) {
  json out = json::array();
  for (double v : radians) out.push_back(v * kDeg);
  return out;
}

json candidate_json(const estimation::ModelEvidence& e);

json rms_json(const estimation::StateErrors& e) {
  json rms = {{"velocity_mps", e.velocity}, {"slip", e.slip}, {"samples", e.samples}};
  if (!e.contact_angle.empty()) rms["contact_angle_deg"] = degrees(e.contact_angle);
  if (!e.side_slip.empty()) rms["side_slip_deg"] = degrees(e.side_slip);
  return rms;
}

// --model auto: the choice and its evidence, one line per candidate.
void print_selection(const json& s, std::FILE* out) {
  std::fprintf(out, "model auto: %s\n", s.at("reason").get<std::string>().c_str());
  std::fprintf(out, "  %-7s %6s %9s %10s %14s %16s %10s\n", "model", "states", "mean NIS", "windows >", "ln L", "AIC",
               "verdict");
  for (const json& c : s.at("candidates")) {
    const auto num = [&](const char* key) { return c.at(key).is_number() ? c.at(key).get<double>() : NAN; };
    std::fprintf(out, "  %-7s %6d %9.3f %9.0f%% %14.1f %16.1f %10s\n", c.at("model").get<std::string>().c_str(),
                 c.at("states").get<int>(), num("mean_nis"), 100.0 * num("nis_windows_above_band"),
                 num("log_likelihood"), num("aic"),
                 c.at("diverged").get<bool>()     ? "diverged"
                 : c.at("consistent").get<bool>() ? "consistent"
                                                  : "rejected");
  }
}

// One table of RMS errors in the layout of seed 000 Tables 6.2-6.5.
void print_rms(const json& rms, const json& wheels, const char* what, std::FILE* out) {
  std::fprintf(out, "\nRMS errors of the %s over %zu moving samples (layout of seed 000 Tables 6.2-6.5):\n", what,
               rms.at("samples").get<std::size_t>());
  std::fprintf(out, "  %-6s %14s %12s %16s %16s\n", "", "velocity (m/s)", "slip (-)", "contact (deg)",
               "side slip (deg)");
  const char* axes[3] = {"x", "y", "z"};
  for (std::size_t w = 0; w < 6; ++w) {
    char vel[32] = "";
    if (w < 3) std::snprintf(vel, sizeof vel, "%s %.4f", axes[w], rms.at("velocity_mps").at(w).get<double>());
    char ca[32] = "-", ss[32] = "-";
    if (rms.contains("contact_angle_deg"))
      std::snprintf(ca, sizeof ca, "%.4f", rms.at("contact_angle_deg").at(w).get<double>());
    if (rms.contains("side_slip_deg"))
      std::snprintf(ss, sizeof ss, "%.4f", rms.at("side_slip_deg").at(w).get<double>());
    std::fprintf(out, "  %-6s %14s %12.4f %16s %16s\n", wheels.at(w).get<std::string>().c_str(), vel,
                 rms.at("slip").at(w).get<double>(), ca, ss);
  }
}

// How its result is shown.
class ContactAnglePresentation : public Presentation {
 public:
  void print(const json& j, std::FILE* out) const override;
  std::vector<KeyMetric> key_metrics() const override {
    return {{"contact_angle_rms_deg", "contact angle RMS (deg, mean of wheels)", "/rms/contact_angle_deg"},
            {"contact_slip_rms", "slip RMS (mean of wheels)", "/rms/slip"}};
  }
  void report(const json& j, ReportSection& section) const override;
};

class ContactAngleAnalysis : public Analysis {
 public:
  ContactAngleAnalysis()
      : Analysis({"contact-angle",
                  "estimate contact-angle",
                  "Contact-angle estimator (seed 000)",
                  "Contact angles, side slip, slip and velocity of a six-wheel DH rover with an EKF or UKF (seed 000)",
                  "Log with imu, joints and wheels streams (truth/ streams for errors)",
                  {estimation::contact_streams::kPrefix},
                  AnalysisChoice{"--model", "Contact-angle &model", {"auto", "smooth", "c", "c+ss"}}},
                 std::make_unique<ContactAnglePresentation>()) {}

  std::string missing(const log::Log& lg) const override {
    for (const char* s : {"imu", "joints", "wheels"}) {
      if (lg.find_stream(s) == nullptr) return std::string("no ") + s + " stream";
    }
    return "";
  }
  bool runs_on_open(const log::Log& lg) const override {
    if (!missing(lg).empty() || lg.find_stream(estimation::contact_streams::kWheels) != nullptr) return false;
    try {
      return rover_description(lg, "").dh.has_value();
    } catch (const InputError&) {
      return false;  // the log names no rover RoverLab knows: nothing to run by itself
    }
  }

  void declare(CLI::App& cmd) override;
  json configuration() const override {
    const auto value = [](const std::optional<double>& v) { return v ? json(*v) : json(nullptr); };
    return {{"rover", rover_ ? json(*rover_) : json(nullptr)},
            {"model", model_},
            {"filter", filter_},
            {"angle_model", angle_model_},
            {"reset_cross_covariance", reset_cross_covariance_},
            {"smoother", smoother_},
            {"smoother_method", smoother_method_},
            {"process_noise", process_noise_},
            {"velocity_variance", value(velocity_variance_)},
            {"attitude_variance", value(attitude_variance_)},
            {"slip_variance", value(slip_variance_)},
            {"angle_variance", value(angle_variance_)},
            {"joint_rate_window_s", joint_rate_window_}};
  }
  // The rover file --rover names or the log's rover id resolves to, whichever named it.
  json resolved_configuration(const log::Log& lg) const override {
    json settings = configuration();
    std::error_code ec;
    const std::string file = rover_description(lg, "the log").file;
    const std::filesystem::path canonical = std::filesystem::weakly_canonical(file, ec);
    settings["rover"] = ec ? file : canonical.string();
    return settings;
  }
  void check_options() const override { (void)options(); }
  AnalysisResult run(const AnalysisInput& in) override;

 private:
  // --rover NAME|FILE, else the log's rover_id (a name only), else the ExoMars BB2.
  io::RoverDescription rover_description(const log::Log& lg, const std::string& file) const {
    const auto folders = resource_subfolders("rovers");
    if (rover_) return io::find_rover(*rover_, folders);
    return io::find_rover_named(lg.metadata.rover_id.empty() ? "exomars_bb2" : lg.metadata.rover_id, folders, file);
  }
  estimation::ContactAngleOptions options() const;
  json document(const std::string& file, const kinematics::RoverModel& rover, const estimation::ContactAngleResult& r,
                double wall) const;
  static json selection_json(const estimation::ModelSelection& s);

  std::optional<std::string> rover_;  // default: the log's rover id, else exomars_bb2
  std::string model_ = "auto", filter_ = "ekf", angle_model_ = "random-walk";
  // The defaults the data support (docs/validation/contact-angle.md): the seed's
  // cross-covariance reset and the two-filter smoother over the fast EKF.
  bool reset_cross_covariance_ = true;
  bool smoother_ = true;
  std::string smoother_method_ = "two-filter";
  bool smoother_method_given_ = false;
  std::string process_noise_ = "seed";  // seed (1e-5 per step, section 6.2) | imu (from the IMU noise alone)
  std::optional<double> velocity_variance_, attitude_variance_, slip_variance_, angle_variance_;
  double joint_rate_window_ = 0.0;
};

void ContactAngleAnalysis::declare(CLI::App& cmd) {
  cmd.add_option("--rover", rover_, "Rover NAME (resources/rovers) or FILE (default: the log's rover)");
  cmd.add_option(
         "--model", model_,
         "auto (smooth, c and c+ss run; the consistent one of least AIC on the innovations) | smooth | c | c+ss")
      ->capture_default_str();
  cmd.add_option("--filter", filter_, "ekf | ukf")->capture_default_str();
  cmd.add_option("--angle-model", angle_model_, "random-walk | damped")->capture_default_str();
  cmd.add_flag("--reset-cross-covariance,!--no-reset-cross-covariance", reset_cross_covariance_,
               "Zero P's off-diagonal elements every step (the seed's workaround; on by default: "
               "--no-reset-cross-covariance for the original filter)");
  cmd.add_flag("--smoother,!--no-smoother", smoother_,
               "Offline smoother over the filter's pass (--smoother-method), errors of both (on by default: "
               "--no-smoother for the forward filter alone)");
  // A method without the smoother would be ignored: it is a usage error (check_options).
  cmd.add_option("--smoother-method", smoother_method_,
                 "two-filter: the filter forward and over the log reversed in time, fused by their variances (any "
                 "filter) | rts: Rauch-Tung-Striebel (the EKF with --reset-cross-covariance only)")
      ->capture_default_str()
      ->each([this](const std::string&) { smoother_method_given_ = true; });
  cmd.add_option(
         "--process-noise", process_noise_,
         "seed: 1e-5 per step on attitude and velocity as seed 000 section 6.2 | imu: only the IMU's noise drives them")
      ->capture_default_str();
  cmd.add_option("--velocity-variance", velocity_variance_, "Velocity process noise per step, m^2/s^2")
      ->check(finite_in(1e-15, 1.0));
  cmd.add_option("--attitude-variance", attitude_variance_, "Attitude process noise per step, rad^2")
      ->check(finite_in(1e-15, 1.0));
  cmd.add_option("--slip-variance", slip_variance_, "Slip process noise per step")->check(finite_in(1e-15, 1.0));
  cmd.add_option("--angle-variance", angle_variance_, "Contact / side-slip angle process noise per step, rad^2")
      ->check(finite_in(1e-15, 1.0));
  cmd.add_option(
         "--joint-rate-window", joint_rate_window_,
         "Fuse joint rates with the slope of the joint angles over this window, s (0: measured rates, as the seed)")
      ->capture_default_str()
      ->check(finite_in(0.0, 10.0));
}

estimation::ContactAngleOptions ContactAngleAnalysis::options() const {
  estimation::ContactAngleOptions o;
  try {
    if (model_ != "auto") o.model = estimation::parse_contact_model(model_);
    o.filter = estimation::parse_filter_kind(filter_);
    o.angle_model = estimation::parse_angle_model(angle_model_);
  } catch (const DataError& e) {
    throw UsageError(e.what());
  }
  o.reset_cross_covariance = reset_cross_covariance_;
  o.smoother = smoother_;
  if (smoother_method_given_ && !smoother_) throw UsageError("--smoother-method: given with --no-smoother");
  try {
    o.smoother_method = estimation::parse_smoother_method(smoother_method_);
  } catch (const DataError& e) {
    throw UsageError(std::string("--smoother-method: ") + e.what());
  }
  if (smoother_ && o.smoother_method == estimation::SmootherMethod::rts &&
      (o.filter != estimation::FilterKind::ekf || !reset_cross_covariance_))
    throw UsageError("--smoother-method rts: runs over the EKF with the cross-covariance reset only");
  if (process_noise_ == "imu") {
    o.attitude_variance = o.velocity_variance = 1e-12;
  } else if (process_noise_ != "seed") {
    throw UsageError("--process-noise " + process_noise_ + ": expected seed or imu");
  }
  o.joint_rate_window = joint_rate_window_;
  if (velocity_variance_) o.velocity_variance = *velocity_variance_;
  if (attitude_variance_) o.attitude_variance = *attitude_variance_;
  if (slip_variance_) o.slip_variance = *slip_variance_;
  if (angle_variance_) o.angle_variance = *angle_variance_;
  return o;
}

AnalysisResult ContactAngleAnalysis::run(const AnalysisInput& in) {
  estimation::ContactAngleOptions o = options();
  const kinematics::RoverModel rover = dh_rover(rover_description(in.log, in.file));
  o.progress = in.progress;
  const auto start = std::chrono::steady_clock::now();
  std::optional<estimation::ModelSelection> selection;
  if (model_ == "auto") selection = estimation::select_contact_model(in.log, rover, o);
  estimation::ContactAngleResult r =
      selection ? std::move(selection->result) : estimation::run_contact_angle(in.log, rover, o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  AnalysisResult out;
  out.document = document(in.file, rover, r, wall);
  if (selection) {
    out.document["model"] = estimation::to_string(selection->chosen);
    out.document["model_selection"] = selection_json(*selection);
    estimation::label_model(
        r.estimates,
        std::string("model ") + estimation::to_string(selection->chosen) +
            (selection->supported ? ", chosen by the data" : ", chosen by the data but not consistent with them"));
  } else {
    const estimation::ModelEvidence e = estimation::model_evidence(o.model, r);
    out.document["model_evidence"] = candidate_json(e);
    char rejected[96];
    std::snprintf(rejected, sizeof rejected, "; the data reject it (mean NIS %.1f per dof)", e.mean_nis);
    estimation::label_model(r.estimates, "model " + model_ + ", set by hand" + (e.consistent ? "" : rejected));
  }
  out.estimates = std::move(r.estimates);
  return out;
}

json candidate_json(const estimation::ModelEvidence& e) {
  const auto band = estimation::mean_nis_band(std::max(e.innovations.dof, 1.0));
  return {{"model", estimation::to_string(e.model)},
          {"states", e.states},
          {"updates", e.innovations.updates},
          {"mean_nis", finite_or_null(e.mean_nis)},
          {"mean_nis_band_95", {band.first, band.second}},
          {"nis_windows_above_band", e.nis_out_of_band},
          {"log_likelihood", finite_or_null(e.innovations.log_likelihood)},
          {"effective_dof", e.innovations.effective_dof},
          {"aic", finite_or_null(e.aic)},
          {"diverged", e.diverged},
          {"consistent", e.consistent}};
}

json ContactAngleAnalysis::selection_json(const estimation::ModelSelection& s) {
  json candidates = json::array();
  for (const auto& e : s.candidates) candidates.push_back(candidate_json(e));
  return {{"requested", "auto"},
          {"chosen", estimation::to_string(s.chosen)},
          {"supported", s.supported},
          {"reason", s.reason},
          {"candidates", candidates}};
}

json ContactAngleAnalysis::document(const std::string& file, const kinematics::RoverModel& rover,
                                    const estimation::ContactAngleResult& r, double wall) const {
  std::vector<std::string> names;
  for (const auto& w : rover.wheels) names.push_back(w.name);
  json j = {{"file", file},
            {"rover", rover.name},
            {"model", model_},
            {"filter", filter_},
            {"angle_model", angle_model_},
            {"reset_cross_covariance", reset_cross_covariance_},
            {"process_noise", process_noise_},
            {"seconds", r.seconds},
            {"wall_seconds", wall},
            {"standstill_samples", r.standstill_samples},
            {"max_cross_correlation", r.max_cross_correlation},
            {"wheels", names},
            {"has_truth", r.has_truth},
            {"warnings", r.warnings},
            {"health", health_json(r.health)}};
  j["smoother"] = r.smoothed;
  if (r.smoothed) j["smoother_method"] = smoother_method_;
  if (r.has_truth) {
    j["rms"] = rms_json(r.rms);  // of the smoothed states with the smoother
    if (r.smoothed) j["filter_rms"] = rms_json(r.filter_rms);
  }
  return j;
}

void ContactAnglePresentation::print(const json& j, std::FILE* out) const {
  const auto str = [&](const char* key) { return j.at(key).get<std::string>(); };
  std::fprintf(out, "%s: rover %s, model %s, %s, %s angles%s; %.1f s of log in %.2f s\n", str("file").c_str(),
               str("rover").c_str(), str("model").c_str(), str("filter").c_str(), str("angle_model").c_str(),
               j.at("reset_cross_covariance").get<bool>() ? ", cross-covariances reset" : "",
               j.at("seconds").get<double>(), j.at("wall_seconds").get<double>());
  for (const auto& w : j.value("warnings", json::array()))
    std::fprintf(out, "warning: %s\n", w.get<std::string>().c_str());
  if (j.contains("model_selection")) print_selection(j.at("model_selection"), out);
  if (j.contains("model_evidence") && !j.at("model_evidence").at("consistent").get<bool>()) {
    const json& e = j.at("model_evidence");
    std::fprintf(out, "warning: the data reject model %s: mean NIS %.2f per dof, %.0f %% of NIS windows above band%s\n",
                 str("model").c_str(), e.at("mean_nis").is_number() ? e.at("mean_nis").get<double>() : NAN,
                 100.0 * e.at("nis_windows_above_band").get<double>(),
                 e.at("diverged").get<bool>() ? ", diverged" : "");
  }
  if (j.value("smoother", false) && !j.value("reset_cross_covariance", false)) {
    std::fprintf(out,
                 "warning: smoothed without --reset-cross-covariance: the filter's variances do not describe its "
                 "errors, and the smoothed angles can be worse than the filter's (docs/validation/contact-angle.md)\n");
  }
  const auto standstill = j.at("standstill_samples").get<std::size_t>();
  if (standstill > 0) std::fprintf(out, "standstill: %zu samples held and left out\n", standstill);
  print_health(j, out);
  if (j.at("has_truth").get<bool>()) {
    const bool smoothed = j.value("smoother", false);
    const std::string method = j.value("smoother_method", "two-filter") == "rts" ? "RTS" : "two-filter";
    print_rms(j.at("rms"), j.at("wheels"), smoothed ? (method + " smoother").c_str() : "filter", out);
    if (smoothed) {
      const std::string filter = "forward filter (" + j.value("filter", std::string("ekf")) + ")";
      print_rms(j.at("filter_rms"), j.at("wheels"), filter.c_str(), out);
    }
  } else {
    std::fprintf(out, "no truth streams: no errors\n");
  }
  std::fprintf(out, "largest cross-correlation in P at the end: %.3f\n", j.at("max_cross_correlation").get<double>());
}

void ContactAnglePresentation::report(const json& j, ReportSection& s) const {
  std::string model = j.at("model").get<std::string>();
  for (char& c : model) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::string filter = j.at("filter").get<std::string>();
  for (char& c : filter) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  s.html << "<h2>Contact-angle estimator (seed 000, model " << model << ", " << filter << ")</h2>\n";
  if (j.contains("model_selection")) {
    const json& sel = j.at("model_selection");
    s.html << "<p>" << (sel.at("supported").get<bool>() ? "" : "<b>Warning:</b> ")
           << ReportSection::escape(sel.at("reason").get<std::string>())
           << ".</p>\n<table><tr><th>model</th><th>states</th><th>mean NIS</th><th>NIS windows above band</th>"
              "<th>AIC</th><th>verdict</th></tr>\n";
    for (const json& c : sel.at("candidates")) {
      s.html << "<tr><td>" << c.at("model").get<std::string>() << "</td><td>" << c.at("states").get<int>()
             << "</td><td>" << ReportSection::number(c.at("mean_nis"), "%.3f") << "</td><td>"
             << ReportSection::number(100.0 * c.at("nis_windows_above_band").get<double>(), "%.0f") << " %</td><td>"
             << ReportSection::number(c.at("aic"), "%.1f") << "</td><td>"
             << (c.at("diverged").get<bool>()     ? "diverged"
                 : c.at("consistent").get<bool>() ? "consistent"
                                                  : "rejected")
             << "</td></tr>\n";
    }
    s.html << "</table>\n";
  }
  if (!j.at("has_truth").get<bool>()) {
    report_health(j, s);
    return;
  }
  const json& rms = j.at("rms");
  const json* filter_rms = j.value("smoother", false) ? &j.at("filter_rms") : nullptr;
  const json none;
  // A cell: the smoother's figure and the forward filter's, or the filter's alone.
  const auto cell = [&](const char* key, std::size_t k, const char* format) {
    const auto at = [&](const json& r) { return r.contains(key) ? r.at(key).at(k) : none; };
    std::string text = ReportSection::number(at(rms), format);
    if (filter_rms != nullptr) text += " / " + ReportSection::number(at(*filter_rms), format);
    return text;
  };
  const char* of = filter_rms != nullptr ? " (smoother / filter)" : "";
  s.html << "<table><tr><th>wheel</th><th>slip RMS" << of << "</th><th>contact angle RMS (deg)" << of
         << "</th><th>side slip RMS (deg)" << of << "</th></tr>\n";
  for (std::size_t k = 0; k < rms.at("slip").size(); ++k) {
    s.html << "<tr><td>" << ReportSection::escape(j.at("wheels").at(k).get<std::string>()) << "</td><td>"
           << cell("slip", k, "%.4f") << "</td><td>" << cell("contact_angle_deg", k, "%.3f") << "</td><td>"
           << cell("side_slip_deg", k, "%.3f") << "</td></tr>\n";
  }
  s.html << "</table>\n<p>Velocity RMS x / y / z" << of << ": " << cell("velocity_mps", 0, "%.4f") << ", "
         << cell("velocity_mps", 1, "%.4f") << ", " << cell("velocity_mps", 2, "%.4f") << " m/s over "
         << rms.at("samples").get<std::size_t>() << " moving samples.</p>\n";
  report_health(j, s);
}

}  // namespace

std::unique_ptr<Analysis> make_contact_angle_analysis() { return std::make_unique<ContactAngleAnalysis>(); }

}  // namespace roverlab::app

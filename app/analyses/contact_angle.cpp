// `estimate contact-angle`: contact angles, side slip, slip and velocity of a
// six-wheel DH rover with an EKF or UKF (seed 000), RMS errors in the layout of
// Tables 6.2-6.5 when the log has truth.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <optional>

#include "app/analyses/health.h"
#include "app/analysis.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/estimation/contact_angle.h"
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

class ContactAngleAnalysis : public Analysis {
 public:
  std::string name() const override { return "contact-angle"; }
  std::string command() const override { return "estimate contact-angle"; }
  std::string title() const override { return "Contact-angle estimator (seed 000)"; }
  std::string help() const override {
    return "Contact angles, side slip, slip and velocity of a six-wheel DH rover with an EKF or UKF (seed 000)";
  }
  std::string log_help() const override {
    return "Log with imu, joints and wheels streams (truth/ streams for errors)";
  }

  std::string missing(const log::Log& lg) const override {
    for (const char* s : {"imu", "joints", "wheels"}) {
      if (lg.find_stream(s) == nullptr) return std::string("no ") + s + " stream";
    }
    return "";
  }
  bool runs_on_open(const log::Log& lg) const override {
    if (!missing(lg).empty() || lg.find_stream("estimate/contact/wheels") != nullptr) return false;
    try {
      return rover_description(lg, "").dh.has_value();
    } catch (const InputError&) {
      return false;  // the log names no rover RoverLab knows: nothing to run by itself
    }
  }

  void declare(CLI::App& cmd) override;
  // The views show model C+SS with the seed's cross-covariance reset.
  void use_view_defaults() override {
    model_ = "c+ss";
    reset_cross_covariance_ = true;
  }
  void check_options() const override { (void)options(); }
  AnalysisResult run(const AnalysisInput& in) override;
  void print(const json& j, std::FILE* out) const override;
  std::vector<KeyMetric> key_metrics() const override {
    return {{"contact_angle_rms_deg", "contact angle RMS (deg, mean of wheels)", "/rms/contact_angle_deg"},
            {"contact_slip_rms", "slip RMS (mean of wheels)", "/rms/slip"}};
  }
  void report(const json& j, ReportSection& section) const override;

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

  std::optional<std::string> rover_;  // default: the log's rover id, else exomars_bb2
  std::string model_ = "c", filter_ = "ekf", angle_model_ = "random-walk";
  bool reset_cross_covariance_ = false;
  std::string process_noise_ = "seed";  // seed (1e-5 per step, section 6.2) | imu (from the IMU noise alone)
  std::optional<double> velocity_variance_, attitude_variance_, slip_variance_, angle_variance_;
  double joint_rate_window_ = 0.0;
};

void ContactAngleAnalysis::declare(CLI::App& cmd) {
  cmd.add_option("--rover", rover_, "Rover NAME (resources/rovers) or FILE (default: the log's rover)");
  cmd.add_option("--model", model_, "smooth | c | c+ss")->capture_default_str();
  cmd.add_option("--filter", filter_, "ekf | ukf")->capture_default_str();
  cmd.add_option("--angle-model", angle_model_, "random-walk | damped")->capture_default_str();
  cmd.add_flag("--reset-cross-covariance", reset_cross_covariance_,
               "Zero P's off-diagonal elements every step (the seed's workaround)");
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
    o.model = estimation::parse_contact_model(model_);
    o.filter = estimation::parse_filter_kind(filter_);
    o.angle_model = estimation::parse_angle_model(angle_model_);
  } catch (const DataError& e) {
    throw UsageError(e.what());
  }
  o.reset_cross_covariance = reset_cross_covariance_;
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
  estimation::ContactAngleResult r = estimation::run_contact_angle(in.log, rover, o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  AnalysisResult out;
  out.document = document(in.file, rover, r, wall);
  out.estimates = std::move(r.estimates);
  return out;
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
            {"health", health_json(r.health)}};
  if (r.has_truth) {
    json rms = {{"velocity_mps", r.rms.velocity}, {"slip", r.rms.slip}, {"samples", r.rms.samples}};
    if (!r.rms.contact_angle.empty()) rms["contact_angle_deg"] = degrees(r.rms.contact_angle);
    if (!r.rms.side_slip.empty()) rms["side_slip_deg"] = degrees(r.rms.side_slip);
    j["rms"] = rms;
  }
  return j;
}

void ContactAngleAnalysis::print(const json& j, std::FILE* out) const {
  const auto str = [&](const char* key) { return j.at(key).get<std::string>(); };
  std::fprintf(out, "%s: rover %s, model %s, %s, %s angles%s; %.1f s of log in %.2f s\n", str("file").c_str(),
               str("rover").c_str(), str("model").c_str(), str("filter").c_str(), str("angle_model").c_str(),
               j.at("reset_cross_covariance").get<bool>() ? ", cross-covariances reset" : "",
               j.at("seconds").get<double>(), j.at("wall_seconds").get<double>());
  const auto standstill = j.at("standstill_samples").get<std::size_t>();
  if (standstill > 0) std::fprintf(out, "standstill: %zu samples held and left out\n", standstill);
  print_health(j, out);
  if (j.at("has_truth").get<bool>()) {
    const json& rms = j.at("rms");
    std::fprintf(out, "\nRMS errors over %zu moving samples (layout of seed 000 Tables 6.2-6.5):\n",
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
      std::fprintf(out, "  %-6s %14s %12.4f %16s %16s\n", j.at("wheels").at(w).get<std::string>().c_str(), vel,
                   rms.at("slip").at(w).get<double>(), ca, ss);
    }
  } else {
    std::fprintf(out, "no truth streams: no errors\n");
  }
  std::fprintf(out, "largest cross-correlation in P at the end: %.3f\n", j.at("max_cross_correlation").get<double>());
}

void ContactAngleAnalysis::report(const json& j, ReportSection& s) const {
  if (!j.at("has_truth").get<bool>()) {
    report_health(j, s);
    return;
  }
  const json& rms = j.at("rms");
  std::string model = j.at("model").get<std::string>();
  for (char& c : model) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::string filter = j.at("filter").get<std::string>();
  for (char& c : filter) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  s.html << "<h2>Contact-angle estimator (seed 000, model " << model << ", " << filter
         << ")</h2>\n<table><tr><th>wheel</th><th>slip RMS</th>"
            "<th>contact angle RMS (deg)</th><th>side slip RMS (deg)</th></tr>\n";
  const json none;
  for (std::size_t k = 0; k < rms.at("slip").size(); ++k) {
    s.html << "<tr><td>" << ReportSection::escape(j.at("wheels").at(k).get<std::string>()) << "</td><td>"
           << ReportSection::number(rms.at("slip").at(k), "%.4f") << "</td><td>"
           << ReportSection::number(rms.contains("contact_angle_deg") ? rms.at("contact_angle_deg").at(k) : none,
                                    "%.3f")
           << "</td><td>"
           << ReportSection::number(rms.contains("side_slip_deg") ? rms.at("side_slip_deg").at(k) : none, "%.3f")
           << "</td></tr>\n";
  }
  const json& v = rms.at("velocity_mps");
  s.html << "</table>\n<p>Velocity RMS x / y / z: " << ReportSection::number(v.at(0), "%.4f") << " / "
         << ReportSection::number(v.at(1), "%.4f") << " / " << ReportSection::number(v.at(2), "%.4f") << " m/s over "
         << rms.at("samples").get<std::size_t>() << " moving samples.</p>\n";
  report_health(j, s);
}

}  // namespace

std::unique_ptr<Analysis> make_contact_angle_analysis() { return std::make_unique<ContactAngleAnalysis>(); }

}  // namespace roverlab::app

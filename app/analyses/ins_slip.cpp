// `estimate ins-slip`: the error-state INS with ZUPT/ZARU/NHC pseudo-measurements
// and slip detection of seed 002, with its metrics against GPS or truth.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <optional>

#include "app/analyses/health.h"
#include "app/analysis.h"
#include "app/command_support.h"
#include "core/estimation/ins_slip/ins_slip.h"
#include "core/estimation/ins_slip/streams.h"

namespace roverlab::app {

namespace {

using estimation::ConfusionMatrix;
using estimation::kSlipClasses;
using estimation::SlipClass;
using nlohmann::json;

const char* class_name(int k) { return estimation::to_string(static_cast<SlipClass>(k)); }

json heading_json(const estimation::InitialHeading& h) {
  using Method = estimation::InitialHeading::Method;
  const char* method = h.method == Method::given ? "given" : h.method == Method::aligned ? "aligned" : "assumed_north";
  return {{"method", method},
          {"heading_rad", h.heading},
          {"sigma_rad", finite_or_null(h.sigma)},
          {"east_m", h.east},
          {"north_m", h.north},
          {"stretch_m", h.stretch},
          {"fixes", h.fixes},
          {"residual_rms_m", finite_or_null(h.residual_rms)},
          {"text", estimation::describe(h)}};
}

json confusion_json(const ConfusionMatrix& c) {
  json j = {{"rows", "estimated"},
            {"columns", "reference"},
            {"classes", json::array()},
            {"counts", json::array()},
            {"column_normalised", json::array()}};
  for (int k = 0; k < kSlipClasses; ++k) j["classes"].push_back(class_name(k));
  for (int e = 0; e < kSlipClasses; ++e) {
    json counts = json::array(), fractions = json::array();
    for (int t = 0; t < kSlipClasses; ++t) {
      counts.push_back(c.counts[static_cast<std::size_t>(e)][static_cast<std::size_t>(t)]);
      fractions.push_back(finite_or_null(c.fraction(e, t)));
    }
    j["counts"].push_back(counts);
    j["column_normalised"].push_back(fractions);
  }
  j["accuracy"] = finite_or_null(c.accuracy());
  j["total"] = c.total();
  return j;
}

// The confusion as a table: rows estimated, columns reference, each cell the
// column-normalised fraction, tinted by it.
ResultTable confusion_table(const json& c, const std::string& title) {
  ResultTable t;
  t.title = title + " (rows: estimated, columns: reference; % of each reference class)";
  for (const json& k : c.at("classes")) {
    t.columns.push_back(k.get<std::string>());
    t.row_names.push_back(k.get<std::string>());
  }
  for (const json& row : c.at("column_normalised")) {
    std::vector<ResultTable::Cell> cells;
    for (const json& f : row) {
      char text[32] = "-";
      if (f.is_number()) std::snprintf(text, sizeof text, "%.1f %%", 100.0 * f.get<double>());
      cells.push_back({text, f.is_number() ? f.get<double>() : 0.0, false});
    }
    t.rows.push_back(std::move(cells));
  }
  t.legend =
      "Each cell: the share of the column's reference samples classed as the row; the tint follows it; the diagonal is "
      "each class's recall. No bold (bold marks a named cause).";
  return t;
}

// Each reference class's recall (the diagonal of the column-normalised
// confusion) with its sample count; classes without samples left out.
struct ClassRecall {
  std::string name;
  double recall = 0;
  long samples = 0;
};
std::vector<ClassRecall> class_recalls(const json& c) {
  std::vector<ClassRecall> out;
  for (int t = 0; t < kSlipClasses; ++t) {
    long column = 0;
    for (int e = 0; e < kSlipClasses; ++e) column += c.at("counts").at(e).at(t).get<long>();
    const json& f = c.at("column_normalised").at(t).at(t);
    if (column > 0 && f.is_number()) out.push_back({class_name(t), f.get<double>(), column});
  }
  return out;
}

// "accuracy 76.5 % of 695 samples; weakest class high: recall 0.0 % of 1 sample"
std::string accuracy_text(const json& c) {
  char text[160];
  std::snprintf(text, sizeof text, "accuracy %.1f %% of %ld samples", 100.0 * c.at("accuracy").get<double>(),
                c.at("total").get<long>());
  std::string out = text;
  const std::vector<ClassRecall> recalls = class_recalls(c);
  const auto worst = std::min_element(recalls.begin(), recalls.end(),
                                      [](const ClassRecall& a, const ClassRecall& b) { return a.recall < b.recall; });
  if (worst == recalls.end()) return out;
  std::snprintf(text, sizeof text, "; weakest class %s: recall %.1f %% of %ld sample%s", worst->name.c_str(),
                100.0 * worst->recall, worst->samples, worst->samples == 1 ? "" : "s");
  return out + text;
}

// "recall per reference class: none 100.0 %, low 70.7 %, ..."
std::string recalls_text(const json& c) {
  std::string out = "recall per reference class:";
  char text[96];
  for (const ClassRecall& r : class_recalls(c)) {
    std::snprintf(text, sizeof text, " %s %.1f %% (%ld),", r.name.c_str(), 100.0 * r.recall, r.samples);
    out += text;
  }
  if (out.back() == ',') out.pop_back();
  return out;
}

void print_confusion(const json& c, std::FILE* out) {
  std::fprintf(out, "slip classes, column-normalised (%% of each reference class; rows: estimated):\n");
  std::fprintf(out, "  %-10s", "");
  for (int t = 0; t < kSlipClasses; ++t) std::fprintf(out, " %8s", class_name(t));
  std::fprintf(out, "\n");
  for (int e = 0; e < kSlipClasses; ++e) {
    std::fprintf(out, "  %-10s", class_name(e));
    for (int t = 0; t < kSlipClasses; ++t) {
      const json& f = c.at("column_normalised").at(e).at(t);
      if (f.is_number()) {
        std::fprintf(out, " %7.1f%%", 100.0 * f.get<double>());
      } else {
        std::fprintf(out, " %8s", "-");
      }
    }
    std::fprintf(out, "\n");
  }
  std::fprintf(out, "  %-10s", "# samples");
  for (int t = 0; t < kSlipClasses; ++t) {
    long column = 0;
    for (int e = 0; e < kSlipClasses; ++e) column += c.at("counts").at(e).at(t).get<long>();
    std::fprintf(out, " %8ld", column);
  }
  std::fprintf(out, "\n  overall %s\n  %s\n", accuracy_text(c).c_str(), recalls_text(c).c_str());
}

constexpr char kInsSlipTitle[] = "INS slip detection (seed 002)";

// How its result is shown.
class InsSlipPresentation : public Presentation {
 public:
  void print(const json& j, std::FILE* out) const override;
  std::vector<KeyMetric> key_metrics() const override {
    return {{"ins_final_error_m", "INS final horizontal error (m)", "/ins/final_position_error_m"},
            {"ins_position_rmse_m", "INS horizontal position RMSE (m)", "/ins/position_rmse_m"},
            {"wheel_odometry_final_error_m", "wheel odometry final horizontal error (m)",
             "/wheel_odometry/final_position_error_m"},
            {"slip_class_accuracy", "slip class accuracy", "/slip_confusion/accuracy"}};
  }
  void report(const json& j, ReportSection& section) const override;
  std::vector<ResultTable> tables(const json& j) const override;
  std::string summary(const json& j) const override;
};

class InsSlipAnalysis : public Analysis {
 public:
  InsSlipAnalysis()
      : Analysis({"ins-slip",
                  "estimate ins-slip",
                  kInsSlipTitle,
                  "Error-state INS with ZUPT/ZARU/NHC pseudo-measurements and slip detection (seed 002)",
                  "Log with imu and wheels streams (gps or truth/slip for metrics)",
                  {estimation::ins_streams::kPrefix, estimation::ins_streams::kOdometryPrefix},
                  std::nullopt},
                 std::make_unique<InsSlipPresentation>()) {}

  std::string missing(const log::Log& lg) const override {
    if (lg.find_stream("imu") == nullptr) return "no imu stream";
    const log::Stream* wheels = lg.find_stream("wheels");
    // A skid-steer log: wheel angles of four wheels.
    if (wheels == nullptr || wheels->find_channel("angle_FL") == nullptr ||
        wheels->find_channel("angle_RR") == nullptr) {
      return "no skid-steer wheels stream (angle_FL .. angle_RR)";
    }
    return "";
  }
  bool runs_on_open(const log::Log& lg) const override {
    return missing(lg).empty() && lg.find_stream(estimation::ins_streams::kPose) == nullptr;
  }

  void declare(CLI::App& cmd) override {
    cmd.add_flag("--no-zupt", no_zupt_, "No zero-velocity updates");
    cmd.add_flag("--no-zaru", no_zaru_, "No zero-angular-rate updates");
    cmd.add_flag("--no-nhc", no_nhc_, "No non-holonomic constraints");
    cmd.add_flag("--no-odometry-aiding", no_odometry_aiding_,
                 "No wheel forward-speed update in the localisation filter (pseudo-measurements only)");
    cmd.add_flag("--no-smoother", no_smoother_,
                 "Forward filter only, as on board (default: RTS smoothing over the whole log)");
    cmd.add_option("--initial-heading", initial_heading_deg_,
                   "Initial heading, deg clockwise from north (default: aligned to the GPS track's first stretch)")
        ->check(finite_in(-360.0, 360.0));
    cmd.add_option("--no-slip-band", no_slip_,
                   "|s| up to which a sample is in the 'none' slip class (default: 0 against GPS, i.e. "
                   "standstill only as in seed 002 Table 2; 0.02 against slip truth)")
        ->check(finite_in(0.0, 0.2));
    cmd.add_option("--imu-mounting", imu_mounting_deg_,
                   "IMU roll,pitch,yaw against the chassis, deg: the NHC and wheel speed hold in chassis axes "
                   "(default 0,0,0)")
        ->expected(3)
        ->delimiter(',')
        ->check(finite_in(-30.0, 30.0));
    cmd.add_option("--odometry-sigma", odometry_sigma_, "Standard deviation of the wheel-speed update, m/s")
        ->capture_default_str()
        ->check(finite_in(1e-4, 10.0));
  }

  json configuration() const override {
    return {{"zupt", !no_zupt_},
            {"zaru", !no_zaru_},
            {"nhc", !no_nhc_},
            {"odometry_aiding", !no_odometry_aiding_},
            {"smoother", !no_smoother_},
            {"initial_heading_deg", initial_heading_deg_ ? json(*initial_heading_deg_) : json(nullptr)},
            {"no_slip_band", no_slip_ ? json(*no_slip_) : json(nullptr)},
            {"imu_mounting_deg", imu_mounting_deg_.empty() ? json({0.0, 0.0, 0.0}) : json(imu_mounting_deg_)},
            {"odometry_sigma_mps", odometry_sigma_}};
  }
  AnalysisResult run(const AnalysisInput& in) override {
    estimation::InsSlipOptions o;
    o.zupt = !no_zupt_;
    o.zaru = !no_zaru_;
    o.nhc = !no_nhc_;
    o.odometry_aiding = !no_odometry_aiding_;
    o.odometry_sigma = odometry_sigma_;
    o.smooth = !no_smoother_;
    if (initial_heading_deg_) o.initial_heading = *initial_heading_deg_ * M_PI / 180.0;
    o.no_slip = no_slip_;
    if (imu_mounting_deg_.size() == 3)
      o.imu_mounting = Eigen::Vector3d(imu_mounting_deg_[0], imu_mounting_deg_[1], imu_mounting_deg_[2]) * M_PI / 180.0;
    o.progress = in.progress;
    estimation::InsSlipResult r = estimation::run_ins_slip(in.log, o);
    AnalysisResult out;
    out.document = document(in.file, o, r);
    out.estimates = std::move(r.estimates);
    return out;
  }

 private:
  static json document(const std::string& file, const estimation::InsSlipOptions& o,
                       const estimation::InsSlipResult& r) {
    const estimation::InsSlipMetrics& m = r.metrics;
    const double deg = 180.0 / M_PI;
    const json mounting = {o.imu_mounting.x() * deg, o.imu_mounting.y() * deg, o.imu_mounting.z() * deg};
    json j = {{"file", file},
              {"updates",
               {{"zupt", o.zupt},
                {"zaru", o.zaru},
                {"nhc", o.nhc},
                {"odometry_aiding", o.odometry_aiding},
                {"smoother", o.smooth},
                {"imu_mounting_deg", mounting}}},
              {"duration_s", m.duration},
              {"standstill_fraction", m.standstill_fraction},
              {"has_reference", m.has_reference},
              {"health", health_json(r.health)},
              {"initial_heading", heading_json(r.heading)}};
    if (m.has_reference) {
      j["distance_m"] = m.distance;
      j["gps_reference"] = {{"fix_sigma_m", finite_or_null(r.gps_fix_sigma)},
                            {"accel_psd", finite_or_null(r.gps_accel_psd)},
                            {"outliers_rejected", r.gps_outliers}};
      j["ins"] = {
          {"final_position_error_m", m.final_position_error},
          {"final_position_error_3d_m", m.final_position_error_3d},
          {"position_rmse_m", m.position_rmse},
          {"position_rmse_enu_m", {m.position_rmse_axes.east, m.position_rmse_axes.north, m.position_rmse_axes.up}},
          {"velocity_rmse_mps", m.velocity_rmse},
          {"heading_drift_rad", finite_or_null(m.heading_drift)},
          {"aligned_position_rmse_m", finite_or_null(m.aligned_position_rmse)},
          {"aligned_final_position_error_m", finite_or_null(m.aligned_final_position_error)},
          {"alignment_rotation_rad", finite_or_null(m.alignment_rotation)}};
      j["wheel_odometry"] = {{"final_position_error_m", r.odometry.final_position_error},
                             {"position_rmse_m", r.odometry.position_rmse},
                             {"aligned_position_rmse_m", finite_or_null(r.odometry.aligned_position_rmse)}};
    }
    const estimation::ImuVibration& v = r.vibration;
    j["imu_vibration"] = {{"forward_vibration_mps2", finite_or_null(v.forward_vibration)},
                          {"vertical_vibration_mps2", finite_or_null(v.vertical_vibration)},
                          {"vertical_walk_mps_per_sqrt_s", finite_or_null(v.vertical_walk)},
                          {"forward_walk_mps_per_sqrt_s", finite_or_null(v.forward_walk)},
                          {"modelled_walk_mps_per_sqrt_s", finite_or_null(v.modelled_walk)},
                          {"longest_drive_s", v.longest_drive},
                          {"detector_speed_error_mps", finite_or_null(v.speed_error)},
                          {"median_speed_mps", finite_or_null(v.median_speed)},
                          {"slip_resolution", finite_or_null(v.slip_resolution)}};
    j["no_slip_band"] = finite_or_null(r.no_slip);
    if (m.confusion.total() > 0) j["slip_confusion"] = confusion_json(m.confusion);
    if (m.confusion_moving.total() > 0) j["slip_confusion_moving"] = confusion_json(m.confusion_moving);
    return j;
  }

  bool no_zupt_ = false, no_zaru_ = false, no_nhc_ = false;
  bool no_odometry_aiding_ = false;  // no wheel forward-speed update in the localisation filter
  bool no_smoother_ = false;         // forward filter only (what the rover had on board)
  double odometry_sigma_ = 0.05;     // m/s
  std::optional<double> initial_heading_deg_;
  std::optional<double> no_slip_;
  std::vector<double> imu_mounting_deg_;  // roll, pitch, yaw of the IMU against the chassis
};

const char* on_off(const json& b) { return b.get<bool>() ? "on" : "off"; }

// The headline: the position errors named by their frame (horizontal, with
// the vertical RMSE beside), the slip classes' accuracy with the weakest class.
std::string InsSlipPresentation::summary(const json& j) const {
  std::string out;
  char text[256];
  if (j.at("has_reference").get<bool>()) {
    const json& ins = j.at("ins");
    std::snprintf(text, sizeof text,
                  "INS position RMSE %.2f m horizontal (%.2f m vertical), final horizontal error %.2f m; wheel "
                  "odometry final horizontal error %.2f m",
                  ins.at("position_rmse_m").get<double>(), ins.at("position_rmse_enu_m").at(2).get<double>(),
                  ins.at("final_position_error_m").get<double>(),
                  j.at("wheel_odometry").at("final_position_error_m").get<double>());
    out = text;
  }
  if (j.contains("slip_confusion"))
    out += (out.empty() ? "slip classes: " : "; slip classes: ") + accuracy_text(j.at("slip_confusion"));
  return out.empty() ? out : out + ".";
}

std::vector<ResultTable> InsSlipPresentation::tables(const json& j) const {
  std::vector<ResultTable> out;
  if (j.contains("slip_confusion")) out.push_back(confusion_table(j.at("slip_confusion"), "Slip classes"));
  if (j.contains("slip_confusion_moving"))
    out.push_back(confusion_table(j.at("slip_confusion_moving"), "Slip classes while driving"));
  return out;
}

// What the IMU's vibration leaves the slip detector (estimation::ImuVibration).
void print_vibration(const json& j, std::FILE* out) {
  if (!j.contains("imu_vibration")) return;
  const json& v = j.at("imu_vibration");
  if (!v.at("detector_speed_error_mps").is_number()) return;
  std::fprintf(out,
               "IMU vibration while moving: %.2f / %.2f m/s^2 RMS forward / vertical; the vertical channel wanders "
               "%.3f m/s/sqrt(s) (the filter models %.4f), forward about %.3f: over the longest drive between stops "
               "(%.0f s) the slip detector's speed is known to about %.2f m/s RMS",
               v.at("forward_vibration_mps2").get<double>(), v.at("vertical_vibration_mps2").get<double>(),
               v.at("vertical_walk_mps_per_sqrt_s").get<double>(), v.at("modelled_walk_mps_per_sqrt_s").get<double>(),
               v.at("forward_walk_mps_per_sqrt_s").get<double>(), v.at("longest_drive_s").get<double>(),
               v.at("detector_speed_error_mps").get<double>());
  if (v.contains("slip_resolution") && v.at("slip_resolution").is_number()) {
    std::fprintf(out, ", at the median speed of %.2f m/s a slip of about %.2f", v.at("median_speed_mps").get<double>(),
                 v.at("slip_resolution").get<double>());
  }
  std::fprintf(out, "\n");
}

void InsSlipPresentation::print(const json& j, std::FILE* out) const {
  const json& u = j.at("updates");
  const bool aiding = u.at("odometry_aiding").get<bool>();
  std::fprintf(out, "%s: %.1f s of IMU data, standstill %.0f %% of it\n", j.at("file").get<std::string>().c_str(),
               j.at("duration_s").get<double>(), 100.0 * j.at("standstill_fraction").get<double>());
  std::fprintf(out, "updates: ZUPT %s, ZARU %s, NHC %s, wheel-speed aiding %s; %s\n", on_off(u.at("zupt")),
               on_off(u.at("zaru")), on_off(u.at("nhc")),
               aiding ? "on (slip judged by a second pass without it)" : "off",
               u.at("smoother").get<bool>() ? "RTS-smoothed" : "forward filter only");
  if (u.contains("imu_mounting_deg")) {
    const json& m = u.at("imu_mounting_deg");
    if (m.at(0).get<double>() != 0.0 || m.at(1).get<double>() != 0.0 || m.at(2).get<double>() != 0.0) {
      std::fprintf(out,
                   "IMU mounting against the chassis: roll %.2f, pitch %.2f, yaw %.2f deg (NHC and wheel speed "
                   "in chassis axes)\n",
                   m.at(0).get<double>(), m.at(1).get<double>(), m.at(2).get<double>());
    }
  }
  print_health(j, out);
  std::fprintf(out, "%s\n", j.at("initial_heading").at("text").get<std::string>().c_str());
  print_vibration(j, out);
  if (j.at("has_reference").get<bool>()) {
    const json& ins = j.at("ins");
    const json& enu = ins.at("position_rmse_enu_m");
    const json& g = j.at("gps_reference");
    std::fprintf(
        out,
        "GPS reference: fix noise %.3f m per axis (from its second differences), RTS-smoothed constant-velocity "
        "model with process noise %.3g m^2/s^3 (most likely), %zu fixes rejected by the 99.9 %% gate\n",
        g.at("fix_sigma_m").is_number() ? g.at("fix_sigma_m").get<double>() : NAN,
        g.at("accel_psd").is_number() ? g.at("accel_psd").get<double>() : NAN,
        g.at("outliers_rejected").get<std::size_t>());
    std::fprintf(out, "\nposition against GPS over %.1f m of track:\n", j.at("distance_m").get<double>());
    std::fprintf(out, "  %-28s %10s %10s   %s\n", "", "final (m)", "RMSE (m)", "RMSE east / north / up (m)");
    std::fprintf(out, "  %-28s %10s %10s\n", "", "horizontal", "horizontal");
    std::fprintf(out, "  %-28s %10.2f %10.2f   %.2f / %.2f / %.2f\n",
                 aiding ? "INS + pseudo-meas. + wheels" : "INS + pseudo-measurements",
                 ins.at("final_position_error_m").get<double>(), ins.at("position_rmse_m").get<double>(),
                 enu.at(0).get<double>(), enu.at(1).get<double>(), enu.at(2).get<double>());
    std::fprintf(out, "  %-28s %10.2f %10.2f\n", "wheel odometry",
                 j.at("wheel_odometry").at("final_position_error_m").get<double>(),
                 j.at("wheel_odometry").at("position_rmse_m").get<double>());
    const json& drift = ins.at("heading_drift_rad");
    std::fprintf(out, "velocity RMSE %.3f m/s; heading drift %.2f deg (last 5 s of driving)\n",
                 ins.at("velocity_rmse_mps").get<double>(),
                 drift.is_number() ? drift.get<double>() * 180.0 / M_PI : NAN);
    const auto num = [](const json& v) { return v.is_number() ? v.get<double>() : NAN; };
    std::fprintf(
        out,
        "after the best rigid alignment over the first 20 m of GPS track (rotation %.2f deg): RMSE INS %.2f m, "
        "wheel odometry %.2f m\n",
        num(ins.at("alignment_rotation_rad")) * 180.0 / M_PI, num(ins.at("aligned_position_rmse_m")),
        num(j.at("wheel_odometry").at("aligned_position_rmse_m")));
  } else {
    std::fprintf(out, "no GPS stream: no position metrics\n");
  }
  if (j.contains("slip_confusion")) {
    std::fprintf(out, "\n");
    if (j.contains("no_slip_band") && j.at("no_slip_band").is_number())
      std::fprintf(out, "no slip: |s| <= %.3f (%s)\n", j.at("no_slip_band").get<double>(),
                   j.at("no_slip_band").get<double>() == 0.0 ? "standstill, Eq. 30's third case" : "band");
    print_confusion(j.at("slip_confusion"), out);
  }
  if (j.contains("slip_confusion_moving")) {
    const json& c = j.at("slip_confusion_moving");
    std::fprintf(out, "  moving samples only: accuracy %.1f %% of %ld\n", 100.0 * c.at("accuracy").get<double>(),
                 c.at("total").get<long>());
  }
}

void InsSlipPresentation::report(const json& j, ReportSection& s) const {
  auto& html = s.html;
  const auto n = [](const json& v, const char* f) { return ReportSection::number(v, f); };
  html << "<h2>" << kInsSlipTitle << "</h2>\n";
  report_health(j, s);
  html << "<p>" << ReportSection::escape(j.at("initial_heading").at("text").get<std::string>()) << ".</p>\n";
  if (j.contains("imu_vibration") && j.at("imu_vibration").at("detector_speed_error_mps").is_number()) {
    const json& v = j.at("imu_vibration");
    html << "<p>IMU vibration while moving: " << n(v.at("forward_vibration_mps2"), "%.2f") << " / "
         << n(v.at("vertical_vibration_mps2"), "%.2f") << " m/s^2 RMS forward / vertical; the vertical channel wanders "
         << n(v.at("vertical_walk_mps_per_sqrt_s"), "%.3f") << " m/s/sqrt(s) (the filter models "
         << n(v.at("modelled_walk_mps_per_sqrt_s"), "%.4f") << "), forward about "
         << n(v.at("forward_walk_mps_per_sqrt_s"), "%.3f") << ": over the longest drive between stops ("
         << n(v.at("longest_drive_s"), "%.0f") << " s) the slip detector's speed is known to about "
         << n(v.at("detector_speed_error_mps"), "%.2f") << " m/s RMS, at the median speed of "
         << n(v.at("median_speed_mps"), "%.2f") << " m/s a slip of about " << n(v.at("slip_resolution"), "%.2f")
         << ".</p>\n";
  }
  if (j.at("has_reference").get<bool>()) {
    const json& ins = j.at("ins");
    const json& enu = ins.at("position_rmse_enu_m");
    const json& odo = j.at("wheel_odometry");
    const json& drift = ins.at("heading_drift_rad");
    html << "<table><tr><th></th><th>final horizontal error (m)</th><th>horizontal RMSE (m)</th><th>RMSE east / north "
            "/ up (m)</th></tr>\n"
         << "<tr><td style=\"text-align:left\">INS + pseudo-measurements + wheels</td><td>"
         << n(ins.at("final_position_error_m"), "%.2f") << "</td><td>" << n(ins.at("position_rmse_m"), "%.2f")
         << "</td><td>" << n(enu.at(0), "%.2f") << " / " << n(enu.at(1), "%.2f") << " / " << n(enu.at(2), "%.2f")
         << "</td></tr>\n<tr><td style=\"text-align:left\">wheel odometry</td><td>"
         << n(odo.at("final_position_error_m"), "%.2f") << "</td><td>" << n(odo.at("position_rmse_m"), "%.2f")
         << "</td><td></td></tr></table>\n"
         << "<p>After the best rigid alignment over the first 20 m of GPS track: RMSE INS "
         << n(ins.at("aligned_position_rmse_m"), "%.2f") << " m, wheel odometry "
         << n(odo.at("aligned_position_rmse_m"), "%.2f") << " m.</p>\n"
         << "<p>Velocity RMSE " << n(ins.at("velocity_rmse_mps"), "%.3f") << " m/s; heading drift "
         << ReportSection::number(drift.is_number() ? drift.get<double>() * 180.0 / M_PI : NAN, "%.2f") << " deg over "
         << n(j.at("distance_m"), "%.1f") << " m.</p>\n";
  }
  if (!j.contains("slip_confusion")) return;
  const json& c = j.at("slip_confusion");
  html << "<h3>Slip classes (column-normalised; rows estimated, columns reference)</h3>\n<table><tr><th></th>";
  std::string csv = "estimated\\reference";
  for (int t = 0; t < kSlipClasses; ++t) {
    html << "<th>" << class_name(t) << "</th>";
    csv += std::string(",") + class_name(t);
  }
  html << "</tr>\n";
  csv += "\n";
  for (int e = 0; e < kSlipClasses; ++e) {
    html << "<tr><th>" << class_name(e) << "</th>";
    csv += class_name(e);
    for (int t = 0; t < kSlipClasses; ++t) {
      const json& f = c.at("column_normalised").at(e).at(t);
      const bool known = f.is_number();
      const int shade = known ? static_cast<int>(255 - 120 * f.get<double>()) : 255;
      html << "<td style=\"background:rgb(" << shade << "," << shade << ",255)\">"
           << (known ? ReportSection::number(100.0 * f.get<double>(), "%.1f") + " %" : "–") << "</td>";
      csv += "," + (known ? ReportSection::number(f, "%.4f") : std::string());
    }
    html << "</tr>\n";
    csv += "\n";
  }
  std::string accuracy = accuracy_text(c);
  accuracy[0] = 'A';
  html << "</table>\n<p>" << ReportSection::escape(accuracy) << "; " << ReportSection::escape(recalls_text(c))
       << ".</p>\n";
  s.write_csv("slip_confusion.csv", csv);
}

}  // namespace

std::unique_ptr<Analysis> make_ins_slip_analysis() { return std::make_unique<InsSlipAnalysis>(); }

}  // namespace roverlab::app

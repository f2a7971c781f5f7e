// `estimate net-traction`: drawbar pull, resistive torque, normal load, slip
// and contact angle of every wheel of a planar rocker-bogie from its own
// sensors (seed 003 sections 5.4-5.6), and the traction surfaces DP(W, s)
// and tau_R(W, s) rebuilt from the estimates (section 5.7), compared with
// the true local model in the layout of Table 5.2 when the log has truth.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <optional>

#include "app/analysis.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/estimation/net_traction/net_traction.h"
#include "core/estimation/net_traction/streams.h"
#include "core/estimation/net_traction/surface.h"
#include "importers/rover_file.h"
#include "importers/soil_file.h"
#include "views/traction_surface_scene.h"

namespace roverlab::app {

namespace {

using nlohmann::json;
constexpr double kDegPerRad = 180.0 / M_PI;
// A rover whose forward speed never exceeds this has not moved.

json vec(const Eigen::Vector3d& v, double scale = 1.0) {
  return json::array({finite_or_null(v(0) * scale), finite_or_null(v(1) * scale), finite_or_null(v(2) * scale)});
}

json surface_json(const terramechanics::PolynomialSurface& s) {
  json terms = json::array(), coefficients = json::array();
  for (std::size_t i = 0; i < s.coefficients().size(); ++i) {
    terms.push_back(analysis::surface_term(i));
    coefficients.push_back(finite_or_null(s.coefficients()[i]));
  }
  return {{"order", s.order()}, {"terms", terms}, {"coefficients", coefficients}};
}

json quantity_json(const analysis::QuantityFit& f, const analysis::TraversedRegion& region) {
  json j = surface_json(f.estimate.surface);
  j["region"] = {{"slip", {region.slip_min, region.slip_max}},
                 {"load_N", {region.load_min, region.load_max}},
                 {"coverage", region.grid.coverage()}};
  j["fit_rmse"] = f.estimate.error.rmse;
  json cv = json::array();
  for (const auto& o : f.estimate.orders) cv.push_back({{"order", o.order}, {"cv_rmse", o.cv_rmse}});
  if (!cv.empty()) j["cross_validation"] = cv;
  if (f.has_truth) {
    j["truth_coefficients"] = surface_json(f.truth.surface).at("coefficients");
    const auto& c = f.comparison;
    j["rms_vs_truth"] = {{"rms", c.rms},
                         {"max_abs", c.max_abs},
                         {"range", c.range},
                         {"rms_percent", c.rms_percent},
                         {"max_percent", c.max_percent},
                         {"grid_points", c.grid_points}};
  }
  return j;
}

// Section 5.9: where along the path the traction relationship changed.
json changes_json(const analysis::ChangeDetection& d) {
  json points = json::array();
  for (const auto& c : d.changes) {
    points.push_back({{"x_m", c.x},
                      {"front_wheel_time_s", finite_or_null(c.front_wheel_time)},
                      {"statistic", c.statistic},
                      {"points_before", c.before},
                      {"points_after", c.after}});
  }
  const analysis::ChangeDetectorOptions o;
  return {{"change_points", points},
          {"change_detector",
           {{"statistic", "sum over DP and tau_R of ln(RSS of one Eq. 2.28 surface / RSS of two split at x)"},
            {"order", o.order},
            {"threshold", o.threshold},
            {"min_points", o.min_points},
            {"points", d.points},
            {"largest_statistic", d.largest_statistic},
            {"largest_at_m", d.largest_at},
            {"min_path_m", o.min_path},
            {"not_run", d.not_run}}}};
}

// The averaged steady-state points (at most 1500, evenly spaced) for the
// traction-surface view, as columns.
json points_json(const std::vector<analysis::TractionPoint>& points) {
  constexpr std::size_t kMost = 1500;
  const std::size_t stride = std::max<std::size_t>(1, (points.size() + kMost - 1) / kMost);
  json wheel = json::array(), load = json::array(), slip = json::array(), dp = json::array(), tau = json::array(),
       x = json::array();
  for (std::size_t i = 0; i < points.size(); i += stride) {
    const auto& p = points[i];
    wheel.push_back(p.wheel);
    load.push_back(finite_or_null(p.load));
    slip.push_back(finite_or_null(p.slip));
    dp.push_back(finite_or_null(p.drawbar_pull));
    tau.push_back(finite_or_null(p.resistive_torque));
    x.push_back(finite_or_null(p.x));
  }
  return {{"every", stride}, {"wheel", wheel},       {"load_N", load},
          {"slip", slip},    {"drawbar_pull_N", dp}, {"resistive_torque_Nm", tau},
          {"x_m", x}};
}

// How its result is shown.
class NetTractionPresentation : public Presentation {
 public:
  bool draws_traction_surfaces() const override { return true; }
  bool traction_surface(const json& document, bool drawbar_pull, views::TractionSurfaceData& d) const override;
  void print(const json& j, std::FILE* out) const override;
  void report(const json& j, ReportSection& section) const override;
  std::vector<KeyMetric> key_metrics() const override {
    return {{"net_traction_tau_r_rms_percent", "net traction: tau_R surface RMS vs truth (%)",
             "/summary/resistive_torque_rms_percent"},
            {"net_traction_dp_rms_percent", "net traction: DP surface RMS vs truth (%)",
             "/summary/drawbar_pull_rms_percent"},
            {"net_traction_changes", "net traction: soil changes found", "/summary/change_count"},
            {"net_traction_change_x_m", "net traction: first soil change at x (m)", "/summary/first_change_x_m"}};
  }
};

class NetTractionAnalysis : public Analysis {
 public:
  NetTractionAnalysis()
      : Analysis({"net-traction",
                  "estimate net-traction",
                  "Net-traction estimator (seed 003)",
                  "Drawbar pull, resistive torque, normal load, slip and contact angle of a planar rocker-bogie's "
                  "wheels, and its traction surfaces rebuilt from them (seed 003)",
                  "Planar rocker-bogie log with joints, imu, velocimeter, forces and commands streams (truth/ for "
                  "errors)",
                  {estimation::net_traction_streams::kPrefix},
                  std::nullopt},
                 std::make_unique<NetTractionPresentation>()) {}

  std::string missing(const log::Log& lg) const override {
    std::string m = estimation::net_traction_missing(lg);
    if (!m.empty()) return m;
    if (!planar_rover(lg)) return "the log's rover '" + lg.metadata.rover_id + "' is not a planar rocker-bogie";
    if (!analysis::drives(lg.stream("velocimeter")))
      return "the rover never moves (forward speed within 2 mm/s over every second)";
    return "";
  }
  bool runs_on_open(const log::Log& lg) const override {
    return missing(lg).empty() && lg.find_stream(estimation::net_traction_streams::kWheels) == nullptr;
  }

  void declare(CLI::App& cmd) override {
    cmd.add_option("--force-sensors", force_sensors_,
                   "two-axis | single-axis (default: two-axis when the log has perpendicular loads)");
    cmd.add_option(
           "--order", order_,
           "Order of the Eq. 2.28 surfaces, 1..6 (the seed's Table 5.2: 2), or auto (cross-validation over 1..4)")
        ->capture_default_str();
    cmd.add_option("--soil", soil_, "Starting soil NAME or FILE for the soil fit to the estimates")
        ->capture_default_str();
    cmd.add_option("--window", window_, "Fit only the last S seconds of estimates (0: all; section 5.9)")
        ->capture_default_str()
        ->check(finite_in(0.0, 1e7));
    cmd.add_option("--bogie-split", bogie_split_,
                   "Single-axis sensors: split of the bogie's perpendicular load, eq-5.66 (in proportion to the "
                   "sensed loads, the seed's), shape (a second pass with DP/W of each bogie wheel from the first "
                   "pass's DP(W, s) surface) or auto (shape unless it makes the DP points fit one surface 25 % worse)")
        ->capture_default_str()
        ->check(CLI::IsMember({"auto", "eq-5.66", "shape"}));
  }
  json configuration() const override {
    return {{"force_sensors", force_sensors_ ? json(*force_sensors_) : json(nullptr)},
            {"order", order_},
            {"soil", soil_},
            {"window_s", window_},
            {"bogie_split", bogie_split_}};
  }
  void check_options() const override {
    (void)order();
    if (force_sensors_) (void)sensors();
  }
  AnalysisResult run(const AnalysisInput& in) override;

 private:
  static std::optional<io::RoverDescription> rover_of(const log::Log& lg, const std::string& file) {
    if (lg.metadata.rover_id.empty()) return std::nullopt;
    try {
      return io::find_rover_named(lg.metadata.rover_id, resource_subfolders("rovers"), file);
    } catch (const InputError&) {
      return std::nullopt;
    }
  }
  static bool planar_rover(const log::Log& lg) {
    const auto d = rover_of(lg, "");
    return d && d->planar.has_value();
  }
  int order() const {
    if (order_ == "auto") return 0;
    try {
      std::size_t used = 0;
      const int n = std::stoi(order_, &used);
      if (used == order_.size() && n >= 1 && n <= 6) return n;
    } catch (const std::exception&) {
    }
    throw UsageError("--order " + order_ + ": expected 1..6 or auto");
  }
  analysis::BogieSplit bogie_split() const {
    if (bogie_split_ == "eq-5.66") return analysis::BogieSplit::eq_5_66;
    return bogie_split_ == "shape" ? analysis::BogieSplit::shape : analysis::BogieSplit::automatic;
  }
  estimation::ForceSensors sensors() const {
    try {
      return estimation::parse_force_sensors(*force_sensors_);
    } catch (const DataError& e) {
      throw UsageError(std::string("--force-sensors: ") + e.what());
    }
  }
  json fits(const log::Log& lg, const estimation::NetTractionResult& r, double wheel_radius) const;
  json soil_fit(const std::vector<analysis::TractionPoint>& points, double wheel_radius) const;

  std::optional<std::string> force_sensors_;
  std::string order_ = "2";  // the seed's Table 5.2
  // The seed's. The shape split is better on the 200 s validation runs but
  // worse on 100-150 s ones (docs/validation/net-traction.md).
  std::string bogie_split_ = "auto";
  std::string soil_ = "ding_tyii";
  double window_ = 0.0;
};

// Item 5: soil strength and shear modulus from the points, then whether the
// sinkage exponent can be told apart from them.
json NetTractionAnalysis::soil_fit(const std::vector<analysis::TractionPoint>& points, double wheel_radius) const {
  using P = terramechanics::Parameter;
  const terramechanics::Soil start = io::find_soil(soil_, resource_subfolders("soils"));
  terramechanics::Wheel wheel;
  wheel.radius = wheel_radius;
  const auto two = analysis::identify_soil_from_points(points, start, wheel, {P::soil_strength, P::shear_modulus});
  const auto three =
      analysis::identify_soil_from_points(points, start, wheel, {P::soil_strength, P::n, P::shear_modulus});
  json params = json::array();
  for (const auto& p : two.fit.parameters) {
    params.push_back({{"name", terramechanics::to_string(p.parameter)},
                      {"value", p.value},
                      {"sigma", finite_or_null(p.sigma)},
                      {"at_bound", p.at_bound}});
  }
  json corr = json::array();
  for (double c : two.fit.correlation) corr.push_back(finite_or_null(c));
  json confounded = json::array();
  for (const auto& [a, b] : three.confounded) {
    confounded.push_back({terramechanics::to_string(a), terramechanics::to_string(b)});
  }
  return {{"start_soil", start.name},
          {"points", two.points},
          {"converged", two.fit.converged},
          {"parameters", params},
          {"correlation", corr},
          {"reduced_chi2", finite_or_null(two.reduced_chi2)},
          {"residual_correlation_factor", finite_or_null(two.correlation_factor)},
          {"cannot_tell_apart_with_n_free", confounded}};
}

json NetTractionAnalysis::fits(const log::Log& lg, const estimation::NetTractionResult& r, double wheel_radius) const {
  analysis::SteadyStateOptions o;
  o.window_seconds = window_;
  json out = json::object();
  const struct {
    const char* name;
    const estimation::FilterTrack* track;
  } estimators[] = {{"two-axis", &r.two_axis}, {"single-axis", &r.single_axis}};
  for (const auto& e : estimators) {
    if (e.track->empty()) continue;
    json j;
    try {
      const analysis::NetTractionModel m = analysis::rebuild_net_traction_model(lg, r, *e.track, o, order());
      j = {{"points", m.points},
           {"kept_samples", m.kept_samples},
           {"drawbar_pull", quantity_json(m.drawbar_pull, m.region)},
           {"resistive_torque", quantity_json(m.resistive_torque, m.region)}};
      j["soil"] = soil_fit(m.estimated_points, wheel_radius);
      j["estimated_points"] = points_json(m.estimated_points);
      j.update(changes_json(m.changes));
    } catch (const DataError& err) {
      j = {{"error", err.what()}};
    }
    const auto errors = estimation::tracking_errors(lg, r, *e.track);
    if (errors.has_truth) {
      j["tracking_rms"] = {{"normal_load_N", vec(errors.normal_load)},
                           {"drawbar_pull_N", vec(errors.drawbar_pull)},
                           {"resistive_torque_Nm", vec(errors.resistive_torque)},
                           {"slip", vec(errors.slip)},
                           {"contact_angle_deg", vec(errors.contact_angle, kDegPerRad)},
                           {"samples", errors.samples}};
    }
    out[e.name] = j;
  }
  return out;
}

AnalysisResult NetTractionAnalysis::run(const AnalysisInput& in) {
  const std::string m = missing(in.log);
  if (!m.empty()) throw DataError(m);
  const io::RoverDescription d = *rover_of(in.log, in.file);
  estimation::net_traction::RoverConstants rover;
  auto& g = rover.geometry;
  g.wheel_radius = d.planar->wheel_radius;
  g.rocker_to_wheel1 = {d.planar->rocker_to_wheel1[0], d.planar->rocker_to_wheel1[1]};
  g.rocker_to_bogie = {d.planar->rocker_to_bogie[0], d.planar->rocker_to_bogie[1]};
  g.bogie_to_wheel2 = {d.planar->bogie_to_wheel2[0], d.planar->bogie_to_wheel2[1]};
  g.bogie_to_wheel3 = {d.planar->bogie_to_wheel3[0], d.planar->bogie_to_wheel3[1]};
  estimation::NetTractionOptions o;
  if (force_sensors_) o.force_sensors = sensors();
  o.progress = in.progress;
  estimation::NetTractionResult r = estimation::run_net_traction(in.log, rover, o);
  analysis::SteadyStateOptions so;
  so.window_seconds = window_;
  const analysis::BogieSplitChoice split = analysis::choose_bogie_split(in.log, rover, o, bogie_split(), so, r);
  const bool shape_split = split.shape;
  const json split_evidence = split.compared ? json{{"first_pass_dp_fit_rmse_N", split.first_pass_fit_rmse},
                                                    {"second_pass_dp_fit_rmse_N", split.second_pass_fit_rmse},
                                                    {"growth_limit", analysis::kSecondPassFitGrowthLimit},
                                                    {"kept", split.shape ? "shape" : "eq-5.66"}}
                                             : json(nullptr);
  AnalysisResult out;
  const double seconds = r.time.empty() ? 0.0 : r.time.back() - r.time.front();
  out.document = {{"file", in.file},
                  {"rover", d.name},
                  {"force_sensors", estimation::force_sensors_name(r.force_sensors)},
                  {"order", order_},
                  {"window_s", window_},
                  {"seconds", seconds},
                  {"wall_seconds", r.filter_seconds},
                  {"standstill_samples", r.standstill_samples},
                  {"rejected_updates",
                   {{"estimator_1", r.rejected_updates[0]},
                    {"estimator_2", r.rejected_updates[1]},
                    {"estimator_3", r.rejected_updates[2]},
                    {"gate_probability", estimation::NetTractionOptions{}.gate_probability}}},
                  {"steady_state",
                   {{"max_wheel_acceleration", analysis::SteadyStateOptions{}.max_wheel_acceleration},
                    {"average_s", analysis::SteadyStateOptions{}.average_seconds},
                    {"settle_s", analysis::SteadyStateOptions{}.settle_seconds}}},
                  {"has_truth", in.log.find_stream("truth/wheels") != nullptr},
                  {"warnings", r.warnings},
                  {"estimators", fits(in.log, r, g.wheel_radius)}};
  json& single = out.document.at("estimators")["single-axis"];
  if (!single.is_null()) {
    single["bogie_split"] = {
        {"requested", bogie_split_},
        {"auto_evidence", split_evidence},
        {"method", shape_split ? "shape" : "eq-5.66"},
        {"passes", shape_split ? 2 : 1},
        {"assumption",
         shape_split ? "wheels 2 and 3 share one contact angle (the mean of their measured ones) and their DP/W differ "
                       "as the first pass's order-2 DP(W, s) surface says at their loads and slips"
                     : "wheels 2 and 3 have the same contact angle and the same DP/W (Eq. 5.66)"}};
  }
  // The streams' estimator's figures, for the campaign table and the views.
  const json& chosen = out.document.at("estimators").at(estimation::force_sensors_name(r.force_sensors));
  const auto at = [&](const char* q, const char* k) {
    return chosen.contains(q) && chosen.at(q).contains("rms_vs_truth") ? chosen.at(q).at("rms_vs_truth").at(k)
                                                                       : json(nullptr);
  };
  json summary = {{"drawbar_pull_rms_percent", at("drawbar_pull", "rms_percent")},
                  {"resistive_torque_rms_percent", at("resistive_torque", "rms_percent")},
                  {"points", chosen.value("points", std::size_t{0})},
                  {"change_count", nullptr},
                  {"first_change_x_m", nullptr}};
  if (chosen.contains("change_points")) {
    out.document["change_points"] = chosen.at("change_points");
    summary["change_count"] = chosen.at("change_points").size();
    if (!chosen.at("change_points").empty()) summary["first_change_x_m"] = chosen.at("change_points").at(0).at("x_m");
  }
  out.document["summary"] = summary;
  out.estimates = std::move(r.estimates);
  return out;
}

void print_tracking_rms(const json& t, std::FILE* out) {
  std::fprintf(out, "  %-6s %10s %10s %12s %8s %12s\n", "wheel", "W (N)", "DP (N)", "tau_R (N m)", "slip",
               "gamma (deg)");
  for (std::size_t w = 0; w < 3; ++w) {
    const auto v = [&](const char* k) {
      const json& x = t.at(k).at(w);
      return x.is_null() ? NAN : x.get<double>();
    };
    std::fprintf(out, "  %-6zu %10.3f %10.3f %12.4f %8.4f %12.3f\n", w + 1, v("normal_load_N"), v("drawbar_pull_N"),
                 v("resistive_torque_Nm"), v("slip"), v("contact_angle_deg"));
  }
}

// Table 5.2's layout: one row per coefficient p_ij of s^i W^j.
void print_table(const json& q, const char* label, std::FILE* out) {
  const bool truth = q.contains("truth_coefficients");
  std::fprintf(out, "  %s, order %d, region s %.3f..%.3f, W %.1f..%.1f N (coverage %.0f %%)\n", label,
               q.at("order").get<int>(), q.at("region").at("slip").at(0).get<double>(),
               q.at("region").at("slip").at(1).get<double>(), q.at("region").at("load_N").at(0).get<double>(),
               q.at("region").at("load_N").at(1).get<double>(), 100.0 * q.at("region").at("coverage").get<double>());
  std::fprintf(out, "    %-10s %14s %14s\n", "term", truth ? "true local" : "", "estimated");
  for (std::size_t i = 0; i < q.at("terms").size(); ++i) {
    char t[32] = "";
    if (truth) std::snprintf(t, sizeof t, "%.5g", q.at("truth_coefficients").at(i).get<double>());
    std::fprintf(out, "    %-10s %14s %14.5g\n", q.at("terms").at(i).get<std::string>().c_str(), t,
                 q.at("coefficients").at(i).get<double>());
  }
  if (truth) {
    const json& c = q.at("rms_vs_truth");
    std::fprintf(
        out,
        "    vs the true local model over the region: RMS %.4g (%.2f %% of its range %.4g), largest %.4g (%.2f %%)\n",
        c.at("rms").get<double>(), c.at("rms_percent").get<double>(), c.at("range").get<double>(),
        c.at("max_abs").get<double>(), c.at("max_percent").get<double>());
  }
}

// Section 5.9's change detector, one line per change (x of the wheels along the path).
void print_changes(const json& e, std::FILE* out) {
  if (!e.contains("change_points")) return;
  const json& d = e.at("change_detector");
  const json& c = e.at("change_points");
  if (!d.at("not_run").get<std::string>().empty()) {
    std::fprintf(out, " soil change: not tested (%s)\n", d.at("not_run").get<std::string>().c_str());
    return;
  }
  if (c.empty()) {
    std::fprintf(out, " soil change: none (largest statistic %.3f at x = %.2f m, threshold %.2f)\n",
                 d.at("largest_statistic").get<double>(), d.at("largest_at_m").get<double>(),
                 d.at("threshold").get<double>());
    return;
  }
  for (const json& p : c) {
    std::fprintf(
        out,
        " soil change at x = %.2f m (front wheel there at %s s; statistic %.3f > %.2f; %zu points before, %zu after)\n",
        p.at("x_m").get<double>(), ReportSection::number(p.at("front_wheel_time_s"), "%.1f").c_str(),
        p.at("statistic").get<double>(), d.at("threshold").get<double>(), p.at("points_before").get<std::size_t>(),
        p.at("points_after").get<std::size_t>());
  }
}

void NetTractionPresentation::print(const json& j, std::FILE* out) const {
  std::fprintf(out, "%s: rover %s, %s force sensors (streams), %.1f s of log, filters %.2f s\n",
               j.at("file").get<std::string>().c_str(), j.at("rover").get<std::string>().c_str(),
               j.at("force_sensors").get<std::string>().c_str(), j.at("seconds").get<double>(),
               j.at("wall_seconds").get<double>());
  for (const auto& w : j.value("warnings", json::array()))
    std::fprintf(out, "warning: %s\n", w.get<std::string>().c_str());
  const auto standstill = j.at("standstill_samples").get<std::size_t>();
  if (standstill > 0) std::fprintf(out, "standstill: %zu samples without a slip measurement\n", standstill);
  const json& gated = j.at("rejected_updates");
  std::fprintf(out, "NIS gate (issue 17) rejected %zu, %zu and %zu updates of Estimators 1, 2 and 3\n",
               gated.at("estimator_1").get<std::size_t>(), gated.at("estimator_2").get<std::size_t>(),
               gated.at("estimator_3").get<std::size_t>());
  std::fprintf(out, "steady state: |wheel acceleration| <= %.4g rad/s^2, averaged over %.1f s\n",
               j.at("steady_state").at("max_wheel_acceleration").get<double>(),
               j.at("steady_state").at("average_s").get<double>());
  for (const char* name : {"two-axis", "single-axis"}) {
    if (!j.at("estimators").contains(name)) continue;
    const json& e = j.at("estimators").at(name);
    const char* which =
        std::string(name) == "two-axis" ? "Estimators 1 and 2 (two-axis)" : "Estimators 1 and 3 (single-axis)";
    std::fprintf(out, "\n%s\n", which);
    if (e.contains("bogie_split")) {
      std::fprintf(out, " bogie split (section 5.6): %s, %d pass(es); assumes %s\n",
                   e.at("bogie_split").at("method").get<std::string>().c_str(),
                   e.at("bogie_split").at("passes").get<int>(),
                   e.at("bogie_split").at("assumption").get<std::string>().c_str());
      const json& ev = e.at("bogie_split").at("auto_evidence");
      if (ev.is_object()) {
        std::fprintf(out,
                     " chosen by auto: DP points' order-2 fit RMS %.3g N (Eq. 5.66) against %.3g N (shape); shape is "
                     "kept below %.3g times\n",
                     ev.at("first_pass_dp_fit_rmse_N").get<double>(), ev.at("second_pass_dp_fit_rmse_N").get<double>(),
                     ev.at("growth_limit").get<double>());
      }
    }
    if (e.contains("tracking_rms")) {
      std::fprintf(out, " RMS error per wheel over %zu samples:\n",
                   e.at("tracking_rms").at("samples").get<std::size_t>());
      print_tracking_rms(e.at("tracking_rms"), out);
    }
    if (e.contains("error")) {
      std::fprintf(out, " no surfaces: %s\n", e.at("error").get<std::string>().c_str());
      continue;
    }
    std::fprintf(out, " surfaces from %zu averaged steady-state points (layout of Table 5.2):\n",
                 e.at("points").get<std::size_t>());
    print_table(e.at("resistive_torque"), "tau_R (N m)", out);
    print_table(e.at("drawbar_pull"), "DP (N)", out);
    const json& soil = e.at("soil");
    std::fprintf(out, " soil fitted to %zu of the points from %s:", soil.at("points").get<std::size_t>(),
                 soil.at("start_soil").get<std::string>().c_str());
    for (const json& p : soil.at("parameters")) {
      std::fprintf(out, " %s %.4g +- %s", p.at("name").get<std::string>().c_str(), p.at("value").get<double>(),
                   ReportSection::number(p.at("sigma"), "%.2g").c_str());
    }
    if (soil.at("correlation").size() == 4) {
      std::fprintf(out, ", correlation %s", ReportSection::number(soil.at("correlation").at(1), "%.2f").c_str());
    }
    std::fprintf(out, "\n");
    for (const json& pair : soil.at("cannot_tell_apart_with_n_free")) {
      std::fprintf(out, "  with n free the points cannot tell %s from %s\n", pair.at(0).get<std::string>().c_str(),
                   pair.at(1).get<std::string>().c_str());
    }
    print_changes(e, out);
  }
}

void NetTractionPresentation::report(const json& j, ReportSection& s) const {
  s.html << "<h2>Net-traction estimator (seed 003, " << ReportSection::escape(j.at("force_sensors").get<std::string>())
         << " force sensors)</h2>\n";
  for (const char* name : {"two-axis", "single-axis"}) {
    if (!j.at("estimators").contains(name)) continue;
    const json& e = j.at("estimators").at(name);
    s.html << "<h3>" << ReportSection::escape(name) << "</h3>\n";
    if (e.contains("tracking_rms")) {
      const json& t = e.at("tracking_rms");
      s.html << "<table><tr><th>wheel</th><th>W RMS (N)</th><th>DP RMS (N)</th><th>&tau;<sub>R</sub> RMS (N m)</th>"
                "<th>slip RMS</th><th>contact angle RMS (deg)</th></tr>\n";
      for (std::size_t w = 0; w < 3; ++w) {
        s.html << "<tr><td>" << w + 1 << "</td>";
        for (const char* k : {"normal_load_N", "drawbar_pull_N", "resistive_torque_Nm", "slip", "contact_angle_deg"}) {
          s.html << "<td>" << ReportSection::number(t.at(k).at(w), "%.4f") << "</td>";
        }
        s.html << "</tr>\n";
      }
      s.html << "</table>\n";
    }
    if (e.contains("error")) {
      s.html << "<p>No surfaces: " << ReportSection::escape(e.at("error").get<std::string>()) << "</p>\n";
      continue;
    }
    for (const char* q : {"resistive_torque", "drawbar_pull"}) {
      const json& f = e.at(q);
      s.html << "<p>" << q << ": order " << f.at("order").get<int>();
      if (f.contains("rms_vs_truth")) {
        s.html << ", against the true local model RMS "
               << ReportSection::number(f.at("rms_vs_truth").at("rms_percent"), "%.2f") << " % and largest "
               << ReportSection::number(f.at("rms_vs_truth").at("max_percent"), "%.2f") << " % of its range";
      }
      s.html << ".</p>\n";
    }
    if (e.contains("change_points")) {
      s.html << "<p>Soil change (section 5.9, threshold "
             << ReportSection::number(e.at("change_detector").at("threshold"), "%.2f") << "): ";
      if (!e.at("change_detector").at("not_run").get<std::string>().empty()) {
        s.html << "not tested: " << ReportSection::escape(e.at("change_detector").at("not_run").get<std::string>());
      } else if (e.at("change_points").empty()) {
        s.html << "none (largest statistic "
               << ReportSection::number(e.at("change_detector").at("largest_statistic"), "%.3f") << ")";
      }
      for (const json& p : e.at("change_points")) {
        s.html << "at x = " << ReportSection::number(p.at("x_m"), "%.2f") << " m (statistic "
               << ReportSection::number(p.at("statistic"), "%.3f") << ") ";
      }
      s.html << ".</p>\n";
    }
  }
}

terramechanics::PolynomialSurface surface_from(const json& order, const json& coefficients) {
  std::vector<double> c;
  for (const auto& v : coefficients) c.push_back(v.is_number() ? v.get<double>() : NAN);
  return {order.get<int>(), c};
}

// The rover's own traction surfaces (seed 003 section 5.7): its estimated
// points coloured by wheel, the surface fitted to them and, with truth, the
// true local model; those of the estimator of the log's force sensors.
bool NetTractionPresentation::traction_surface(const json& r, bool dp, views::TractionSurfaceData& d) const {
  if (!r.contains("estimators")) return false;
  const std::string sensors = r.value("force_sensors", std::string("two-axis"));
  if (!r.at("estimators").contains(sensors)) return false;
  const json& e = r.at("estimators").at(sensors);
  const char* key = dp ? "drawbar_pull" : "resistive_torque";
  if (!e.contains(key) || !e.contains("estimated_points")) return false;
  const json& q = e.at(key);
  d.surface = surface_from(q.at("order"), q.at("coefficients"));
  if (q.contains("truth_coefficients")) d.reference = surface_from(q.at("order"), q.at("truth_coefficients"));
  d.load_min = q.at("region").at("load_N").at(0).get<double>();
  d.load_max = q.at("region").at("load_N").at(1).get<double>();
  d.slip_min = q.at("region").at("slip").at(0).get<double>();
  d.slip_max = q.at("region").at("slip").at(1).get<double>();
  const json& p = e.at("estimated_points");
  const json& values = p.at(dp ? "drawbar_pull_N" : "resistive_torque_Nm");
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!values.at(i).is_number() || !p.at("load_N").at(i).is_number() || !p.at("slip").at(i).is_number()) continue;
    d.points.push_back(
        {p.at("load_N").at(i).get<double>(), p.at("slip").at(i).get<double>(), values.at(i).get<double>(), 1.0});
    d.point_group.push_back(p.at("wheel").at(i).get<int>());
  }
  const int groups = d.point_group.empty() ? 0 : *std::max_element(d.point_group.begin(), d.point_group.end());
  for (int g = 1; g <= groups; ++g) {
    d.group_names.push_back("wheel " + std::to_string(g));
  }
  d.quantity += std::string(" (rover's estimates, ") + sensors + (d.reference ? "; grey: true local model)" : ")");
  return true;
}

}  // namespace

std::unique_ptr<Analysis> make_net_traction_analysis() { return std::make_unique<NetTractionAnalysis>(); }

}  // namespace roverlab::app

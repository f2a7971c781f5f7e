#include "app/report_lab_test.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "app/command_support.h"
#include "app/lab_figures.h"
#include "app/render_view.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/discrepancy/likelihood.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"

namespace roverlab::app {

namespace {

using nlohmann::json;
using terramechanics::Quantity;
using terramechanics::WheelTestPoint;

std::string esc(const std::string& s) { return ReportSection::escape(s); }
std::string num(double v, const char* f = "%.3g") { return ReportSection::number(v, f); }

// "a, b and c"
std::string listed(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == items.size() ? " and " : ", ") + items[i];
  }
  return out;
}

// What was tested: the wheels, the rows, the loads, the slips and slip angles, the quantities measured.
struct TestDescription {
  std::vector<std::string> wheels;
  std::vector<double> loads, slip_angles_deg;
  double slip_min = 0, slip_max = 0;
  std::vector<std::string> quantities;
  std::size_t rows = 0;
};

std::string wheel_text(const WheelTestPoint& p) {
  std::string text = (p.wheel_label.empty() ? std::string("wheel") : p.wheel_label) + " (r " +
                     num(p.wheel.radius * 1000.0, "%.4g") + " mm, b " + num(p.wheel.width * 1000.0, "%.4g") + " mm";
  if (p.wheel.grouser_count > 0) {
    text += ", " + std::to_string(p.wheel.grouser_count) + " grousers of " +
            num(p.wheel.grouser_height * 1000.0, "%.3g") + " mm";
  }
  return text + ")";
}

TestDescription describe(const std::vector<WheelTestPoint>& points) {
  TestDescription d;
  d.rows = points.size();
  std::set<double> loads, angles;
  std::set<Quantity> measured;
  d.slip_min = points.front().slip;
  d.slip_max = points.front().slip;
  for (const auto& p : points) {
    const std::string w = wheel_text(p);
    if (std::find(d.wheels.begin(), d.wheels.end(), w) == d.wheels.end()) d.wheels.push_back(w);
    loads.insert(std::round(p.load * 10.0) / 10.0);
    angles.insert(std::round(p.slip_angle * 180.0 / M_PI * 100.0) / 100.0);
    d.slip_min = std::min(d.slip_min, p.slip);
    d.slip_max = std::max(d.slip_max, p.slip);
    for (Quantity q : terramechanics::kQuantities) {
      if (p.measured(q)) measured.insert(q);
    }
  }
  d.loads.assign(loads.begin(), loads.end());
  d.slip_angles_deg.assign(angles.begin(), angles.end());
  for (Quantity q : measured) d.quantities.emplace_back(terramechanics::to_string(q));
  return d;
}

// The values one by one, or their range when there are more than 8 (a file
// of jittered loads).
std::string numbers_text(const std::vector<double>& values, const char* unit) {
  if (values.size() > 8) {
    const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
    return num(*lo, "%g") + " to " + num(*hi, "%g") + " " + unit + " (" + std::to_string(values.size()) + " values)";
  }
  std::vector<std::string> items;
  items.reserve(values.size());
  for (double v : values) items.push_back(num(v, "%g"));
  return listed(items) + " " + unit;
}

analysis::DiscrepancyReport run_study(const ViewInput& in, const terramechanics::Soil& soil) {
  const io::WheelTestFile file = io::read_wheel_test_file(in.file);
  analysis::DiscrepancyOptions options;
  options.compare_families = true;  // as `discrepancy single-wheel` by default: the family the data support
  if (!file.slip_definition.empty()) {
    options.slip_definition = terramechanics::parse_slip_definition(file.slip_definition);
  }
  return about_file(in.file, [&] {
    const ProgressLine progress("single-wheel study");
    options.progress = progress.callback();
    return analysis::study_single_wheel(soil, in.wheel_points, options);
  });
}

// An error of quantity q as the tables show it: sinkage in mm, the others in their units.
std::string shown(Quantity q, double v) {
  return q == Quantity::sinkage ? num(v * 1000.0) + " mm" : num(v) + " " + terramechanics::unit_of(q);
}

// The held-out RMSE per measured quantity: the baseline's and the final model's.
void error_table(ReportSection& section, const analysis::DiscrepancyReport& r, const SingleWheelModel& final_model,
                 json& out) {
  section.html << "<table><caption>Held-out RMSE (" << esc(r.held_out_method)
               << ")</caption><tr><th>quantity</th><th>baseline</th><th>final model</th></tr>\n";
  for (std::size_t k = 0; k < r.quantities.size(); ++k) {
    const Quantity q = r.quantities[k];
    const double before = k < r.baseline_held_out_rmse.size() ? r.baseline_held_out_rmse[k] : NAN;
    const double after = rms_residual(final_model.held_out, q);
    section.html << "<tr><td style=\"text-align:left\">" << esc(terramechanics::to_string(q)) << "</td><td>"
                 << esc(shown(q, before)) << "</td><td>" << esc(shown(q, after)) << "</td></tr>\n";
    out[terramechanics::to_string(q)] = {{"baseline", finite_or_null(before)},
                                         {"final_model", finite_or_null(after)},
                                         {"unit", terramechanics::unit_of(q)}};
  }
  section.html << "</table>\n";
}

// The model families compared (issue 43): which the study took and by how much, each family's final model and
// its held-out error, and its baseline's held-out RMSE per quantity and fitted parameters.
void family_table(ReportSection& section, const analysis::DiscrepancyReport& r, json& out) {
  out = json::array();
  if (r.families.empty()) return;
  section.html << "<table><caption>Model families: " << esc(r.family_choice)
               << "</caption><tr><th>family</th><th>final model</th><th>its held-out RMS (sigma)</th><th>baseline's "
                  "held-out RMS (sigma)</th>";
  for (const Quantity q : r.quantities) section.html << "<th>" << esc(terramechanics::to_string(q)) << "</th>";
  section.html << "<th>fitted</th></tr>\n";
  for (const auto& f : r.families) {
    section.html << "<tr><td style=\"text-align:left\">" << esc(f.family) << "</td><td style=\"text-align:left\">"
                 << esc(f.final_model.empty()  ? "not extended (the other family fits within the noise)"
                        : f.studied_points > 0 ? f.final_model + " (studied on " + std::to_string(f.studied_points) +
                                                     " of the " + std::to_string(r.points) + " points)"
                                               : f.final_model)
                 << "</td><td>" << num(f.final_held_out_score) << "</td><td>" << num(f.held_out_score) << " ("
                 << esc(f.held_out_method) << ")</td>";
    json rmse = json::object();
    for (std::size_t k = 0; k < r.quantities.size(); ++k) {
      const Quantity q = r.quantities[k];
      const double v = k < f.held_out_rmse.size() ? f.held_out_rmse[k] : NAN;
      section.html << "<td>" << esc(shown(q, v)) << "</td>";
      rmse[terramechanics::to_string(q)] = finite_or_null(v);
    }
    std::string fitted;
    for (const auto& p : f.parameters) {
      fitted += std::string(fitted.empty() ? "" : "; ") + terramechanics::to_string(p.parameter) + " = " +
                analysis::format_fitted(p.value, p.sigma, "1", p.at_bound);
    }
    section.html << "<td style=\"text-align:left\">" << esc(fitted.empty() ? "nothing" : fitted) << "</td></tr>\n";
    out.push_back({{"family", f.family},
                   {"final_model", f.final_model},
                   {"final_held_out_score_sigma", finite_or_null(f.final_held_out_score)},
                   {"final_studied_points", f.final_studied_points(r.points)},
                   {"held_out_score_sigma", finite_or_null(f.held_out_score)},
                   {"held_out_method", f.held_out_method},
                   {"held_out_rmse", rmse}});
  }
  section.html << "</table>\n";
}

void image(ReportSection& section, const std::filesystem::path& folder, const views::View& view,
           const views::SceneInput& input, int w, int h) {
  if (!view.needs(input).empty()) {
    section.html << "<p class=\"note\">No " << esc(view.name()) << " view: " << esc(view.needs(input)) << "</p>\n";
    return;
  }
  std::string name = view.name();
  std::replace(name.begin(), name.end(), '-', '_');
  name += ".png";
  const Rendered r = render_view(view, input, w, static_cast<int>(h * view.report_height()));
  save_png(r.image, (folder / name).string());
  section.wrote(name);
  section.html << "<h2>" << esc(view.heading()) << "</h2>\n<img src=\"" << name << "\" alt=\"" << esc(view.heading())
               << "\">\n";
  for (const auto& n : r.notes) section.html << "<p class=\"note\">" << esc(n) << "</p>\n";
}

void single_wheel_section(ReportSection& section, const std::filesystem::path& folder, json& metrics,
                          const ViewInput& in, const std::optional<std::string>& soil_name, int w, int h) {
  const terramechanics::Soil soil = io::find_soil(soil_name.value_or("dry_sand"), resource_subfolders("soils"));
  const analysis::DiscrepancyReport r = run_study(in, soil);
  const SingleWheelModel final_model = final_single_wheel_model(soil, in.wheel_points, r);
  const TestDescription d = describe(in.wheel_points);
  auto& html = section.html;
  html << "<h2>Verdict of the single-wheel study</h2>\n<p class=\"verdict\">" << esc(r.verdict) << "</p>\n<p>"
       << esc(r.what_is_wrong) << "</p>\n";
  for (const auto& other : r.other_reading) {
    html << "<p>Read as " << esc(other.slip_definition) << " slip: " << esc(other.verdict) << "</p>\n";
  }
  html << "<p class=\"run\"><b>The test</b>: single-wheel rig, " << esc(listed(d.wheels)) << " on " << esc(soil.name)
       << (soil_name ? "" : " (the default soil: give --soil NAME for another)") << "; " << d.rows << " rows at loads "
       << esc(numbers_text(d.loads, "N")) << ", slip " << num(d.slip_min, "%g") << " to " << num(d.slip_max, "%g")
       << ", slip angles " << esc(numbers_text(d.slip_angles_deg, "deg")) << "; measured " << esc(listed(d.quantities))
       << ".</p>\n";
  html << "<p>Study: baseline " << esc(r.baseline_model)
       << (r.slip_definition.empty() ? ""
                                     : ", " + esc(r.slip_definition) + " slip (" + esc(r.slip_definition_reason) + ")")
       << "; final model: " << esc(r.final_model) << ".</p>\n";
  if (r.step_screen_points > 0) {  // the CLI's and the JSON's note, here too
    html << "<p>Each forward step's candidates were ranked on a random subset of " << r.step_screen_points << " of the "
         << r.points << " rows; the best there were refitted on all of them.</p>\n";
  }
  json families;
  family_table(section, r, families);
  json errors = json::object();
  error_table(section, r, final_model, errors);
  views::SceneInput input;
  input.lab = single_wheel_figures(in.wheel_points, final_model);
  for (const char* name : {"slip-panels", "slip-angle-residuals"}) {
    if (const views::View* view = views::find_view(name)) image(section, folder, *view, input, w, h);
  }
  metrics["single_wheel"] = {{"test",
                              {{"wheels", d.wheels},
                               {"soil", soil.name},
                               {"rows", d.rows},
                               {"loads_N", d.loads},
                               {"slip_range", {d.slip_min, d.slip_max}},
                               {"slip_angles_deg", d.slip_angles_deg},
                               {"measured", d.quantities}}},
                             {"verdict", r.verdict},
                             {"what_is_wrong", r.what_is_wrong},
                             {"baseline_model", r.baseline_model},
                             {"family_choice", r.family_choice},
                             {"families", families},
                             {"slip_definition", r.slip_definition},
                             {"final_model", r.final_model},
                             {"curves", final_model.name},
                             {"held_out_method", r.held_out_method},
                             {"step_screen_points", r.step_screen_points},
                             {"held_out_rmse", errors}};
}

// The plate test: its relations fitted (as `soil plate` fits them) with their parameters, and its force against depth.
void plate_section(ReportSection& section, const std::filesystem::path& folder, json& metrics, const ViewInput& in,
                   int w, int h) {
  const terramechanics::PlateAnalysis a = about_file(in.file, [&] {
    return terramechanics::analyse_plate_tests(in.plate_records, terramechanics::PlateFitOptions{});
  });
  const terramechanics::PlateRecord& rec = in.plate_records.front();
  auto& html = section.html;
  html << "<h2>Plate test</h2>\n<p class=\"run\"><b>The test</b>: a "
       << (rec.plate.circular ? "circular" : "rectangular") << " plate, b = " << num(rec.plate.b() * 1000.0, "%.4g")
       << " mm; " << rec.depth.size() << " samples, " << a.records.front().virgin.size()
       << " of them virgin loading (fitted); force noise " << num(a.records.front().force_noise) << " N.</p>\n";
  html << "<table><caption>Pressure-sinkage relations (soil plate)</caption><tr><th>relation</th><th>parameters "
          "(+-1 sigma)</th><th>RMSE</th><th>held-out RMSE</th></tr>\n";
  json fits = json::array();
  for (const auto& f : a.fits) {
    std::string params;
    json pj = json::object();
    for (const auto& p : f.parameters) {
      params +=
          (params.empty() ? "" : "; ") + p.name + " = " + num(p.value, "%.4g") +
          (std::isfinite(p.sigma) ? " +- " + num(p.sigma, "%.2g") : std::string(p.at_bound ? " (at its bound)" : "")) +
          (p.unit == "1" ? std::string() : " " + p.unit);
      pj[p.name] = {{"value", p.value}, {"sigma", finite_or_null(p.sigma)}, {"unit", p.unit}};
    }
    html << "<tr><td style=\"text-align:left\">" << terramechanics::to_string(f.model)
         << "</td><td style=\"text-align:left\">" << esc(params) << "</td><td>" << num(f.rmse_N) << " N</td><td>"
         << num(f.held_out_rmse_N) << " N</td></tr>\n";
    fits.push_back({{"relation", terramechanics::to_string(f.model)},
                    {"parameters", pj},
                    {"rmse_N", f.rmse_N},
                    {"held_out_rmse_N", f.held_out_rmse_N},
                    {"note", f.note}});
  }
  html << "</table>\n";
  for (const auto& f : a.fits) {
    if (!f.note.empty())
      html << "<p class=\"note\">" << terramechanics::to_string(f.model) << ": " << esc(f.note) << "</p>\n";
  }
  views::SceneInput input;
  input.lab = lab_figures_of(in, std::nullopt);
  if (const views::View* view = views::find_view("force-depth")) image(section, folder, *view, input, w, h);
  metrics["plate_test"] = {{"plate_b_m", rec.plate.b()}, {"samples", rec.depth.size()}, {"fits", fits}};
}

}  // namespace

void write_lab_test_section(ReportSection& section, const std::filesystem::path& folder, json& metrics,
                            const ViewInput& in, const std::optional<std::string>& soil, int w, int h) {
  if (in.is_wheel_test()) single_wheel_section(section, folder, metrics, in, soil, w, h);
  if (in.is_plate_test()) plate_section(section, folder, metrics, in, w, h);
}

}  // namespace roverlab::app

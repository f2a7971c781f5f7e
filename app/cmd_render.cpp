// `roverlab render`: one view of a log as a PNG, headless; `roverlab report`:
// an HTML page with the views and the metric tables (also CSV and JSON).
#include <cmath>
#include <memory>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>

#include <vtkContextView.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include "app/commands.h"
#include "views/x_display.h"
#include "app/views_input.h"
#include "core/common/error.h"
#include "core/estimation/slip.h"
#include "importers/atomic_file.h"
#include "views/contact_angle_scene.h"
#include "views/offscreen.h"
#include "views/planar_rover_scene.h"
#include "views/rover_scene.h"
#include "views/timeseries_chart.h"
#include "views/traction_surface_scene.h"

namespace roverlab::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::pair<int, int> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 16 || h < 16 ||
      w > 8192 || h > 8192) {
    throw UsageError("--size " + s + ": expected WxH, each 16..8192 (e.g. 1280x800)");
  }
  return {w, h};
}

// A time inside the drive: the middle of the first pose track's moving part.
double default_time(const views::RoverScene& scene) { return 0.5 * (scene.start_time() + scene.end_time()); }

views::Image render_renderer(vtkRenderer* renderer, int w, int h) {
  auto window = views::make_offscreen_window(w, h);
  window->AddRenderer(renderer);
  return views::capture(window);
}

views::Image render_chart(views::TimeSeriesChart& chart, int w, int h) {
  auto window = views::make_offscreen_window(w, h);
  chart.view()->SetRenderWindow(window);
  chart.set_window(chart.start_time(), chart.end_time(), static_cast<std::size_t>(w));
  return views::capture(window);
}

void save_png(const views::Image& img, const std::string& path) {
  io::write_atomically(path, [&](const std::string& tmp) { views::write_png(img, tmp); });
}

struct Rendered {
  views::Image image;
  std::vector<std::string> notes;
  double time = NAN;
};

Rendered render_view(const ViewInput& in, const std::string& view, std::optional<double> time,
                     const std::optional<std::string>& channels, const std::optional<std::string>& soil,
                     const std::string& quantity, int w, int h) {
  Rendered r;
  if (view == "rover" && views::is_planar_rocker_bogie_log(in.log)) {
    views::PlanarRoverScene scene(in.log);
    r.time = time.value_or(0.5 * (scene.start_time() + scene.end_time()));
    scene.set_time(r.time);
    r.image = render_renderer(scene.renderer(), w, h);
  } else if (view == "rover") {
    if (in.is_wheel_test()) throw InputError(in.file, "single-wheel test points have no rover pose");
    views::RoverScene scene(in.log, rover_geometry(in.log));
    if (scene.pose_source().empty()) throw InputError(in.file, scene.notes().front());
    r.time = time.value_or(default_time(scene));
    scene.set_time(r.time);
    r.image = render_renderer(scene.renderer(), w, h);
    r.notes = scene.notes();
  } else if (view == "timeseries") {
    if (in.is_wheel_test()) throw InputError(in.file, "single-wheel test points are not time series");
    std::vector<views::ChannelRef> refs;
    try {
      refs = channels ? views::parse_channels(in.log, *channels) : views::default_channels(in.log);
    } catch (const DataError& e) {
      throw InputError(in.file, e.what());
    }
    views::TimeSeriesChart chart(in.log, refs);
    r.time = time.value_or(chart.start_time());
    chart.set_cursor(r.time);
    r.image = render_chart(chart, w, h);
  } else if (view == "traction-surface") {
    const views::TractionSurfaceData d = traction_surface_of(in, quantity, soil);
    const views::TractionSurfaceScene scene = views::make_traction_surface_scene(d);
    r.image = render_renderer(scene.renderer, w, h);
  } else if (view == "contact-angles") {
    if (in.is_wheel_test()) throw InputError(in.file, "single-wheel test points have no contact angles");
    std::unique_ptr<views::ContactAngleScene> scene;
    try {
      scene = std::make_unique<views::ContactAngleScene>(in.log);
    } catch (const DataError& e) {
      throw InputError(in.file, std::string(e.what()) + " (the log needs imu, joints and wheels of a DH rover)");
    }
    r.time = time.value_or(0.5 * (scene->start_time() + scene->end_time()));
    auto window = views::make_offscreen_window(w, h);
    for (const auto& ren : scene->renderers()) window->AddRenderer(ren);
    scene->set_time(r.time);
    r.image = views::capture(window);
  } else {
    throw UsageError("--view " + view + ": expected rover, traction-surface, contact-angles or timeseries");
  }
  return r;
}

std::string html_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else if (c == '&') o += "&amp;";
    else o += c;
  }
  return o;
}

std::string fmt(double v, const char* f = "%.3g") {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

}  // namespace

int run_render(const RenderOptions& o) {
  const auto [w, h] = parse_size(o.size);
  if (o.view != "rover" && o.view != "timeseries" && o.view != "traction-surface" && o.view != "contact-angles") {
    throw UsageError("--view " + o.view + ": expected rover, traction-surface, contact-angles or timeseries");
  }
  if (fs::path(o.output).extension() != ".png") throw UsageError("--output " + o.output + ": must end in .png");
  ViewInputOptions vo;
  vo.run_estimator = o.view == "rover";
  vo.run_contact_estimator = o.view == "contact-angles";
  const ViewInput in = load_view_input(o.file, o.mapping, vo);
  views::ensure_display();
  const Rendered r = render_view(in, o.view, o.time, o.channels, o.soil, o.quantity, w, h);
  save_png(r.image, o.output);
  for (const auto& n : in.notes) std::printf("note: %s\n", n.c_str());
  for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
  std::printf("wrote %s (%dx%d, %s view%s)\n", o.output.c_str(), w, h, o.view.c_str(),
              std::isfinite(r.time) ? (", t = " + fmt(r.time, "%.2f") + " s").c_str() : "");
  return kSuccess;
}

int run_report(const ReportOptions& o) {
  const auto [w, h] = parse_size(o.size);
  ViewInputOptions vo;
  vo.run_odometry_study = true;
  vo.run_contact_estimator = true;
  const ViewInput in = load_view_input(o.file, o.mapping, vo);
  const fs::path dir(o.output);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw InputError(o.output, "cannot create the report folder");
  views::ensure_display();

  json metrics = {{"file", o.file}, {"notes", in.notes}};
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>RoverLab report: "
       << html_escape(fs::path(o.file).filename().string()) << "</title>\n<style>"
       << "body{font-family:sans-serif;max-width:1100px;margin:2em auto;color:#222}"
       << "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:4px 8px;text-align:right}"
       << "th{background:#eef}img{max-width:100%;border:1px solid #ccc}.note{color:#555}</style></head><body>\n"
       << "<h1>RoverLab report</h1>\n<p>" << html_escape(o.file) << "</p>\n";
  for (const auto& n : in.notes) html << "<p class=\"note\">" << html_escape(n) << "</p>\n";
  auto image = [&](const std::string& name, const std::string& title, const Rendered& r) {
    save_png(r.image, (dir / name).string());
    html << "<h2>" << title << "</h2>\n<img src=\"" << name << "\" alt=\"" << title << "\">\n";
    for (const auto& n : r.notes) html << "<p class=\"note\">" << html_escape(n) << "</p>\n";
  };

  if (!in.is_wheel_test()) {
    // Streams.
    html << "<h2>Streams</h2>\n<table><tr><th>stream</th><th>samples</th><th>rate (Hz)</th><th>duration (s)</th>"
            "<th>channels</th></tr>\n";
    json streams = json::array();
    for (const auto& s : in.log.streams()) {
      html << "<tr><td style=\"text-align:left\">" << html_escape(s.name()) << "</td><td>" << s.size() << "</td><td>"
           << fmt(s.mean_rate_hz(), "%.1f") << "</td><td>" << fmt(s.duration(), "%.2f") << "</td><td>"
           << s.channels().size() << "</td></tr>\n";
      streams.push_back({{"name", s.name()}, {"samples", s.size()}, {"rate_hz", s.mean_rate_hz()}});
    }
    html << "</table>\n";
    metrics["streams"] = streams;
    views::RoverScene probe(in.log);
    if (!probe.pose_source().empty() || views::is_planar_rocker_bogie_log(in.log)) {
      image("rover.png", "Rover", render_view(in, "rover", std::nullopt, std::nullopt, std::nullopt, o.quantity, w, h));
    } else {
      html << "<p class=\"note\">No rover view: " << html_escape(probe.notes().front()) << "</p>\n";
    }
    if (in.log.find_stream("estimate/contact/wheels") != nullptr) {
      image("contact_angles.png", "Contact and side-slip angles",
            render_view(in, "contact-angles", std::nullopt, std::nullopt, std::nullopt, o.quantity, w, h));
    }
    std::optional<std::string> slip_channels;
    if (in.log.find_stream("estimate/ins/slip") && in.log.stream("estimate/ins/slip").find_channel("reference_slip")) {
      slip_channels = "estimate/ins/slip:slip_ratio,estimate/ins/slip:reference_slip";
    }
    image("timeseries.png", "Time series", render_view(in, "timeseries", std::nullopt, std::nullopt, std::nullopt, o.quantity, w, h / 2));
    if (slip_channels) {
      image("slip.png", "Slip ratio: INS estimate and reference",
            render_view(in, "timeseries", std::nullopt, slip_channels, std::nullopt, o.quantity, w, h / 2));
    }
  }
  if (in.ins) {
    const auto& m = in.ins->metrics;
    json ins = {{"duration_s", m.duration}, {"standstill_fraction", m.standstill_fraction}};
    html << "<h2>INS slip detection (seed 002)</h2>\n";
    if (m.has_reference) {
      html << "<table><tr><th></th><th>final error (m)</th><th>RMSE (m)</th><th>RMSE east / north / up (m)</th></tr>\n"
           << "<tr><td style=\"text-align:left\">INS + pseudo-measurements + wheels</td><td>"
           << fmt(m.final_position_error, "%.2f") << "</td><td>" << fmt(m.position_rmse, "%.2f") << "</td><td>"
           << fmt(m.position_rmse_axes.east, "%.2f") << " / " << fmt(m.position_rmse_axes.north, "%.2f") << " / "
           << fmt(m.position_rmse_axes.up, "%.2f") << "</td></tr>\n<tr><td style=\"text-align:left\">wheel odometry</td><td>"
           << fmt(in.ins->odometry.final_position_error, "%.2f") << "</td><td>"
           << fmt(in.ins->odometry.position_rmse, "%.2f") << "</td><td></td></tr></table>\n"
           << "<p>Velocity RMSE " << fmt(m.velocity_rmse, "%.3f") << " m/s; heading drift "
           << fmt(m.heading_drift * 180.0 / M_PI, "%.2f") << " deg over " << fmt(m.distance, "%.1f") << " m.</p>\n";
      ins["final_position_error_m"] = m.final_position_error;
      ins["position_rmse_m"] = m.position_rmse;
      ins["velocity_rmse_mps"] = m.velocity_rmse;
      ins["wheel_odometry_final_error_m"] = in.ins->odometry.final_position_error;
    }
    if (m.confusion.total() > 0) {
      html << "<h3>Slip classes (column-normalised; rows estimated, columns reference)</h3>\n<table><tr><th></th>";
      std::string csv = "estimated\\reference";
      for (int t = 0; t < estimation::kSlipClasses; ++t) {
        html << "<th>" << estimation::to_string(static_cast<estimation::SlipClass>(t)) << "</th>";
        csv += std::string(",") + estimation::to_string(static_cast<estimation::SlipClass>(t));
      }
      html << "</tr>\n";
      csv += "\n";
      json rows = json::array();
      for (int e = 0; e < estimation::kSlipClasses; ++e) {
        html << "<tr><th>" << estimation::to_string(static_cast<estimation::SlipClass>(e)) << "</th>";
        csv += estimation::to_string(static_cast<estimation::SlipClass>(e));
        json row = json::array();
        for (int t = 0; t < estimation::kSlipClasses; ++t) {
          const double f = m.confusion.fraction(e, t);
          const int shade = std::isfinite(f) ? static_cast<int>(255 - 120 * f) : 255;
          html << "<td style=\"background:rgb(" << shade << "," << shade << ",255)\">"
               << (std::isfinite(f) ? fmt(100.0 * f, "%.1f") + " %" : "–") << "</td>";
          csv += "," + (std::isfinite(f) ? fmt(f, "%.4f") : std::string());
          row.push_back(std::isfinite(f) ? json(f) : json(nullptr));
        }
        html << "</tr>\n";
        csv += "\n";
        rows.push_back(row);
      }
      html << "</table>\n<p>Accuracy " << fmt(100.0 * m.confusion.accuracy(), "%.1f") << " % of "
           << m.confusion.total() << " samples.</p>\n";
      io::write_text_atomically((dir / "slip_confusion.csv").string(), csv);
      ins["slip_confusion"] = rows;
      ins["slip_accuracy"] = m.confusion.accuracy();
    }
    metrics["ins_slip"] = ins;
  }
  if (in.contact && in.contact->has_truth) {
    const auto& e = in.contact->rms;
    html << "<h2>Contact-angle estimator (seed 000, model C+SS, EKF)</h2>\n<table><tr><th>wheel</th><th>slip RMS</th>"
            "<th>contact angle RMS (deg)</th><th>side slip RMS (deg)</th></tr>\n";
    json rows = json::array();
    const auto& names = in.contact->estimates.stream("estimate/contact/wheels").channels();
    for (std::size_t k = 0; k < e.slip.size(); ++k) {
      const std::string wheel = names[k].name.substr(5);
      html << "<tr><td>" << html_escape(wheel) << "</td><td>" << fmt(e.slip[k], "%.4f") << "</td><td>"
           << fmt(e.contact_angle.empty() ? NAN : e.contact_angle[k] * 180 / M_PI, "%.3f") << "</td><td>"
           << fmt(e.side_slip.empty() ? NAN : e.side_slip[k] * 180 / M_PI, "%.3f") << "</td></tr>\n";
      rows.push_back({{"wheel", wheel}, {"slip", e.slip[k]},
                      {"contact_angle_deg", e.contact_angle.empty() ? json(nullptr) : json(e.contact_angle[k] * 180 / M_PI)},
                      {"side_slip_deg", e.side_slip.empty() ? json(nullptr) : json(e.side_slip[k] * 180 / M_PI)}});
    }
    html << "</table>\n<p>Velocity RMS x / y / z: " << fmt(e.velocity[0], "%.4f") << " / " << fmt(e.velocity[1], "%.4f")
         << " / " << fmt(e.velocity[2], "%.4f") << " m/s over " << e.samples << " moving samples.</p>\n";
    metrics["contact_angle"] = {{"wheels", rows}, {"velocity_rms_mps", e.velocity}};
  }
  if (in.odometry) {
    const auto& r = *in.odometry;
    html << "<h2>What the wheel odometry gets wrong</h2>\n<p>" << html_escape(r.what_is_wrong) << "</p>\n"
         << "<table><tr><th>candidate</th><th>fitted</th><th>fit RMSE (m)</th><th>delta BIC</th>"
            "<th>held-out RMSE (m)</th><th>held-out final (m)</th></tr>\n"
         << "<tr><td style=\"text-align:left\">(nominal)</td><td></td><td>" << fmt(r.baseline_fit_rmse, "%.2f")
         << "</td><td>0</td><td>" << fmt(r.baseline_held_out_rmse, "%.2f") << "</td><td>"
         << fmt(r.baseline_held_out_final, "%.2f") << "</td></tr>\n";
    std::string csv = "candidate,fit_rmse_m,delta_bic,held_out_rmse_m,held_out_final_m,significant\n";
    json cands = json::array();
    for (std::size_t i = 0; i < r.candidates.size(); ++i) {
      const auto& c = r.candidates[i];
      std::string params;
      for (const auto& p : c.parameters) params += p.name + " = " + fmt(p.value, "%.4g") + " ";
      const bool best = static_cast<int>(i) == r.best;
      html << "<tr" << (best ? " style=\"font-weight:bold\"" : "") << "><td style=\"text-align:left\">"
           << html_escape(c.name) << "</td><td style=\"text-align:left\">" << html_escape(params) << "</td><td>"
           << fmt(c.fit_rmse, "%.2f") << "</td><td>" << fmt(c.delta_bic, "%.1f") << "</td><td>"
           << fmt(c.held_out_rmse, "%.2f") << "</td><td>" << fmt(c.held_out_final, "%.2f") << "</td></tr>\n";
      csv += c.name + "," + fmt(c.fit_rmse, "%.6g") + "," + fmt(c.delta_bic, "%.6g") + "," +
             fmt(c.held_out_rmse, "%.6g") + "," + fmt(c.held_out_final, "%.6g") + "," + (c.significant ? "1" : "0") + "\n";
      cands.push_back({{"name", c.name}, {"held_out_rmse_m", c.held_out_rmse}, {"significant", c.significant}});
    }
    html << "</table>\n<p><b>" << html_escape(r.verdict) << "</b></p>\n";
    io::write_text_atomically((dir / "odometry_candidates.csv").string(), csv);
    metrics["odometry_discrepancy"] = {{"cause", r.best >= 0 ? json(r.candidates[static_cast<std::size_t>(r.best)].name) : json(nullptr)},
                                       {"verdict", r.verdict},
                                       {"baseline_held_out_rmse_m", r.baseline_held_out_rmse},
                                       {"candidates", cands}};
  }
  if (in.is_wheel_test() || o.soil) {
    for (const char* q : {"drawbar-pull", "torque"}) {
      terramechanics::SurfaceFit fit;
      views::TractionSurfaceData d;
      try {
        d = traction_surface_of(in, q, o.soil, &fit);
      } catch (const InputError& e) {
        html << "<p class=\"note\">No " << q << " surface: " << html_escape(e.problem()) << "</p>\n";
        continue;
      }
      const views::TractionSurfaceScene scene = views::make_traction_surface_scene(d);
      Rendered r;
      r.image = render_renderer(scene.renderer, w, h);
      image(std::string("surface_") + q + ".png", "Traction surface: " + d.quantity, r);
      html << "<table><tr><th>term</th><th>coefficient</th></tr>\n";
      std::string csv = "k_slip,l_load,coefficient\n";
      json coeffs = json::array();
      const auto& c = fit.surface.coefficients();
      for (std::size_t i = 0; i < c.size(); ++i) {
        const auto [k, l] = terramechanics::PolynomialSurface::exponents(i);
        html << "<tr><td>s^" << k << " W^" << l << "</td><td>" << fmt(c[i], "%.6g") << "</td></tr>\n";
        csv += std::to_string(k) + "," + std::to_string(l) + "," + fmt(c[i], "%.10g") + "\n";
        coeffs.push_back(c[i]);
      }
      html << "</table>\n<p>Fit RMSE " << fmt(fit.error.rmse, "%.4g") << " " << d.unit << ", order "
           << fit.surface.order() << ".</p>\n";
      io::write_text_atomically((dir / (std::string("surface_") + q + ".csv")).string(), csv);
      metrics[std::string("traction_surface_") + q] = {{"order", fit.surface.order()}, {"coefficients", coeffs},
                                                        {"fit_rmse", fit.error.rmse}};
    }
  }
  html << "<p class=\"note\">Generated by roverlab report.</p>\n</body></html>\n";
  io::write_text_atomically((dir / "metrics.json").string(), metrics.dump(2) + "\n");
  io::write_text_atomically((dir / "index.html").string(), html.str());
  std::printf("wrote %s\n", (dir / "index.html").string().c_str());
  return kSuccess;
}

}  // namespace roverlab::app

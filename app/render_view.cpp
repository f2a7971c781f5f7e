#include "app/render_view.h"

#include <cmath>
#include <cstdio>
#include <memory>

#include <vtkContextView.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include "app/commands.h"
#include "core/common/error.h"
#include "importers/atomic_file.h"
#include "views/contact_angle_scene.h"
#include "views/planar_rover_scene.h"
#include "views/rover_scene.h"
#include "views/timeseries_chart.h"
#include "views/traction_surface_scene.h"

namespace roverlab::app {

namespace {

// A time inside the drive: the middle of the first pose track's moving part.
double default_time(const views::RoverScene& scene) { return 0.5 * (scene.start_time() + scene.end_time()); }

views::Image render_chart(views::TimeSeriesChart& chart, int w, int h) {
  auto window = views::make_offscreen_window(w, h);
  chart.view()->SetRenderWindow(window);
  chart.set_window(chart.start_time(), chart.end_time(), static_cast<std::size_t>(w));
  return views::capture(window);
}

}  // namespace

views::Image render_renderer(vtkRenderer* renderer, int w, int h) {
  auto window = views::make_offscreen_window(w, h);
  window->AddRenderer(renderer);
  return views::capture(window);
}

std::pair<int, int> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') || w < 16 || h < 16 ||
      w > 8192 || h > 8192) {
    throw UsageError("--size " + s + ": expected WxH, each 16..8192 (e.g. 1280x800)");
  }
  return {w, h};
}

void save_png(const views::Image& img, const std::string& path) {
  io::write_atomically(path, [&](const std::string& tmp) { views::write_png(img, tmp); });
}

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

}  // namespace roverlab::app

#include "app/render_view.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include <vtkRenderWindow.h>

#include "app/commands.h"
#include "core/common/error.h"
#include "importers/atomic_file.h"

namespace roverlab::app {

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

Rendered render_scene(views::Scene& scene, std::optional<double> time, int w, int h) {
  Rendered r;
  auto window = views::make_offscreen_window(w, h);
  scene.attach(window);
  scene.fit_width(w);
  if (scene.follows_time()) {
    r.time = time.value_or(scene.default_time());
    if (r.time < scene.start_time() || r.time > scene.end_time()) {
      char span[96];
      std::snprintf(span, sizeof span, "--time %g s is outside the log, which spans %.2f .. %.2f s", r.time,
                    scene.start_time(), scene.end_time());
      throw UsageError(span);
    }
    scene.set_time(r.time);
  }
  r.image = views::capture(window);
  r.notes = scene.notes();
  scene.detach(window);
  return r;
}

Rendered render_view(const ViewInput& in, const views::View& view, const ViewOptions& options, int w, int h) {
  return render_view(view, scene_input(in, view, options), w, h);
}

Rendered render_view(const views::View& view, const views::SceneInput& input, int w, int h) {
  const std::unique_ptr<views::Scene> scene = view.build(input);
  return render_scene(*scene, input.time, w, h);
}

void check_time_in_log(const log::Log& lg, std::optional<double> time) {
  if (!time) return;
  double start = std::numeric_limits<double>::infinity(), end = -start;
  for (const auto& s : lg.streams()) {
    if (s.size() == 0) continue;
    start = std::min(start, s.start_time());
    end = std::max(end, s.end_time());
  }
  if (!(start <= end) || (*time >= start && *time <= end)) return;
  char span[96];
  std::snprintf(span, sizeof span, "--time %g s is outside the log, which spans %.2f .. %.2f s", *time, start, end);
  throw UsageError(span);
}

Rendered render_traction_surface(const views::TractionSurfaceData& data, int w, int h) {
  for (const auto& view : views::all_views()) {
    if (!view->uses_surface_data()) continue;
    views::SceneInput input;
    input.surface = data;
    const std::string missing = view->needs(input);
    if (!missing.empty()) throw DataError(missing);
    const std::unique_ptr<views::Scene> scene = view->build(input);
    return render_scene(*scene, std::nullopt, w, h);
  }
  throw std::logic_error("no view draws traction surfaces");
}

}  // namespace roverlab::app

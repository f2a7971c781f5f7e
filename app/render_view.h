#pragma once
// Views of a log rendered offscreen through the view registry
// (views/views.def): the `render` command's PNG and the report's images.
// Also the --size option both take.

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/view_data.h"
#include "app/views_input.h"
#include "views/offscreen.h"
#include "views/view.h"

namespace roverlab::app {

// "WxH", each 16..8192; a UsageError otherwise.
std::pair<int, int> parse_size(const std::string& size);

struct Rendered {
  views::Image image;
  std::vector<std::string> notes;
  double time = NAN;  // NaN for views that do not follow time
};

// `view` of `in` with `options` (time default: the view's own, a time inside
// the drive), `w` x `h` pixels. Throws InputError when the view cannot be
// drawn from `in`.
Rendered render_view(const ViewInput& in, const views::View& view, const ViewOptions& options, int w, int h);

// The same for a scene input already made (scene_input), e.g. checked
// before the display server is started.
Rendered render_view(const views::View& view, const views::SceneInput& input, int w, int h);

// Throws a UsageError when `time` lies outside every stream of `log` (before
// any analysis runs on it).
void check_time_in_log(const log::Log& log, std::optional<double> time);

// The registry's view of a traction surface, for `data` the caller computed.
Rendered render_traction_surface(const views::TractionSurfaceData& data, int w, int h);

// A built scene, offscreen: attached, laid out, at `time` (default: its own).
Rendered render_scene(views::Scene& scene, std::optional<double> time, int w, int h);

// Writes the image as PNG, atomically.
void save_png(const views::Image& image, const std::string& path);

}  // namespace roverlab::app

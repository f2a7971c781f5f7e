#pragma once
// One view of a log rendered offscreen (the `render` command and the report's
// images), and the --size option both take.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "app/views_input.h"
#include "views/offscreen.h"

class vtkRenderer;

namespace roverlab::app {

// "WxH", each 16..8192; a UsageError otherwise.
std::pair<int, int> parse_size(const std::string& size);

struct Rendered {
  views::Image image;
  std::vector<std::string> notes;
  double time = NAN;
};

// View rover | timeseries | traction-surface | contact-angles of `in` at
// `time` (default: a time inside the drive), `w` x `h` pixels.
Rendered render_view(const ViewInput& in, const std::string& view, std::optional<double> time,
                     const std::optional<std::string>& channels, const std::optional<std::string>& soil,
                     const std::string& quantity, int w, int h);

// The scene of one renderer, offscreen.
views::Image render_renderer(vtkRenderer* renderer, int w, int h);

// Writes the image as PNG, atomically.
void save_png(const views::Image& image, const std::string& path);

}  // namespace roverlab::app

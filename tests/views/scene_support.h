#pragma once
// Shared by the scene tests: a scene rendered offscreen (under the private
// Xvfb RoverLab starts when DISPLAY is unset), and the pixels of a colour.

#include <cstdlib>
#include <functional>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include <vtkRenderWindow.h>

#include "views/offscreen.h"
#include "views/view.h"
#include "views/x_display.h"

namespace roverlab::test {

// Renders `scene` in a w x h offscreen window at time t (default: the
// scene's own), as `render` does: attach, lay out, set the time, capture.
// With ROVERLAB_SCENE_PNG=<folder> set, the picture is also written there.
inline views::Image render_scene(views::Scene& scene, int w, int h, std::optional<double> t = std::nullopt) {
  views::ensure_display();
  auto window = views::make_offscreen_window(w, h);
  scene.attach(window);
  scene.fit_width(w);
  if (scene.follows_time()) scene.set_time(t.value_or(scene.default_time()));
  views::Image image = views::capture(window);
  scene.detach(window);
  // ROVERLAB_SCENE_PNG=<folder>: keep the picture, to look at.
  if (const char* folder = std::getenv("ROVERLAB_SCENE_PNG")) {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    views::write_png(image, std::string(folder) + "/" + test->test_suite_name() + "." + test->name() + ".png");
  }
  return image;
}

struct Region {
  int count = 0;
  double mean_x = 0, mean_y = 0;
};

// Pixels in [x0, x1) x [y0, y1) matching `pred` (r, g, b): their count and centroid.
inline Region find_pixels(const views::Image& img, const std::function<bool(int, int, int)>& pred, int x0 = 0,
                          int x1 = -1, int y0 = 0, int y1 = -1) {
  Region r;
  if (x1 < 0) x1 = img.width;
  if (y1 < 0) y1 = img.height;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const unsigned char* p = img.pixel(x, y);
      if (pred(p[0], p[1], p[2])) {
        ++r.count;
        r.mean_x += x;
        r.mean_y += y;
      }
    }
  }
  if (r.count > 0) {
    r.mean_x /= r.count;
    r.mean_y /= r.count;
  }
  return r;
}

// Samples 0, dt, ..., up to `duration`.
inline std::vector<double> times(double duration, double dt) {
  std::vector<double> t;
  for (int i = 0; i * dt <= duration + 1e-9; ++i) t.push_back(i * dt);
  return t;
}

}  // namespace roverlab::test

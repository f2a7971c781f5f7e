#pragma once
// Shared by the scene tests: a scene rendered offscreen (under the private
// Xvfb RoverLab starts when DISPLAY is unset), and the pixels of a colour.

#include <cstdlib>
#include <functional>
#include <optional>
#include <string>

#include <gtest/gtest.h>

#include <vtkRenderWindow.h>

#include "image_support.h"
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

// Samples 0, dt, ..., up to `duration`.
inline std::vector<double> times(double duration, double dt) {
  std::vector<double> t;
  for (int i = 0; i * dt <= duration + 1e-9; ++i) t.push_back(i * dt);
  return t;
}

// The pixels of an estimate's arrow (ContactAngleScene::estimate_rgb, unlit).
inline bool estimate_blue(int r, int g, int b) { return b > 180 && r < 90 && g < 140; }

}  // namespace roverlab::test

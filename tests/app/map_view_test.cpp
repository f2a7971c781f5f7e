// The map view of the bundled WVU Pathfinder log (tests/data/test17run.mat),
// built as `render --view map` builds it (the log, then the analyses that add
// estimate streams): the GPS, INS and odometry tracks are drawn, each whole
// inside what the camera shows at 1400x900, with a labelled scale bar. The
// odometry track ends about 12 m from the others: the rover view's chase
// camera never showed it.
#include <gtest/gtest.h>

#include <cmath>

#include <vtkRenderWindow.h>
#include "app/analysis.h"
#include "app/view_data.h"
#include "app/views_input.h"

#include "views/map_scene.h"
#include "views/offscreen.h"
#include "views/x_display.h"

using namespace roverlab;

TEST(MapView, TheWvuLogShowsGpsInsAndOdometryWholeWithAScaleBar) {
  app::ViewInputOptions options;
  for (const auto& a : app::all_analyses()) {
    if (a->adds_streams()) options.analyses.push_back(a->name());
  }
  const app::ViewInput in =
      app::load_view_input(std::string(ROVERLAB_TEST_DATA) + "/test17run.mat", std::string("wvu_pathfinder"), options);
  const views::View* view = views::find_view("map");
  ASSERT_NE(view, nullptr);
  const views::SceneInput scene_input = app::scene_input(in, *view, app::ViewOptions{});
  const std::unique_ptr<views::Scene> built = view->build(scene_input);
  auto* map = dynamic_cast<views::MapScene*>(built.get());
  ASSERT_NE(map, nullptr);
  const std::vector<std::string> sources = map->sources();
  for (const char* s : {"gps", "estimate/ins/pose", "estimate/odometry/pose"}) {
    EXPECT_NE(std::find(sources.begin(), sources.end(), s), sources.end()) << s;
  }
  views::ensure_display();
  auto window = views::make_offscreen_window(1400, 900);
  map->attach(window);
  map->fit_width(1400);
  map->set_time(map->default_time());
  const views::MapRect shown = map->visible();
  double far_apart = 0;
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const views::MapRect b = map->track_bounds(k);
    EXPECT_TRUE(b[0] >= shown[0] && b[1] >= shown[1] && b[2] <= shown[2] && b[3] <= shown[3]) << sources[k];
    far_apart = std::max(far_apart, std::hypot(b[2] - b[0], b[3] - b[1]));
  }
  EXPECT_GT(far_apart, 30.0);  // a 34 m drive north
  EXPECT_FALSE(map->scale_text().empty());
  EXPECT_EQ(map->scale_text(), std::to_string(static_cast<int>(map->scale_length())) + " m");
  const views::Image img = views::capture(window);
  EXPECT_EQ(img.width, 1400);
  map->detach(window);
}

// Another run's rover as a ghost over the rover view (issue 45): two GPS
// drives north at 0.5 m/s, the second recorded 2 s later on its clock. At
// time t the ghost stands where the second run is at t on its own clock
// (the clocks as recorded: 1 m behind), semi-transparent, drawn in the
// picture beside the rover; without a pose at that time it is hidden.
#include <gtest/gtest.h>

#include <cmath>

#include "core/log/log.h"
#include "scene_support.h"
#include "views/ghost_rover_scene.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

log::Log north_drive(double start) {
  log::Log lg;
  std::vector<double> t = times(20.0, 0.1);
  std::vector<double> east(t.size(), 0.0), north(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    north[i] = 0.5 * t[i];
    t[i] += start;
  }
  log::Stream gps("gps", t);
  gps.add_channel("east", "m", east);
  gps.add_channel("north", "m", north);
  lg.add_stream(std::move(gps));
  return lg;
}

// Pixels of the light rover body (RoverScene::body_colour) in the picture.
int body_pixels(const views::Image& img) {
  return find_pixels(img, [](int r, int g, int b) { return r > 200 && g > 200 && b > 205 && b - r < 20; }).count;
}

}  // namespace

TEST(GhostRoverScene, TheOtherRunsRoverStandsWhereItIsOnItsOwnClock) {
  const log::Log a = north_drive(0.0), b = north_drive(2.0);
  views::GhostRoverScene scene(a, "later", b, estimation::SkidSteerGeometry{});
  const views::Image both = render_scene(scene, 640, 400, 10.0);
  EXPECT_TRUE(scene.ghost_shown());
  EXPECT_NEAR(scene.position().y(), 5.0, 1e-9);
  EXPECT_NEAR(scene.ghost_position().y(), 4.0, 1e-9);  // 2 s later at 0.5 m/s: 1 m behind
  EXPECT_NEAR(scene.ghost_position().x(), scene.position().x(), 1e-9);
  EXPECT_DOUBLE_EQ(scene.ghost_opacity(), 0.35);
  // At t = 1 s the second run has not started on its clock: no ghost, and fewer light pixels than with it.
  const views::Image alone = render_scene(scene, 640, 400, 1.0);
  EXPECT_FALSE(scene.ghost_shown());
  EXPECT_GT(body_pixels(both), 0);
  EXPECT_NE(body_pixels(both), body_pixels(alone));
}

TEST(GhostRoverScene, NeedsAnotherRunWithAPoseTrack) {
  const views::View* view = views::find_view("ghost-rover");
  ASSERT_NE(view, nullptr);
  const log::Log a = north_drive(0.0), none;
  views::SceneInput in;
  in.log = &a;
  EXPECT_NE(view->needs(in).find("another run"), std::string::npos);
  in.compared = {{"empty", &none}};
  EXPECT_NE(view->needs(in).find("empty: "), std::string::npos) << view->needs(in);
  const log::Log b = north_drive(2.0);
  in.compared = {{"later", &b}};
  EXPECT_EQ(view->needs(in), "");
}

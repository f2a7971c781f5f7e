// The 3D rover scene on a small log made here: a GPS track driving north at
// 0.5 m/s with a slip estimate of class none; the chase camera puts the
// rover, its green wheels and light body, in the middle of the picture.
#include <gtest/gtest.h>

#include <cmath>

#include "core/log/log.h"
#include "scene_support.h"
#include "views/rover_scene.h"

#include <vtkPolyData.h>

using namespace roverlab;
using namespace roverlab::test;

namespace {

log::Log north_drive(bool with_slip) {
  log::Log lg;
  const std::vector<double> t = times(20.0, 0.1);
  std::vector<double> east(t.size(), 0.0), north(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) north[i] = 0.5 * t[i];
  log::Stream gps("gps", t);
  gps.add_channel("east", "m", east);
  gps.add_channel("north", "m", north);
  lg.add_stream(std::move(gps));
  if (with_slip) {
    log::Stream slip("estimate/ins/slip", t);
    slip.add_channel("slip_ratio", "1", std::vector<double>(t.size(), 0.01));
    slip.add_channel("slip_class", "1", std::vector<double>(t.size(), 0.0));
    lg.add_stream(std::move(slip));
  }
  return lg;
}

}  // namespace

TEST(RoverScene, FollowsTheGpsTrackWithWheelsInTheSlipClassColour) {
  const log::Log lg = north_drive(true);
  views::RoverScene scene(lg);
  EXPECT_EQ(scene.pose_source(), "gps");
  EXPECT_DOUBLE_EQ(scene.start_time(), 0.0);
  EXPECT_DOUBLE_EQ(scene.end_time(), 20.0);
  const views::Image img = render_scene(scene, 320, 240, 10.0);
  ASSERT_EQ(img.width, 320);
  ASSERT_EQ(img.height, 240);
  EXPECT_NEAR(scene.rover_position().x(), 0.0, 1e-9);
  EXPECT_NEAR(scene.rover_position().y(), 5.0, 1e-9);
  EXPECT_EQ(scene.shown_slip_class(), 0);
  // Issue 32: the legend names the track, behind a filled swatch (a line at the foot read as "_gps").
  EXPECT_EQ(scene.legend_entries(), std::vector<std::string>{"gps"});
  ASSERT_NE(scene.legend_symbol(), nullptr);
  EXPECT_EQ(scene.legend_symbol()->GetNumberOfPolys(), 1);
  EXPECT_EQ(scene.legend_symbol()->GetNumberOfLines(), 0);
  const double* box = scene.legend_symbol()->GetBounds();
  EXPECT_GT(box[3] - box[2], 0.5 * (box[1] - box[0])) << "as tall as wide, not a line";
  // Class none: green wheels, around the middle of the picture.
  const Region green = find_pixels(img, [](int r, int g, int b) { return g - r > 50 && g - b > 50; });
  EXPECT_GT(green.count, 100);
  EXPECT_NEAR(green.mean_x, 160, 32);
  EXPECT_NEAR(green.mean_y, 120, 48);
  // The light body between them.
  const Region body = find_pixels(
      img, [](int r, int g, int b) { return r > 200 && g > 200 && b > 200; }, 80, 240, 60, 180);
  EXPECT_GT(body.count, 100);
  EXPECT_NEAR(body.mean_x, 160, 32);
}

TEST(RoverScene, SaysWhatTheLogLacks) {
  const log::Log lg = north_drive(false);
  views::RoverScene scene(lg);
  bool attitude = false, slip = false;
  for (const auto& n : scene.notes()) {
    attitude = attitude || n.find("no attitude") != std::string::npos;
    slip = slip || n.find("no slip estimate") != std::string::npos;
  }
  EXPECT_TRUE(attitude);
  EXPECT_TRUE(slip);
  render_scene(scene, 320, 240, 5.0);
  EXPECT_EQ(scene.shown_slip_class(), -1);  // grey wheels
  EXPECT_EQ(views::pose_track_needs(lg), "");
  EXPECT_NE(views::pose_track_needs(log::Log{}), "");
}

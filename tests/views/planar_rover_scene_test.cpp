// The planar rocker-bogie side view on a small log made here: the rover
// rolls along x on flat ground at 0.1 m/s; its three low-slip wheels sit in
// the middle of the picture, the brown terrain line under them.
#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/log/log.h"
#include "scene_support.h"
#include "views/planar_rover_scene.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

constexpr double kRadius = 0.075;

log::Log planar_drive() {
  log::Log lg;
  lg.metadata.extra["truth/wheel_radius_m"] = "0.075";
  const std::vector<double> t = times(10.0, 0.05);
  const std::size_t n = t.size();
  std::vector<double> x(n), z(n, 0.25), zero(n, 0.0), pivot_x(n), pivot_z(n, 0.15);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = 0.1 * t[i];
    pivot_x[i] = x[i] - 0.15;
  }
  log::Stream pose("truth/pose", t);
  pose.add_channel("x", "m", x);
  pose.add_channel("z", "m", z);
  pose.add_channel("pitch", "rad", zero);
  pose.add_channel("bogie_angle", "rad", zero);
  pose.add_channel("bogie_pivot_x", "m", pivot_x);
  pose.add_channel("bogie_pivot_z", "m", pivot_z);
  lg.add_stream(std::move(pose));
  log::Stream wheels("truth/wheels", t);
  const double offset[3] = {0.2, -0.05, -0.25};
  for (int w = 0; w < 3; ++w) {
    std::vector<double> cx(n);
    for (std::size_t i = 0; i < n; ++i) cx[i] = x[i] + offset[w];
    const std::string k = std::to_string(w + 1);
    wheels.add_channel("centre_x_" + k, "m", cx);
    wheels.add_channel("centre_z_" + k, "m", std::vector<double>(n, kRadius));
    wheels.add_channel("slip_" + k, "1", std::vector<double>(n, 0.1));
  }
  lg.add_stream(std::move(wheels));
  return lg;
}

}  // namespace

TEST(PlanarRoverScene, DrawsTheWheelsOnTheTerrainWhereTheLogPutsThem) {
  const log::Log lg = planar_drive();
  ASSERT_TRUE(views::is_planar_rocker_bogie_log(lg));
  views::PlanarRoverScene scene(lg);
  const views::Image img = render_scene(scene, 320, 240, 5.0);
  EXPECT_NEAR(scene.wheel_centre(0).x(), 0.7, 1e-9);
  EXPECT_NEAR(scene.wheel_centre(2).y(), kRadius, 1e-12);
  // Low slip: yellow-green wheels around the middle.
  const Region wheels = find_pixels(img, [](int r, int g, int b) { return g - b > 90 && g >= r && g > 120; });
  EXPECT_GT(wheels.count, 300);
  EXPECT_NEAR(wheels.mean_x, 160, 40);
  // The terrain (0.55, 0.45, 0.3) below their centres.
  const Region terrain = find_pixels(img, [](int r, int g, int b) {
    return std::abs(r - 140) < 25 && std::abs(g - 115) < 25 && std::abs(b - 77) < 25;
  });
  EXPECT_GT(terrain.count, 300);
  EXPECT_GT(terrain.mean_y, wheels.mean_y);
}

TEST(PlanarRoverScene, RefusesALogWithoutTheRockerBogieTruth) {
  EXPECT_FALSE(views::is_planar_rocker_bogie_log(log::Log{}));
  EXPECT_THROW(views::PlanarRoverScene{log::Log{}}, DataError);
}

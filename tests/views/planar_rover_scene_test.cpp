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

namespace {

// The body held still while the bogie turns by 0.3 rad over 10 s: wheel 2
// (extreme slip, red) rises, wheel 3 (low slip) sinks.
log::Log turning_bogie() {
  log::Log lg = planar_drive();
  const auto& t = lg.stream("truth/pose").time();
  const std::size_t n = t.size();
  log::Log out;
  out.metadata = lg.metadata;
  log::Stream pose("truth/pose", t);
  std::vector<double> angle(n), pivot_x(n, -0.15), pivot_z(n, 0.15);
  for (std::size_t i = 0; i < n; ++i) angle[i] = 0.03 * t[i];
  pose.add_channel("x", "m", std::vector<double>(n, 0.0));
  pose.add_channel("z", "m", std::vector<double>(n, 0.25));
  pose.add_channel("pitch", "rad", std::vector<double>(n, 0.0));
  pose.add_channel("bogie_angle", "rad", angle);
  pose.add_channel("bogie_pivot_x", "m", pivot_x);
  pose.add_channel("bogie_pivot_z", "m", pivot_z);
  out.add_stream(std::move(pose));
  log::Stream wheels("truth/wheels", t);
  const Eigen::Vector2d arm[3] = {{0.35, -0.1}, {0.1, -0.075}, {-0.1, -0.075}};  // wheel 1 from the pivot at rest
  for (int w = 0; w < 3; ++w) {
    std::vector<double> cx(n), cz(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double a = w == 0 ? 0.0 : angle[i];  // wheel 1 hangs on the rocker
      cx[i] = -0.15 + std::cos(a) * arm[w].x() - std::sin(a) * arm[w].y();
      cz[i] = 0.15 + std::sin(a) * arm[w].x() + std::cos(a) * arm[w].y();
    }
    const std::string k = std::to_string(w + 1);
    wheels.add_channel("centre_x_" + k, "m", cx);
    wheels.add_channel("centre_z_" + k, "m", cz);
    wheels.add_channel("slip_" + k, "1", std::vector<double>(n, w == 1 ? 0.9 : 0.1));
  }
  out.add_stream(std::move(wheels));
  return out;
}

}  // namespace

TEST(PlanarRoverScene, InThreeDimensionsTheWheelPixelsMoveAsTheBogieTurns) {
  const log::Log lg = turning_bogie();
  views::PlanarRoverScene scene(lg);
  EXPECT_GT(scene.track(), 0.4);  // both sides drawn a wheelbase apart
  const auto red = [](int r, int g, int b) { return r > 180 && g < 80 && b < 80; };
  const auto green = [](int r, int g, int b) { return g - b > 90 && g >= r && g > 120; };
  const views::Image before = render_scene(scene, 480, 360, 0.0);
  const Region red0 = find_pixels(before, red), green0 = find_pixels(before, green);
  const views::Image after = render_scene(scene, 480, 360, 10.0);
  const Region red1 = find_pixels(after, red), green1 = find_pixels(after, green);
  ASSERT_GT(red0.count, 200);  // wheel 2 on both sides
  ASSERT_GT(green0.count, 400);
  // Wheel 2 rose 3.3 cm: its pixels move up (smaller rows); the wheels 1 and 3 (3 sank 1.6 cm) do not follow it.
  EXPECT_LT(red1.mean_y, red0.mean_y - 4.0);
  EXPECT_GT(green1.mean_y, green0.mean_y - 1.0);
  EXPECT_NEAR(scene.wheel_centre(1).y(), 0.15 + std::sin(0.3) * 0.1 - std::cos(0.3) * 0.075, 1e-9);
}

namespace {

// The flat drive with every wheel's contact angle set to `truth` and its
// net-traction estimate to `estimate` (1-sigma 0.05 rad).
log::Log drive_with_contact_angles(double truth, double estimate) {
  const log::Log base = planar_drive();
  log::Log lg;
  lg.metadata = base.metadata;
  lg.add_stream(base.stream("truth/pose"));
  log::Stream wheels = base.stream("truth/wheels");
  const std::vector<double> t = wheels.time();
  const std::size_t n = t.size();
  log::Stream est("estimate/net_traction/wheels", t);
  for (int w = 1; w <= 3; ++w) {
    const std::string k = std::to_string(w);
    wheels.add_channel("contact_angle_" + k, "rad", std::vector<double>(n, truth));
    est.add_channel("contact_angle_" + k, "rad", std::vector<double>(n, estimate));
    est.add_channel("contact_angle_sigma_" + k, "rad", std::vector<double>(n, 0.05));
  }
  lg.add_stream(std::move(wheels));
  lg.add_stream(std::move(est));
  return lg;
}

bool truth_green(int r, int g, int b) { return g > 120 && r < 60 && b < 90; }

}  // namespace

TEST(PlanarRoverScene, TheContactArrowsPointAlongThePathAtTheContactAngle) {
  const log::Log climbing = drive_with_contact_angles(0.4, 0.3), level = drive_with_contact_angles(0.0, 0.0);
  views::PlanarRoverScene climbing_scene(climbing), level_scene(level);
  const views::Image up = render_scene(climbing_scene, 480, 360, 5.0);
  const views::Image flat = render_scene(level_scene, 480, 360, 5.0);
  EXPECT_TRUE(climbing_scene.notes().empty());
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(climbing_scene.contact_direction(i, false).y(), std::sin(0.3), 1e-12);  // forward and up
    EXPECT_NEAR(climbing_scene.contact_direction(i, false).x(), std::cos(0.3), 1e-12);
    EXPECT_NEAR(climbing_scene.contact_direction(i, true).y(), std::sin(0.4), 1e-12);
    EXPECT_NEAR(level_scene.contact_direction(i, true).y(), 0.0, 1e-12);
  }
  // On screen both arrows rise with the contact angle.
  const Region blue_up = find_pixels(up, estimate_blue), blue_flat = find_pixels(flat, estimate_blue);
  const Region green_up = find_pixels(up, truth_green), green_flat = find_pixels(flat, truth_green);
  ASSERT_GT(blue_up.count, 100);
  ASSERT_GT(blue_flat.count, 100);
  ASSERT_GT(green_up.count, 20);
  ASSERT_GT(green_flat.count, 20);
  EXPECT_LT(blue_up.mean_y, blue_flat.mean_y - 3.0);
  EXPECT_LT(green_up.mean_y, green_flat.mean_y - 3.0);
}

TEST(PlanarRoverScene, WithoutAnEstimateNoBlueArrowIsDrawnAndANoteSaysHowToGetOne) {
  const log::Log lg = planar_drive();
  views::PlanarRoverScene scene(lg);
  const views::Image img = render_scene(scene, 480, 360, 5.0);
  ASSERT_EQ(scene.notes().size(), 1U);
  EXPECT_NE(scene.notes()[0].find("estimate net-traction"), std::string::npos);
  EXPECT_TRUE(std::isnan(scene.contact_direction(0, false).x()));
  EXPECT_EQ(find_pixels(img, estimate_blue).count, 0);
}

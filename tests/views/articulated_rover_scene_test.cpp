// The articulated 3D rover on a small ExoMars BB2 log made here: the
// front-left bogie turns from 0 to 0.5 rad, FL slips (red) and its estimated
// contact angle is +-0.5 rad; the wheel moves on screen as its bogie turns and
// the arrow points where the wheel moves.
#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/log/log.h"
#include "importers/rover_file.h"
#include "scene_support.h"
#include "views/articulated_rover_scene.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

const char* const kWheels[] = {"FL", "ML", "RL", "RR", "MR", "FR"};

kinematics::RoverModel bb2() { return *io::load_rover(ROVERLAB_RESOURCES_DIR "/rovers/exomars_bb2.json").dh; }

// Joints over 2 s, bogie_FL 0 until 1 s then 0.5 rad; FL's contact angle
// `fl_angle`, the only one estimated (the others NaN: no arrow).
log::Log bb2_log(double fl_angle) {
  log::Log lg;
  const std::vector<double> t = times(2.0, 0.01);
  log::Stream joints("joints", t);
  for (const auto& name : bb2().joints) {
    std::vector<double> v(t.size(), 0.0);
    if (name == "bogie_FL") {
      for (std::size_t k = 0; k < t.size(); ++k) v[k] = t[k] < 1.0 ? 0.0 : 0.5;
    }
    joints.add_channel(name, "rad", v);
  }
  lg.add_stream(std::move(joints));
  log::Stream estimate("estimate/contact/wheels", t);
  for (const char* w : kWheels) {
    const bool fl = std::string(w) == "FL";
    estimate.add_channel(std::string("contact_angle_") + w, "rad", std::vector<double>(t.size(), fl ? fl_angle : NAN));
    estimate.add_channel(std::string("slip_") + w, "1", std::vector<double>(t.size(), fl ? 1.0 : 0.0));
  }
  lg.add_stream(std::move(estimate));
  return lg;
}

bool slipping_red(int r, int g, int b) { return r > 120 && g < 80 && b < 80; }

}  // namespace

TEST(ArticulatedRoverScene, TheWheelFollowsItsBogieOnScreen) {
  const log::Log lg = bb2_log(0.0);
  views::ArticulatedRoverScene scene(lg, bb2());
  ASSERT_EQ(scene.wheel_centres().size(), 6u);
  const views::Image before = render_scene(scene, 640, 400, 0.5);
  const Eigen::Vector3d fl_before = scene.wheel_centres()[0], rl_before = scene.wheel_centres()[2];
  const views::Image after = render_scene(scene, 640, 400, 1.5);
  const Eigen::Vector3d fl_after = scene.wheel_centres()[0], rl_after = scene.wheel_centres()[2];
  // The bogie's arm is 0.32 m: 0.5 rad moves the wheel by about 0.16 m; the
  // rear bogie's wheels stay.
  EXPECT_NEAR((fl_after - fl_before).norm(), 2.0 * 0.32 * std::sin(0.25), 0.05);
  EXPECT_LT((rl_after - rl_before).norm(), 1e-9);
  const Region red_before = find_pixels(before, slipping_red), red_after = find_pixels(after, slipping_red);
  ASSERT_GT(red_before.count, 200);
  ASSERT_GT(red_after.count, 200);
  EXPECT_GT(std::hypot(red_after.mean_x - red_before.mean_x, red_after.mean_y - red_before.mean_y), 8.0);
}

TEST(ArticulatedRoverScene, TheArrowPointsWhereTheWheelMoves) {
  const log::Log up = bb2_log(0.5), down = bb2_log(-0.5), level = bb2_log(0.0);
  views::ArticulatedRoverScene up_scene(up, bb2()), down_scene(down, bb2()), level_scene(level, bb2());
  const views::Image up_image = render_scene(up_scene, 640, 400, 0.5);
  const views::Image level_image = render_scene(level_scene, 640, 400, 0.5);
  // Up is +z in the body frame: FL's arrow climbs at 0.5 rad, the others are level.
  EXPECT_NEAR(up_scene.contact_directions()[0].z(), std::sin(0.5), 1e-9);
  EXPECT_NEAR(down_scene.contact_directions()[0].z(), -std::sin(0.5), 1e-9);
  EXPECT_TRUE(std::isnan(up_scene.contact_directions()[1].z()));
  EXPECT_GT(up_scene.contact_directions()[0].x(), 0.8);  // forward
  // On screen FL's arrow, the only blue one, sits higher when it points up
  // than when it runs along the ground (pointing down it goes into the ground).
  const Region blue_up = find_pixels(up_image, estimate_blue), blue_level = find_pixels(level_image, estimate_blue);
  ASSERT_GT(blue_up.count, 100);
  ASSERT_GT(blue_level.count, 100);
  EXPECT_LT(blue_up.mean_y, blue_level.mean_y - 5.0);
}

// Issue 32: each wheel named beside it, and the key names only what is
// drawn (this log estimates contact angles only: no side slip, no truth).
TEST(ArticulatedRoverScene, WheelsAreLabelledAndTheKeyListsOnlyWhatIsDrawn) {
  const log::Log lg = bb2_log(0.3);
  views::ArticulatedRoverScene scene(lg, bb2());
  render_scene(scene, 640, 400, 0.5);
  const auto labels = scene.wheel_labels();
  ASSERT_EQ(labels.size(), 6u);
  for (std::size_t w = 0; w < 6; ++w) {
    EXPECT_EQ(labels[w].first, kWheels[w]);
    const Eigen::Vector3d offset = labels[w].second - scene.wheel_centres()[w];
    EXPECT_GT(offset.z(), 0.0) << kWheels[w] << " above its wheel";
    EXPECT_LT(offset.norm(), 0.5) << kWheels[w];
  }
  const std::string caption = scene.caption();
  EXPECT_NE(caption.find("blue: velocity at the estimated contact angle"), std::string::npos) << caption;
  EXPECT_EQ(caption.find("side slip"), std::string::npos) << caption;
  EXPECT_EQ(caption.find("green: truth"), std::string::npos) << caption;
}

TEST(ArticulatedRoverScene, NeedsADhRoverAndItsJoints) {
  const log::Log empty;
  const kinematics::RoverModel model = bb2();
  EXPECT_NE(views::articulated_rover_needs(empty, &model).find("joints"), std::string::npos);
  EXPECT_NE(views::articulated_rover_needs(bb2_log(0.0), nullptr).find("DH"), std::string::npos);
  EXPECT_EQ(views::articulated_rover_needs(bb2_log(0.0), &model), "");
  EXPECT_THROW(views::ArticulatedRoverScene(empty, model), DataError);
}

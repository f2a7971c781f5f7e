// The articulated 3D rover on a small ExoMars BB2 log made here: the
// front-left bogie turns from 0 to 0.5 rad, FL slips (red) and its estimated
// contact angle is +-0.5 rad; the wheel moves on screen as its bogie turns and
// the arrow points where the wheel moves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "core/log/log.h"
#include "core/simulation/flying_rover.h"
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

namespace {

// The strips' centre lines (each pair of vertices across a strip, averaged), per strip in order.
std::vector<Eigen::Vector3d> centre_line(const std::vector<Eigen::Vector3d>& vertices) {
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i + 1 < vertices.size(); i += 2) out.push_back(0.5 * (vertices[i] + vertices[i + 1]));
  return out;
}

}  // namespace

// Issue 32: the wheels touch the ground where the kinematics put them, and
// the bump of the bump-crossing scenario is drawn. The flying BB2 crossing
// its bump (truth contact angles to +-0.6 rad): the ground under each side
// passes through every wheel's contact point, no point of it comes inside a
// wheel, it is flat at the start and rises by centimetres on the bump, and
// the base plane lies below it all. (The old single plane at the wheels' rest
// height had the middle-left wheel 3 cm into it at 6.4 s.)
TEST(ArticulatedRoverScene, WheelsTouchTheGroundAndTheBumpIsDrawn) {
  const kinematics::RoverModel rover = bb2();
  simulation::FlyingRoverScenario scenario = simulation::flying_rover_scenario("bump-crossing", rover);
  scenario.rate = 50.0;
  scenario.noise = false;
  const log::Log lg = simulation::simulate_flying_rover(rover, scenario);
  views::ArticulatedRoverScene scene(lg, rover);
  const double r = rover.wheel_radius;
  double rest_ground = 0.0, largest_rise = 0.0, deepest_below_rest = 0.0;
  for (const double t : {0.0, 6.4, 9.3, 19.0, 22.2, 30.0}) {
    scene.set_time(t);
    const auto strips = scene.ground_strips();
    ASSERT_EQ(strips.size(), 2u);
    std::vector<Eigen::Vector3d> line, vertices;
    std::vector<std::size_t> ends;  // where each strip's centre line ends in `line`
    for (const auto& strip : strips) {
      const auto one = centre_line(strip);
      line.insert(line.end(), one.begin(), one.end());
      vertices.insert(vertices.end(), strip.begin(), strip.end());
      ends.push_back(line.size());
    }
    for (std::size_t w = 0; w < 6; ++w) {
      const Eigen::Vector3d centre = scene.wheel_centres()[w], contact = scene.ground_contacts()[w];
      EXPECT_NEAR((contact - centre).norm(), r, 1e-9);
      double nearest = 1e9;
      for (const auto& p : line) nearest = std::min(nearest, (p - contact).norm());
      EXPECT_LT(nearest, 1e-6) << kWheels[w] << " at t = " << t << ": the ground misses its contact point";
      // (vtkPoints hold floats: a micrometre.) The ground's centre line, sampled every few millimetres near the wheel,
      // stays outside its circle.
      for (std::size_t i = 0; i + 1 < line.size(); ++i) {
        if (std::find(ends.begin(), ends.end(), i + 1) != ends.end()) continue;  // not across two strips
        if (std::abs(line[i].y() - centre.y()) > r) continue;
        for (int s = 0; s <= 40; ++s) {
          const Eigen::Vector3d p = line[i] + (line[i + 1] - line[i]) * (s / 40.0);
          const Eigen::Vector2d in_plane(p.x() - centre.x(), p.z() - centre.z());
          EXPECT_GE(in_plane.norm(), r - 2e-3) << kWheels[w] << " cuts into the ground at t = " << t;
        }
      }
      if (t == 0.0) rest_ground = std::min(rest_ground, centre.z() - r);
      deepest_below_rest = std::max(deepest_below_rest, rest_ground - (centre.z() - r));
    }
    double lo = 1e9, hi = -1e9;
    for (const auto& p : line) {
      if (p.y() < 0) continue;  // the left side crosses the bump
      lo = std::min(lo, p.z());
      hi = std::max(hi, p.z());
    }
    if (t == 0.0) {
      EXPECT_LT(hi - lo, 1e-6) << "flat at the start";
    }
    largest_rise = std::max(largest_rise, hi - lo);
    const std::vector<double> base = scene.base_plane_bounds();
    for (const auto& p : vertices) EXPECT_LT(base[5], p.z()) << "the base plane covers the ground at t = " << t;
  }
  EXPECT_GT(largest_rise, 0.04);        // the bump, drawn
  EXPECT_GT(deepest_below_rest, 0.01);  // what the old plane at rest height cut into
}

// The map scene on a small log made here: GPS and an INS estimate driving
// north, wheel odometry drifting 12 m east of them (the track the chase
// camera of the rover view loses), and slip classes none then high. Read
// from the scene: every track's actor inside what the camera shows, the
// scale bar's round length and its label, the legend naming exactly what is
// drawn, the markers on the tracks at the time; and from the picture.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/log/log.h"
#include "scene_support.h"
#include "views/map_scene.h"
#include "views/offscreen.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

log::Log drive() {
  log::Log lg;
  const std::vector<double> t = times(60.0, 0.1);
  const std::size_t k = t.size();
  std::vector<double> east(k), north(k), odo_east(k), cls(k), ratio(k);
  for (std::size_t i = 0; i < k; ++i) {
    north[i] = 0.5 * t[i];
    east[i] = 0.5 * std::sin(0.1 * t[i]);
    odo_east[i] = 12.0 * (t[i] / 60.0) * (t[i] / 60.0);
    cls[i] = t[i] < 30 ? 0 : 3;
    ratio[i] = t[i] < 30 ? 0.01 : 0.5;
  }
  log::Stream gps("gps", t);
  gps.add_channel("east", "m", east);
  gps.add_channel("north", "m", north);
  lg.add_stream(std::move(gps));
  log::Stream ins("estimate/ins/pose", t);
  ins.add_channel("east", "m", east);
  ins.add_channel("north", "m", north);
  ins.add_channel("yaw", "rad", std::vector<double>(k, 0.0));
  lg.add_stream(std::move(ins));
  log::Stream odo("estimate/odometry/pose", t);
  odo.add_channel("east", "m", odo_east);
  odo.add_channel("north", "m", north);
  lg.add_stream(std::move(odo));
  log::Stream slip("estimate/ins/slip", t);
  slip.add_channel("slip_ratio", "1", ratio);
  slip.add_channel("slip_class", "1", cls);
  lg.add_stream(std::move(slip));
  return lg;
}

bool inside(const views::MapRect& in, const views::MapRect& out) {
  return in[0] >= out[0] && in[1] >= out[1] && in[2] <= out[2] && in[3] <= out[3];
}

}  // namespace

// Every track whole in a landscape and in a portrait window: the camera is
// fitted to the window's shape, not a fixed one.
TEST(MapScene, ShowsEveryTrackWholeInAnyWindowShape) {
  const log::Log lg = drive();
  views::MapScene scene(lg);
  EXPECT_EQ(scene.sources(), (std::vector<std::string>{"estimate/ins/pose", "estimate/odometry/pose", "gps"}));
  views::ensure_display();
  for (const auto& [w, h] : {std::pair{1400, 900}, {500, 900}, {1400, 300}}) {
    auto window = views::make_offscreen_window(w, h);
    scene.attach(window);
    scene.fit_width(w);
    const views::MapRect shown = scene.visible();
    for (std::size_t k = 0; k < scene.sources().size(); ++k) {
      const views::MapRect b = scene.track_bounds(k);
      EXPECT_TRUE(inside(b, shown)) << scene.sources()[k] << " in " << w << "x" << h << ": track " << b[0] << ".."
                                    << b[2] << " x " << b[1] << ".." << b[3] << ", shown " << shown[0] << ".."
                                    << shown[2] << " x " << shown[1] << ".." << shown[3];
    }
    // The odometry reaches 12 m east: the shown width covers it.
    EXPECT_NEAR(scene.track_bounds(1)[2], 12.0, 1e-9);
    // The scale bar: 1, 2 or 5 times a power of ten, a tenth to a quarter of the width, labelled.
    const double len = scene.scale_length(), decade = std::pow(10.0, std::floor(std::log10(len)));
    const double mantissa = len / decade;
    EXPECT_TRUE(std::abs(mantissa - 1) < 1e-9 || std::abs(mantissa - 2) < 1e-9 || std::abs(mantissa - 5) < 1e-9) << len;
    const double width = shown[2] - shown[0];
    EXPECT_GE(len, 0.08 * width);
    EXPECT_LE(len, 0.2 * width + 1e-9);
    char label[32];
    std::snprintf(label, sizeof label, "%g m", len);
    EXPECT_EQ(scene.scale_text(), label);
    scene.detach(window);
  }
}

TEST(MapScene, LegendNamesWhatIsDrawnAndMarkersFollowTheTime) {
  const log::Log lg = drive();
  views::MapScene scene(lg);
  // Tracks in their order, then only the slip classes along the path (none and high).
  EXPECT_EQ(scene.legend_entries(),
            (std::vector<std::string>{"INS estimate", "wheel odometry", "GPS", "slip none", "slip high"}));
  const auto segments = scene.slip_segments();
  EXPECT_GT(segments[0], 250);
  EXPECT_GT(segments[3], 250);
  EXPECT_EQ(segments[1] + segments[2] + segments[4], 0);
  const views::Image img = render_scene(scene, 1400, 900, 45.0);
  // At t = 45 s the markers sit on each track: north 22.5 m, odometry 6.75 m east.
  EXPECT_NEAR(scene.marker(0).y(), 22.5, 1e-6);
  EXPECT_NEAR(scene.marker(1).x(), 12.0 * 0.75 * 0.75, 1e-6);
  EXPECT_NEAR(scene.marker(2).x(), 0.5 * std::sin(4.5), 1e-6);
  // The picture: purple odometry pixels (apart from the slip classes' colours) well right of the blue
  // INS track, both in the map (the window's left 78 %).
  const Region purple = find_pixels(
      img, [](int r, int g, int b) { return r > 110 && r < 170 && g < 80 && b > 160; }, 0, 1090, 0, 900);
  const Region blue = find_pixels(
      img, [](int r, int g, int b) { return b > 170 && r < 60 && g < 120; }, 0, 1090, 0, 900);
  EXPECT_GT(purple.count, 200);
  EXPECT_GT(blue.count, 200);
  EXPECT_GT(purple.mean_x - blue.mean_x, 60);  // about 4 m east on average, 25 pixels a metre
}

TEST(MapScene, SaysWhyALogWithoutPositionCannotBeMapped) {
  log::Log lg;
  log::Stream body("truth/body", times(1.0, 0.1));
  body.add_channel("velocity_x", "m/s", std::vector<double>(11, 0.05));
  lg.add_stream(std::move(body));
  EXPECT_NE(views::map_needs(lg).find("no position to map"), std::string::npos);
  EXPECT_EQ(views::map_needs(drive()), "");
  const views::View* map = views::find_view("map");
  ASSERT_NE(map, nullptr);
  views::SceneInput in;
  in.log = &lg;
  EXPECT_EQ(map->needs(in), views::map_needs(lg));
}

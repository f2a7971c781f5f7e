// The scatter view (issue 44 item 5) on small logs made here: a plate's
// force against its depth (one stream), and a channel of one stream against
// one of another (interpolated to the first's times).
#include <gtest/gtest.h>

#include <vtkAxis.h>
#include <vtkChartXY.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/log/log.h"
#include "scene_support.h"
#include "views/scatter_scene.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

// Depth 0..0.05 m over 10 s, force = 2e5 * depth^1.1 N, one sample NaN.
log::Log plate() {
  log::Log lg;
  const std::vector<double> t = times(10.0, 0.1);
  std::vector<double> depth(t.size()), force(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    depth[i] = 0.005 * t[i];
    force[i] = 2e5 * std::pow(depth[i], 1.1);
  }
  force[40] = std::numeric_limits<double>::quiet_NaN();
  log::Stream s("plate", t);
  s.add_channel("depth", "m", depth);
  s.add_channel("force", "N", force);
  lg.add_stream(std::move(s));
  return lg;
}

bool blue(int r, int g, int b) { return b > 140 && r < 90 && g < 160; }

}  // namespace

TEST(ScatterScene, DrawsEveryFinitePairInsideItsAxesRisingAsTheForceDoes) {
  const log::Log lg = plate();
  views::ScatterScene scene(lg, {"plate", "depth"}, {"plate", "force"});
  const auto& p = scene.points();
  ASSERT_EQ(p.x.size(), lg.stream("plate").size() - 1);  // the NaN force left out
  EXPECT_FALSE(p.interpolated);
  for (std::size_t i = 0; i < p.x.size(); ++i) EXPECT_NEAR(p.y[i], 2e5 * std::pow(p.x[i], 1.1), 1e-9 * p.y[i] + 1e-12);
  vtkAxis* bottom = scene.chart()->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* left = scene.chart()->GetAxis(vtkAxis::LEFT);
  EXPECT_EQ(std::string(bottom->GetTitle()), "plate:depth (m)");
  EXPECT_EQ(std::string(left->GetTitle()), "plate:force (N)");
  const double fmax = 2e5 * std::pow(0.05, 1.1);
  EXPECT_LT(bottom->GetMinimum(), 0.0);
  EXPECT_GT(bottom->GetMaximum(), 0.05);
  EXPECT_LT(left->GetMinimum(), 0.0);
  EXPECT_GT(left->GetMaximum(), fmax);
  EXPECT_LT(left->GetMaximum(), 1.2 * fmax);  // the range is the data's, not a default
  EXPECT_EQ(scene.notes().size(), 1u);        // "100 of 101 samples drawn"

  const views::Image img = render_scene(scene, 400, 300);
  const Region left_half = find_pixels(img, blue, 0, 200);
  const Region right_half = find_pixels(img, blue, 200, 400);
  ASSERT_GT(left_half.count, 0);
  ASSERT_GT(right_half.count, 0);
  // Rows count from the top: the deeper points, with more force, sit higher.
  EXPECT_LT(right_half.mean_y + 50, left_half.mean_y);
}

TEST(ScatterScene, InterpolatesAnotherStreamsChannelToTheXTimesInsideItsSpan) {
  log::Log lg;
  const std::vector<double> t = times(10.0, 0.1);
  log::Stream a("wheels", t);
  a.add_channel("speed", "m/s", t);  // speed = t
  lg.add_stream(std::move(a));
  std::vector<double> u, slip;
  for (int k = 0; k <= 18; ++k) {  // 2 .. 8 s at 3 Hz
    u.push_back(2.0 + k / 3.0);
    slip.push_back(0.5 * u.back());
  }
  log::Stream b("estimate", u);
  b.add_channel("slip", "1", slip);
  lg.add_stream(std::move(b));
  views::ScatterScene scene(lg, {"wheels", "speed"}, {"estimate", "slip"});
  const auto& p = scene.points();
  EXPECT_TRUE(p.interpolated);
  ASSERT_FALSE(p.x.empty());
  for (std::size_t i = 0; i < p.x.size(); ++i) {
    EXPECT_GE(p.x[i], 2.0 - 1e-9);
    EXPECT_LE(p.x[i], u.back() + 1e-9);
    EXPECT_NEAR(p.y[i], 0.5 * p.x[i], 1e-12);  // linear in time, so exact
  }
  const auto inside = std::count_if(t.begin(), t.end(), [&](double ti) { return ti >= u.front() && ti <= u.back(); });
  EXPECT_EQ(p.x.size(), static_cast<std::size_t>(inside));  // 60 or 61 as 8.0 rounds: every one inside
  EXPECT_GE(p.x.size(), 60u);
  EXPECT_EQ(std::string(scene.chart()->GetAxis(vtkAxis::LEFT)->GetTitle()), "estimate:slip");
  ASSERT_FALSE(scene.notes().empty());
  EXPECT_NE(scene.notes().front().find("interpolated"), std::string::npos);
}

TEST(ScatterView, SaysWhatItNeeds) {
  const log::Log lg = plate();
  const views::View* view = views::find_view("scatter");
  ASSERT_NE(view, nullptr);
  EXPECT_TRUE(view->plots_channel_pair());
  views::SceneInput in;
  in.log = &lg;
  EXPECT_NE(view->needs(in).find("--x"), std::string::npos);
  in.channels = {{"plate", "depth"}, {"plate", "torque"}};
  EXPECT_NE(view->needs(in).find("no channel 'torque'"), std::string::npos);
  in.channels = {{"plate", "depth"}, {"plate", "force"}};
  EXPECT_EQ(view->needs(in), "");
  EXPECT_NE(view->build(in), nullptr);
}

// The time-series chart on a small log made here: a step from 1 down to 0
// at 5 s (the legend sits top right); the line is drawn lower after the
// step, the cursor at its time.
#include <gtest/gtest.h>

#include <vtkAxis.h>
#include <vtkChartXY.h>

#include <cmath>

#include "core/log/log.h"
#include "scene_support.h"
#include "views/timeseries_chart.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

log::Log step() {
  log::Log lg;
  const std::vector<double> t = times(10.0, 0.01);
  std::vector<double> x(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) x[i] = t[i] < 5.0 ? 1.0 : 0.0;
  log::Stream s("step", t);
  s.add_channel("x", "m", x);
  lg.add_stream(std::move(s));
  return lg;
}

}  // namespace

TEST(TimeSeriesChart, DrawsTheStepWhereItsDataIsAndTheCursorAtItsTime) {
  const log::Log lg = step();
  views::TimeSeriesChart chart(lg, views::default_channels(lg));
  ASSERT_EQ(chart.plot_count(), 1u);
  const views::Image img = render_scene(chart, 320, 240, 7.5);
  EXPECT_DOUBLE_EQ(chart.chart(0)->GetAxis(vtkAxis::BOTTOM)->GetMinimum(), 0.0);
  EXPECT_DOUBLE_EQ(chart.chart(0)->GetAxis(vtkAxis::BOTTOM)->GetMaximum(), 10.0);
  EXPECT_LE(chart.drawn_points().at(0), 2u * 320u);  // decimated to the window's width
  // The first plot colour, (31, 119, 180), left and right of the middle.
  auto line = [](int r, int g, int b) {
    return std::abs(r - 31) < 40 && std::abs(g - 119) < 40 && std::abs(b - 180) < 40;
  };
  const Region left = find_pixels(img, line, 0, 120), right = find_pixels(img, line, 200, 320);
  ASSERT_GT(left.count, 20);
  ASSERT_GT(right.count, 20);
  EXPECT_GT(right.mean_y - left.mean_y, 60.0);  // after the step the line is far lower on screen
  // The cursor: the column with the most black pixels right of the value axis (x = 50).
  int best_x = -1, best = 0;
  for (int x = img.width / 4; x < img.width; ++x) {
    const int k = find_pixels(
                      img, [](int r, int g, int b) { return r < 40 && g < 40 && b < 40; }, x, x + 1)
                      .count;
    if (k > best) {
      best = k;
      best_x = x;
    }
  }
  EXPECT_GT(best, 80);
  EXPECT_NEAR(best_x, 0.75 * img.width, 0.12 * img.width);
}

// Issue 32: a value axis names its quantity, not only the unit ("(1)" said nothing).
TEST(TimeSeriesChart, ValueAxesNameTheirQuantityAndUnit) {
  log::Log lg;
  const std::vector<double> t = times(1.0, 0.1);
  log::Stream imu("imu", t);
  for (const char* axis : {"x", "y", "z"}) imu.add_channel(std::string("angular_rate_") + axis, "rad/s", t);
  imu.add_channel("specific_force_z", "m/s^2", t);
  lg.add_stream(std::move(imu));
  log::Stream slip("estimate/ins/slip", t);
  slip.add_channel("slip_ratio", "1", t);
  slip.add_channel("reference_slip", "1", t);
  lg.add_stream(std::move(slip));
  views::TimeSeriesChart chart(lg, {{"imu", "angular_rate_x"},
                                    {"imu", "angular_rate_z"},
                                    {"imu", "specific_force_z"},
                                    {"estimate/ins/slip", "slip_ratio"},
                                    {"estimate/ins/slip", "reference_slip"}});
  ASSERT_EQ(chart.plot_count(), 3u);
  EXPECT_EQ(chart.y_title(0), "angular rate (rad/s)");
  EXPECT_EQ(chart.y_title(1), "specific force (m/s^2)");
  EXPECT_EQ(chart.y_title(2), "slip ratio, reference slip");
  EXPECT_EQ(chart.chart(0)->GetAxis(vtkAxis::LEFT)->GetTitle(), "angular rate (rad/s)");
  EXPECT_EQ(chart.chart(2)->GetAxis(vtkAxis::LEFT)->GetTitle(), "slip ratio, reference slip");
}

TEST(TimeSeriesChart, ItsViewResetsItWithOtherChannelsInTheSameContextView) {
  const log::Log lg = step();
  const views::View* plots = nullptr;
  for (const auto& v : views::all_views()) {
    if (v->uses_channels()) plots = v.get();
  }
  ASSERT_NE(plots, nullptr);
  views::SceneInput in;
  in.log = &lg;
  ASSERT_EQ(plots->needs(in), "");
  const std::unique_ptr<views::Scene> scene = plots->build(in);
  auto* chart = dynamic_cast<views::TimeSeriesChart*>(scene.get());
  ASSERT_NE(chart, nullptr);
  EXPECT_EQ(chart->channels().size(), 1u);  // the log's default
  EXPECT_DOUBLE_EQ(chart->default_time(), 0.0);
  vtkContextView* view = chart->view();
  in.channels = {{"step", "x"}, {"step", "x"}};
  ASSERT_TRUE(plots->resets_scene());
  ASSERT_TRUE(plots->reset(*scene, in));
  EXPECT_EQ(chart->view(), view);
  EXPECT_EQ(chart->channels().size(), 2u);
}

// The time-series chart on a small log made here: a step from 1 down to 0
// at 5 s (the legend sits top right); the line is drawn lower after the
// step, the cursor at its time.
#include <gtest/gtest.h>

#include <vtkAxis.h>
#include <vtkChartXY.h>
#include <vtkContextMouseEvent.h>
#include <vtkPlot.h>
#include <vtkRect.h>

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

// Issue 44: a ROS field path keeps its underscores ("position.robot joint" named no joint).
TEST(TimeSeriesChart, RosFieldPathsKeepTheirUnderscores) {
  log::Log lg;
  const std::vector<double> t = times(1.0, 0.1);
  log::Stream joints("joint_states", t);
  joints.add_channel("position.robot_joint", "rad", t);
  lg.add_stream(std::move(joints));
  views::TimeSeriesChart chart(lg, {{"joint_states", "position.robot_joint"}});
  EXPECT_EQ(chart.y_title(0), "position.robot_joint (rad)");
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
  // The cursor starts mid-log, as render --help says for every view.
  EXPECT_DOUBLE_EQ(chart->default_time(), 0.5 * (chart->start_time() + chart->end_time()));
  EXPECT_GT(chart->default_time(), chart->start_time());
  vtkContextView* view = chart->view();
  in.channels = {{"step", "x"}, {"step", "x"}};
  ASSERT_TRUE(plots->resets_scene());
  ASSERT_TRUE(plots->reset(*scene, in));
  EXPECT_EQ(chart->view(), view);
  EXPECT_EQ(chart->channels().size(), 2u);
}

// Issue 32: the default plot is chosen for what it shows, not the first
// stream's raw channels: an estimate against its truth (the truth that
// changes: a flat contact angle is passed over for the drawbar pull), drawn
// with its +-1 sigma band, whose area holds estimate - sigma .. estimate + sigma;
// without truth, an estimate against the reference in its stream.
TEST(TimeSeriesChart, TheDefaultPlotIsAnEstimateAgainstTruthWithItsBand) {
  log::Log lg;
  const std::vector<double> t = times(10.0, 0.1);
  log::Stream imu("imu", t);
  imu.add_channel("pitch_rate", "rad/s", t);
  lg.add_stream(std::move(imu));
  std::vector<double> pull(t.size()), sigma(t.size(), 0.5), flat(t.size(), 0.0);
  for (std::size_t k = 0; k < t.size(); ++k) pull[k] = std::sin(t[k]);
  log::Stream estimate("estimate/net_traction/wheels", t);
  estimate.add_channel("contact_angle_1", "rad", flat);
  estimate.add_channel("drawbar_pull_1", "N", pull);
  estimate.add_channel("drawbar_pull_sigma_1", "N", sigma);
  lg.add_stream(std::move(estimate));
  log::Stream truth("truth/wheels", t);
  truth.add_channel("contact_angle_1", "rad", flat);
  truth.add_channel("drawbar_pull_1", "N", pull);
  lg.add_stream(std::move(truth));
  const std::vector<views::ChannelRef> shown = views::default_channels(lg);
  ASSERT_EQ(shown.size(), 2u);
  EXPECT_EQ(shown[0].stream, "estimate/net_traction/wheels");
  EXPECT_EQ(shown[0].channel, "drawbar_pull_1");
  EXPECT_EQ(shown[1].stream, "truth/wheels");
  EXPECT_EQ(shown[1].channel, "drawbar_pull_1");
  views::TimeSeriesChart chart(lg, shown);
  ASSERT_EQ(chart.band_count(), 1u);
  // The value axis holds the band: -1 - 0.5 .. 1 + 0.5, padded.
  EXPECT_LT(chart.chart(0)->GetAxis(vtkAxis::LEFT)->GetMinimum(), -1.45);
  EXPECT_GT(chart.chart(0)->GetAxis(vtkAxis::LEFT)->GetMaximum(), 1.45);
  EXPECT_EQ(views::sigma_channel_of(lg.stream("estimate/net_traction/wheels"), "drawbar_pull_1"),
            "drawbar_pull_sigma_1");
  const views::Image img = render_scene(chart, 320, 240, 5.0);
  // The band's light blue (first colour at alpha 70 on white) is drawn.
  const Region band = find_pixels(img, [](int r, int g, int b) { return r > 150 && r < 215 && b > 200 && g > 190; });
  EXPECT_GT(band.count, 200);

  log::Log ins;
  log::Stream raw("imu", t);
  raw.add_channel("pitch_rate", "rad/s", t);
  ins.add_stream(std::move(raw));
  log::Stream slip("estimate/ins/slip", t);
  slip.add_channel("standstill", "1", t);
  slip.add_channel("slip_ratio", "1", t);
  slip.add_channel("reference_slip", "1", t);
  ins.add_stream(std::move(slip));
  const std::vector<views::ChannelRef> ins_shown = views::default_channels(ins);
  ASSERT_EQ(ins_shown.size(), 2u);
  EXPECT_EQ(ins_shown[0].channel, "slip_ratio");
  EXPECT_EQ(ins_shown[1].channel, "reference_slip");
}

namespace {

// 10 s at 100 Hz: s:distance = 2 t (m) and s:area = t^2 (m^2).
log::Log distance_and_area() {
  log::Log lg;
  const std::vector<double> t = times(10.0, 0.01);
  std::vector<double> ramp(t.size()), square(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    ramp[k] = 2.0 * t[k];
    square[k] = t[k] * t[k];
  }
  log::Stream s("s", t);
  s.add_channel("distance", "m", ramp);
  s.add_channel("area", "m^2", square);
  lg.add_stream(std::move(s));
  return lg;
}

}  // namespace

// Issue 32: the cursor reads every curve's value at its time (in the legend),
// and zoom is linked: the mouse wheel over one plot zooms every plot's time axis.
TEST(TimeSeriesChart, TheCursorReadsEveryCurveAndZoomIsLinkedAcrossPlots) {
  const log::Log lg = distance_and_area();
  views::TimeSeriesChart chart(lg, {{"s", "distance"}, {"s", "area"}});
  ASSERT_EQ(chart.plot_count(), 2u);
  (void)render_scene(chart, 480, 360, 2.505);
  const auto now = chart.readout();
  ASSERT_EQ(now.size(), 2u);
  EXPECT_NEAR(now[0].value, 5.01, 1e-9);           // between samples: linear
  EXPECT_NEAR(now[1].value, 2.505 * 2.505, 1e-4);  // (the square, linear between 2.50 and 2.51)
  EXPECT_EQ(now[1].unit, "m^2");
  EXPECT_NE(std::string(chart.chart(0)->GetPlot(0)->GetLabel()).find("distance (m) = 5.01"), std::string::npos)
      << chart.chart(0)->GetPlot(0)->GetLabel();
  EXPECT_NE(std::string(chart.chart(1)->GetPlot(0)->GetLabel()).find("area (m^2) = 6.27"), std::string::npos)
      << chart.chart(1)->GetPlot(0)->GetLabel();

  // The wheel over the lower plot, in its middle.
  vtkChartXY* lower = chart.chart(1);
  vtkContextMouseEvent wheel;
  const vtkRectf area(lower->GetPoint1()[0], lower->GetPoint1()[1], lower->GetPoint2()[0] - lower->GetPoint1()[0],
                      lower->GetPoint2()[1] - lower->GetPoint1()[1]);
  wheel.SetScreenPos(vtkVector2i(static_cast<int>(area.GetX() + area.GetWidth() / 2),
                                 static_cast<int>(area.GetY() + area.GetHeight() / 2)));
  wheel.SetPos(vtkVector2f(area.GetX() + area.GetWidth() / 2, area.GetY() + area.GetHeight() / 2));
  ASSERT_TRUE(lower->MouseWheelEvent(wheel, 3));
  const double lo = lower->GetAxis(vtkAxis::BOTTOM)->GetMinimum(), hi = lower->GetAxis(vtkAxis::BOTTOM)->GetMaximum();
  EXPECT_LT(hi - lo, 9.0);  // zoomed in
  EXPECT_DOUBLE_EQ(chart.chart(0)->GetAxis(vtkAxis::BOTTOM)->GetMinimum(), lo);
  EXPECT_DOUBLE_EQ(chart.chart(0)->GetAxis(vtkAxis::BOTTOM)->GetMaximum(), hi);
  EXPECT_DOUBLE_EQ(chart.window().first, lo);
  EXPECT_DOUBLE_EQ(chart.window().second, hi);
}

namespace {

// The mouse wheel over the middle of plot `c` (delta > 0 zooms in), as vtkChartXY takes it.
void wheel_over(vtkChartXY* c, int delta) {
  vtkContextMouseEvent wheel;
  const float x = 0.5f * (c->GetPoint1()[0] + c->GetPoint2()[0]), y = 0.5f * (c->GetPoint1()[1] + c->GetPoint2()[1]);
  wheel.SetScreenPos(vtkVector2i(static_cast<int>(x), static_cast<int>(y)));
  wheel.SetPos(vtkVector2f(x, y));
  ASSERT_TRUE(c->MouseWheelEvent(wheel, delta));
}

std::pair<double, double> value_range(vtkChartXY* c) {
  return {c->GetAxis(vtkAxis::LEFT)->GetMinimum(), c->GetAxis(vtkAxis::LEFT)->GetMaximum()};
}

}  // namespace

// Issue 32: linked zoom shares the time axis only. The user's own value zoom
// on one plot stays when another plot's zoom moves the time window (it was
// fitted to the data again); a plot the user has not zoomed fits the data in
// the window; zoom_to_fit gives the whole range and fitted values back.
TEST(TimeSeriesChart, LinkedZoomSharesTheTimeAxisOnlyAndKeepsTheUsersValueZoom) {
  const log::Log lg = distance_and_area();
  views::TimeSeriesChart chart(lg, {{"s", "distance"}, {"s", "area"}});
  (void)render_scene(chart, 480, 360, 2.0);
  vtkChartXY *upper = chart.chart(0), *lower = chart.chart(1);
  EXPECT_FALSE(chart.value_axis_set_by_user(0));
  EXPECT_FALSE(chart.value_axis_set_by_user(1));
  std::vector<std::pair<double, double>> windows;
  chart.on_user_window([&](double a, double b) { windows.emplace_back(a, b); });

  // The user zooms the lower plot: its time and value axes (vtkChartXY zooms both).
  wheel_over(lower, 2);
  ASSERT_TRUE(chart.value_axis_set_by_user(1));
  EXPECT_FALSE(chart.value_axis_set_by_user(0)) << "the upper plot only follows the time axis";
  const auto users = value_range(lower);
  EXPECT_LT(users.second - users.first, 0.7 * 100.0) << "zoomed in on the values (0..100 m^2)";
  ASSERT_FALSE(windows.empty());
  EXPECT_DOUBLE_EQ(windows.back().first, chart.window().first);
  EXPECT_DOUBLE_EQ(windows.back().second, chart.window().second);

  // Then the upper plot is panned in time through its time axis: both plots
  // show the new window; the lower keeps the user's values, the upper fits
  // its ramp (2 t) in the window, 5 % padded.
  vtkAxis* time = upper->GetAxis(vtkAxis::BOTTOM);
  time->SetRange(6.0, 8.0);
  EXPECT_DOUBLE_EQ(chart.window().first, 6.0);
  EXPECT_DOUBLE_EQ(chart.window().second, 8.0);
  EXPECT_DOUBLE_EQ(lower->GetAxis(vtkAxis::BOTTOM)->GetMinimum(), 6.0);
  EXPECT_DOUBLE_EQ(value_range(lower).first, users.first);
  EXPECT_DOUBLE_EQ(value_range(lower).second, users.second);
  EXPECT_NEAR(value_range(upper).first, 12.0 - 0.2, 0.05);
  EXPECT_NEAR(value_range(upper).second, 16.0 + 0.2, 0.05);
  EXPECT_DOUBLE_EQ(windows.back().first, 6.0);

  // Redrawn at another width (a pane resized): the window stays.
  chart.fit_width(300);
  EXPECT_DOUBLE_EQ(chart.window().first, 6.0);
  EXPECT_DOUBLE_EQ(value_range(lower).second, users.second);

  // Zoom to fit: the whole time range, both value axes on their data again.
  chart.zoom_to_fit();
  EXPECT_FALSE(chart.value_axis_set_by_user(1));
  EXPECT_DOUBLE_EQ(chart.window().first, 0.0);
  EXPECT_DOUBLE_EQ(chart.window().second, 10.0);
  EXPECT_NEAR(value_range(lower).first, -5.0, 1e-9);  // 0..100, 5 % padded
  EXPECT_NEAR(value_range(lower).second, 105.0, 1e-9);
}

// The value axis's title is whole (issue 32: the rover study's disagreement
// plot cut it): with tick labels as wide as "-0.0011" the left margin grows
// past vtkChartMatrix's fixed 50 px, so the turned title "wheel angle (rad)"
// is drawn clear of the window's edge, not under it.
TEST(TimeSeriesChart, TheValueAxisTitleIsWholeBesideWideTickLabels) {
  log::Log lg;
  const std::vector<double> t = times(30.0, 0.02);
  std::vector<double> v(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) v[i] = -0.00038 * t[i];
  log::Stream joints("joints", t);
  joints.add_channel("wheel_angle_3", "rad", v);
  lg.add_stream(std::move(joints));
  views::TimeSeriesChart chart(lg, {{"joints", "wheel_angle_3"}});
  const views::Image img = render_scene(chart, 1280, 400);
  EXPECT_GT(chart.left_border(), 50);
  const auto dark = [](int r, int g, int b) { return r < 110 && g < 110 && b < 110; };
  // Nothing of the title on the window's first columns; the title's letters a little further in.
  EXPECT_EQ(find_pixels(img, dark, 0, 3).count, 0);
  EXPECT_GT(find_pixels(img, dark, 3, 30).count, 40);
  // The tick labels right of the title, left of the axis.
  EXPECT_GT(find_pixels(img, dark, 30, chart.left_border() - 4).count, 40);
}

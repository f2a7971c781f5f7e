// The lab test views (views/panel_figure_scene.cpp) drawn: each panel's
// points in their group's colour inside its own panel, the band around the
// curve tinted, and a view without its figure saying why.
#include <gtest/gtest.h>

#include "scene_support.h"
#include "views/panel_figure.h"
#include "views/view.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

// Two panels in one row: the left holds group 0's points (blue) on a rising
// curve with a band, the right group 1's (red) on a flat curve.
views::PanelFigure two_panels() {
  views::PanelFigure f;
  f.caption = "test figure";
  f.x_title = "slip";
  f.group_names = {"blue wheel", "red wheel"};
  views::PanelRow row;
  row.y_title = "drawbar pull (N)";
  views::PanelSeries left, right;
  left.group = 0;
  left.band = 3.0;
  right.group = 1;
  for (int i = 0; i <= 10; ++i) {
    const double s = -0.5 + 0.1 * i;
    left.x.push_back(s);
    left.y.push_back(20.0 * s);
    left.curve_x.push_back(s);
    left.curve_y.push_back(20.0 * s);
    right.x.push_back(s);
    right.y.push_back(-5.0);
    right.curve_x.push_back(s);
    right.curve_y.push_back(i == 5 ? NAN : -5.0);  // the model has no value there: the curve breaks
  }
  row.panels.push_back({"slip angle 0 deg", {left}});
  row.panels.push_back({"slip angle 30 deg", {right}});
  f.rows.push_back(row);
  return f;
}

const views::View& view_named(const std::string& name) {
  const views::View* v = views::find_view(name);
  if (v == nullptr) throw std::logic_error("no view " + name);
  return *v;
}

}  // namespace

TEST(PanelFigureScene, EachPanelHoldsItsGroupsPointsInTheirColour) {
  views::SceneInput in;
  in.lab = views::LabFigures{};
  in.lab->slip_panels = two_panels();
  const views::View& view = view_named("slip-panels");
  ASSERT_TRUE(view.uses_lab_figures());
  ASSERT_EQ(view.needs(in), "");
  const std::unique_ptr<views::Scene> scene = view.build(in);
  EXPECT_FALSE(scene->follows_time());
  const views::Image img = render_scene(*scene, 800, 500);
  // Group 0 is (31, 119, 180), group 1 (214, 39, 40).
  const auto blue = [](int r, int g, int b) { return b > 150 && r < 70 && g > 90 && g < 150; };
  const auto red = [](int r, int g, int b) { return r > 180 && g < 70 && b < 70; };
  const Region left_blue = find_pixels(img, blue, 0, 400, 110, 500);
  const Region right_red = find_pixels(img, red, 400, 800, 110, 500);
  EXPECT_GT(left_blue.count, 100);
  EXPECT_GT(right_red.count, 100);
  EXPECT_LT(find_pixels(img, red, 0, 400, 110, 500).count, 5);  // each group in its own panel
  EXPECT_LT(find_pixels(img, blue, 400, 800, 110, 500).count, 5);
  // The rising points climb to the right: their upper half lies right of their lower half.
  const Region upper = find_pixels(img, blue, 0, 400, 110, static_cast<int>(left_blue.mean_y));
  const Region lower = find_pixels(img, blue, 0, 400, static_cast<int>(left_blue.mean_y), 500);
  EXPECT_GT(upper.mean_x, lower.mean_x + 40.0);
  // The band: a light tint of the group's blue around the curve.
  const auto tint = [](int r, int g, int b) { return b > 220 && r > 190 && r < 235 && g > 210 && g < 240; };
  EXPECT_GT(find_pixels(img, tint, 0, 400, 110, 500).count, 1000);
}

TEST(PanelFigureScene, AViewWithoutItsFigureSaysWhy) {
  views::SceneInput in;
  EXPECT_NE(view_named("force-depth").needs(in), "");
  in.lab = views::LabFigures{};
  in.lab->slip_panels = two_panels();
  in.lab->why_not = "a single-wheel test, not a plate test";
  EXPECT_EQ(view_named("force-depth").needs(in), "a single-wheel test, not a plate test");
  EXPECT_EQ(view_named("slip-angle-residuals").needs(in), "a single-wheel test, not a plate test");
}

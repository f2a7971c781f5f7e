// The traction-surface scene on a plane made here, DP = -20 + 100 s N: the
// surface spans the colour map from blue (low slip) to red (high slip), the
// measured points are drawn dark, and the scene does not follow time.
#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkCubeAxesActor.h>
#include <vtkDoubleArray.h>
#include <vtkPropCollection.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "scene_support.h"
#include "views/offscreen.h"
#include "views/traction_surface_scene.h"
#include "views/x_display.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

views::TractionSurfaceData plane() {
  views::TractionSurfaceData d;
  d.surface = terramechanics::PolynomialSurface(1, {-20.0, 100.0, 0.0});  // p00 + p10 s + p01 W
  d.load_min = 50;
  d.load_max = 150;
  for (double s : {0.1, 0.5, 1.0}) d.points.push_back({100.0, s, -20.0 + 100.0 * s + 5.0});
  return d;
}

}  // namespace

TEST(TractionSurfaceScene, SpansItsColourMapWithTheMeasuredPoints) {
  const views::TractionSurfaceData d = plane();
  const views::TractionSurfaceScene surface = views::make_traction_surface_scene(d);
  EXPECT_DOUBLE_EQ(surface.value_min, -20.0);
  EXPECT_DOUBLE_EQ(surface.value_max, 85.0);  // the highest point, above the surface
  // Surface, points and residual lines are three actors (and the cube axes).
  EXPECT_GE(surface.renderer->GetActors()->GetNumberOfItems(), 3);
  double bounds[6];
  surface.renderer->ComputeVisiblePropBounds(bounds);
  EXPECT_LE(bounds[0], 0.0);
  EXPECT_GE(bounds[1], 1.0);
  views::SceneInput in;
  in.surface = d;
  const views::View* view = nullptr;
  for (const auto& v : views::all_views()) {
    if (v->uses_surface_data()) view = v.get();
  }
  ASSERT_NE(view, nullptr);
  ASSERT_EQ(view->needs(in), "");
  const std::unique_ptr<views::Scene> scene = view->build(in);
  EXPECT_FALSE(scene->follows_time());
  const views::Image img = render_scene(*scene, 320, 240);
  const Region red = find_pixels(img, [](int r, int g, int b) { return r > 170 && g < 110 && b < 110; });
  const Region blue = find_pixels(img, [](int r, int g, int b) { return b > 170 && r < 120 && g < 150; });
  const Region dark = find_pixels(img, [](int r, int g, int b) { return r < 40 && g < 40 && b < 40; });
  EXPECT_GT(red.count, 300);
  EXPECT_GT(blue.count, 300);
  EXPECT_GT(dark.count, 30);  // points, residuals and axis text
}

// Issue 32: the colour bar's values are round (they were its range in fifths,
// 38.9, 26.8, 14.6, 2.49, -9.65), and the height axis names the quantity and
// its unit only, the model in a caption above.
TEST(TractionSurfaceScene, RoundColourValuesAndItsOwnAxisTitles) {
  views::TractionSurfaceData d = plane();
  d.quantity = "drawbar pull (ding_tyii model)";
  d.points.push_back({60.0, 0.3, -9.65});  // a range that does not start at a round value
  const views::TractionSurfaceScene surface = views::make_traction_surface_scene(d);
  vtkScalarBarActor* bar = nullptr;
  vtkCubeAxesActor* axes = nullptr;
  std::vector<std::string> texts;
  vtkPropCollection* props = surface.renderer->GetViewProps();
  props->InitTraversal();
  for (vtkProp* p = props->GetNextProp(); p != nullptr; p = props->GetNextProp()) {
    if (auto* b = vtkScalarBarActor::SafeDownCast(p)) bar = b;
    if (auto* a = vtkCubeAxesActor::SafeDownCast(p)) axes = a;
    if (auto* t = vtkTextActor::SafeDownCast(p)) texts.emplace_back(t->GetInput());
  }
  ASSERT_NE(bar, nullptr);
  ASSERT_NE(axes, nullptr);
  EXPECT_EQ(std::string(axes->GetZTitle()), "drawbar pull (N)");
  EXPECT_NE(std::find(texts.begin(), texts.end(), "drawbar pull (N)"), texts.end());  // the scene's own title
  EXPECT_EQ(std::count(texts.begin(), texts.end(), "surface: ding_tyii model"), 1);
  EXPECT_EQ(std::count_if(texts.begin(), texts.end(), [](const std::string& t) { return t.find("(") != t.npos; }), 2);
  ASSERT_TRUE(bar->GetUseCustomLabels());
  vtkDoubleArray* labels = bar->GetCustomLabels();
  ASSERT_GE(labels->GetNumberOfTuples(), 4);
  EXPECT_LE(labels->GetNumberOfTuples(), 8);
  const double step = labels->GetValue(1) - labels->GetValue(0);
  for (vtkIdType k = 0; k < labels->GetNumberOfTuples(); ++k) {
    const double v = labels->GetValue(k);
    EXPECT_GE(v, surface.value_min - 1e-9);
    EXPECT_LE(v, surface.value_max + 1e-9);
    EXPECT_NEAR(v / step, std::round(v / step), 1e-9) << v;  // a multiple of the step
  }
  const double decade = std::pow(10.0, std::floor(std::log10(step)));
  const double m = step / decade;
  EXPECT_TRUE(std::abs(m - 1) < 1e-9 || std::abs(m - 2) < 1e-9 || std::abs(m - 5) < 1e-9) << step;
}

TEST(TractionSurfaceScene, RefusesAnEmptyRange) {
  views::TractionSurfaceData d = plane();
  d.load_max = d.load_min;
  EXPECT_THROW(views::make_traction_surface_scene(d), DataError);
}

namespace {

struct PlacedText {
  std::string text;
  double box[4];  // x0, x1, y0, y1 in pixels
  double colour[3];
};

// Every text of the scene as drawn in a w x h window: its words, its pixel
// box and its colour, read from the actors rather than the picture.
std::vector<PlacedText> texts_drawn(const views::TractionSurfaceScene& scene, int w, int h) {
  views::ensure_display();
  auto window = views::make_offscreen_window(w, h);
  window->AddRenderer(scene.renderer);
  window->Render();
  std::vector<PlacedText> out;
  vtkPropCollection* props = scene.renderer->GetViewProps();
  props->InitTraversal();
  for (vtkProp* p = props->GetNextProp(); p != nullptr; p = props->GetNextProp()) {
    auto* t = vtkTextActor::SafeDownCast(p);
    if (t == nullptr) continue;
    PlacedText placed;
    placed.text = t->GetInput();
    t->GetBoundingBox(scene.renderer, placed.box);  // about the text's anchor
    const int* anchor = t->GetPositionCoordinate()->GetComputedDisplayValue(scene.renderer);
    for (int k = 0; k < 4; ++k) placed.box[k] += anchor[k / 2];
    t->GetTextProperty()->GetColor(placed.colour);
    out.push_back(placed);
  }
  window->RemoveRenderer(scene.renderer);
  return out;
}

}  // namespace

// Issue 33, item 2: F_y(W, s) at a slip angle, points of two wheels. The key
// names the wheels drawn in their colours (not a third one without points);
// the tick labels are round and no two texts meet, at two window sizes (the
// cube axes' own labels put the load axis's 70 on the slip axis's 0.0); the
// height axis is the lateral force's.
TEST(TractionSurfaceScene, ALateralForceSurfaceKeysItsWheelsAndNoTwoTextsMeet) {
  views::TractionSurfaceData d;
  d.surface = terramechanics::PolynomialSurface(1, {-30.0, 20.0, 0.05});  // F_y = -30 + 20 s + 0.05 W
  d.load_min = 30;
  d.load_max = 70;
  d.slip_min = 0;
  d.slip_max = 1;
  d.quantity = "lateral force F_y (fitted to the points at slip angle 30 deg)";
  for (int k = 0; k < 6; ++k) {
    const double W = 30 + 8 * k, s = 0.1 * (k + 1);
    d.points.push_back({W, s, -30 + 20 * s + 0.05 * W + 0.5});
    d.point_group.push_back(1 + k % 2);
  }
  d.group_names = {"smooth", "grousered", "not drawn"};
  const views::TractionSurfaceScene scene = views::make_traction_surface_scene(d);
  for (const auto& [w, h] : {std::pair{1280, 800}, std::pair{640, 400}}) {
    const std::vector<PlacedText> texts = texts_drawn(scene, w, h);
    std::vector<std::string> words;
    for (const auto& t : texts) words.push_back(t.text);
    for (const char* must : {"lateral force F_y (N)", "load W (N)", "slip s", "smooth", "grousered",
                             "surface: fitted to the points at slip angle 30 deg", "40", "50", "60", "0.2", "0.8"}) {
      EXPECT_NE(std::find(words.begin(), words.end(), must), words.end()) << must;
    }
    EXPECT_EQ(std::find(words.begin(), words.end(), "not drawn"), words.end());
    EXPECT_EQ(std::find(words.begin(), words.end(), "70"), words.end());  // at the corner: not labelled
    for (const auto& t : texts) {
      for (int g : {1, 2}) {
        if (t.text != d.group_names[static_cast<std::size_t>(g - 1)]) continue;
        double rgb[3];
        views::group_colour(g, rgb);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(t.colour[k], rgb[k], 1e-6) << t.text;
      }
      double v = 0;
      char rest = 0;
      if (std::sscanf(t.text.c_str(), "%lf%c", &v, &rest) == 1) {  // a tick label: at most 10 steps of 1, 2 or 5 x 10^k
        bool round = false;
        for (int k = -3; k <= 3; ++k) {
          for (double m : {1.0, 2.0, 5.0}) {
            const double q = v / (m * std::pow(10.0, k));
            round = round || (std::abs(q - std::round(q)) < 1e-9 && std::abs(q) <= 10);
          }
        }
        EXPECT_TRUE(round) << t.text;
      }
      EXPECT_GE(t.box[0], 0.0) << t.text;  // inside the window
      EXPECT_LE(t.box[1], w) << t.text;
    }
    for (std::size_t i = 0; i < texts.size(); ++i) {
      for (std::size_t j = i + 1; j < texts.size(); ++j) {
        const double* a = texts[i].box;
        const double* b = texts[j].box;
        const bool apart = a[1] < b[0] || b[1] < a[0] || a[3] < b[2] || b[3] < a[2];
        EXPECT_TRUE(apart) << w << "x" << h << ": '" << texts[i].text << "' meets '" << texts[j].text << "'";
      }
    }
  }
}

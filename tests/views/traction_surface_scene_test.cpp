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

#include <cmath>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "scene_support.h"
#include "views/traction_surface_scene.h"

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
  EXPECT_EQ(texts, std::vector<std::string>{"surface: ding_tyii model"});
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

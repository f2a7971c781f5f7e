// The traction-surface scene on a plane made here, DP = -20 + 100 s N: the
// surface spans the colour map from blue (low slip) to red (high slip), the
// measured points are drawn dark, and the scene does not follow time.
#include <gtest/gtest.h>

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkRenderer.h>

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

TEST(TractionSurfaceScene, RefusesAnEmptyRange) {
  views::TractionSurfaceData d = plane();
  d.load_max = d.load_min;
  EXPECT_THROW(views::make_traction_surface_scene(d), DataError);
}

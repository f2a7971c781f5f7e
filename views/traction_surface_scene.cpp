#include "views/traction_surface_scene.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCubeAxesActor.h>
#include <vtkDoubleArray.h>
#include <vtkGlyph3D.h>
#include <vtkLookupTable.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"

namespace roverlab::views {

namespace {

constexpr double kHeight = 0.7;  // display height of the value axis (load and slip span 1)

vtkSmartPointer<vtkLookupTable> lookup(double lo, double hi) {
  auto lut = vtkSmartPointer<vtkLookupTable>::New();
  lut->SetNumberOfTableValues(256);
  lut->SetRange(lo, hi);
  for (int i = 0; i < 256; ++i) {
    double rgb[3];
    surface_colour(i / 255.0, rgb);
    lut->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
  }
  lut->Build();
  return lut;
}

}  // namespace

void surface_colour(double f, double rgb[3]) {
  // Blue (low) through white to red (high): the sign of a drawbar pull reads at a glance.
  f = std::clamp(f, 0.0, 1.0);
  if (f < 0.5) {
    const double a = f / 0.5;
    rgb[0] = 0.15 + 0.8 * a;
    rgb[1] = 0.3 + 0.65 * a;
    rgb[2] = 0.85 + 0.1 * a;
  } else {
    const double a = (f - 0.5) / 0.5;
    rgb[0] = 0.95;
    rgb[1] = 0.95 - 0.75 * a;
    rgb[2] = 0.95 - 0.8 * a;
  }
}

TractionSurfaceScene make_traction_surface_scene(const TractionSurfaceData& d, int grid) {
  if (!(d.load_max > d.load_min) || !(d.slip_max > d.slip_min)) throw DataError("empty load or slip range");
  TractionSurfaceScene out;
  // Surface values on the grid.
  const int n = std::max(grid, 4);
  std::vector<double> v(static_cast<std::size_t>(n * n));
  double lo = INFINITY, hi = -INFINITY;
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double W = d.load_min + (d.load_max - d.load_min) * i / (n - 1);
      const double s = d.slip_min + (d.slip_max - d.slip_min) * j / (n - 1);
      const double x = d.surface(W, s);
      v[static_cast<std::size_t>(i * n + j)] = x;
      lo = std::min(lo, x);
      hi = std::max(hi, x);
    }
  }
  for (const auto& p : d.points) {
    lo = std::min(lo, p.value);
    hi = std::max(hi, p.value);
  }
  if (!(hi > lo)) hi = lo + 1.0;
  out.value_min = lo;
  out.value_max = hi;
  auto X = [&](double W) { return (W - d.load_min) / (d.load_max - d.load_min); };
  auto Y = [&](double s) { return (s - d.slip_min) / (d.slip_max - d.slip_min); };
  auto Z = [&](double x) { return kHeight * (x - lo) / (hi - lo); };

  auto points = vtkSmartPointer<vtkPoints>::New();
  auto scalars = vtkSmartPointer<vtkDoubleArray>::New();
  scalars->SetName(d.quantity.c_str());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x = v[static_cast<std::size_t>(i * n + j)];
      points->InsertNextPoint(static_cast<double>(i) / (n - 1), static_cast<double>(j) / (n - 1), Z(x));
      scalars->InsertNextValue(x);
    }
  }
  auto quads = vtkSmartPointer<vtkCellArray>::New();
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      const vtkIdType ids[4] = {i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1};
      quads->InsertNextCell(4, ids);
    }
  }
  auto surface = vtkSmartPointer<vtkPolyData>::New();
  surface->SetPoints(points);
  surface->SetPolys(quads);
  surface->GetPointData()->SetScalars(scalars);
  auto lut = lookup(lo, hi);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputData(surface);
  mapper->SetLookupTable(lut);
  mapper->SetScalarRange(lo, hi);
  mapper->ScalarVisibilityOn();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetAmbient(0.35);
  actor->GetProperty()->SetDiffuse(0.7);

  auto renderer = vtkSmartPointer<vtkRenderer>::New();
  renderer->SetBackground(1.0, 1.0, 1.0);
  renderer->AddActor(actor);

  // Data points and residual lines to the surface.
  if (!d.points.empty()) {
    auto pts = vtkSmartPointer<vtkPoints>::New();
    auto res = vtkSmartPointer<vtkPoints>::New();
    auto lines = vtkSmartPointer<vtkCellArray>::New();
    for (const auto& p : d.points) {
      const double x = X(p.load), y = Y(p.slip);
      pts->InsertNextPoint(x, y, Z(p.value));
      const vtkIdType a = res->InsertNextPoint(x, y, Z(p.value));
      const vtkIdType b = res->InsertNextPoint(x, y, Z(d.surface(p.load, p.slip)));
      const vtkIdType ids[2] = {a, b};
      lines->InsertNextCell(2, ids);
    }
    auto cloud = vtkSmartPointer<vtkPolyData>::New();
    cloud->SetPoints(pts);
    auto sphere = vtkSmartPointer<vtkSphereSource>::New();
    sphere->SetRadius(0.012);
    sphere->SetThetaResolution(12);
    sphere->SetPhiResolution(12);
    auto glyphs = vtkSmartPointer<vtkGlyph3D>::New();
    glyphs->SetSourceConnection(sphere->GetOutputPort());
    glyphs->SetInputData(cloud);
    glyphs->SetScaleModeToDataScalingOff();
    auto gm = vtkSmartPointer<vtkPolyDataMapper>::New();
    gm->SetInputConnection(glyphs->GetOutputPort());
    gm->ScalarVisibilityOff();
    auto ga = vtkSmartPointer<vtkActor>::New();
    ga->SetMapper(gm);
    ga->GetProperty()->SetColor(0.1, 0.1, 0.1);
    renderer->AddActor(ga);
    auto rpoly = vtkSmartPointer<vtkPolyData>::New();
    rpoly->SetPoints(res);
    rpoly->SetLines(lines);
    auto rm = vtkSmartPointer<vtkPolyDataMapper>::New();
    rm->SetInputData(rpoly);
    auto ra = vtkSmartPointer<vtkActor>::New();
    ra->SetMapper(rm);
    ra->GetProperty()->SetColor(0.1, 0.1, 0.1);
    ra->GetProperty()->SetLineWidth(2.0);
    renderer->AddActor(ra);
  }

  // Axes in real units.
  auto axes = vtkSmartPointer<vtkCubeAxesActor>::New();
  axes->SetBounds(0, 1, 0, 1, 0, kHeight);
  axes->SetXAxisRange(d.load_min, d.load_max);
  axes->SetYAxisRange(d.slip_min, d.slip_max);
  axes->SetZAxisRange(lo, hi);
  axes->SetXTitle("load W (N)");
  axes->SetYTitle("slip s");
  axes->SetZTitle((d.quantity + " (" + d.unit + ")").c_str());
  axes->SetCamera(renderer->GetActiveCamera());
  axes->SetFlyModeToOuterEdges();
  for (int k = 0; k < 3; ++k) {
    axes->GetTitleTextProperty(k)->SetColor(0.1, 0.1, 0.1);
    axes->GetLabelTextProperty(k)->SetColor(0.1, 0.1, 0.1);
  }
  axes->GetXAxesLinesProperty()->SetColor(0.2, 0.2, 0.2);
  axes->GetYAxesLinesProperty()->SetColor(0.2, 0.2, 0.2);
  axes->GetZAxesLinesProperty()->SetColor(0.2, 0.2, 0.2);
  renderer->AddActor(axes);

  auto bar = vtkSmartPointer<vtkScalarBarActor>::New();
  bar->SetLookupTable(lut);
  bar->SetNumberOfLabels(5);
  bar->GetTitleTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->UnconstrainedFontSizeOn();
  bar->GetTitleTextProperty()->SetFontSize(14);
  bar->GetLabelTextProperty()->SetFontSize(14);
  bar->SetTitle(d.unit.c_str());
  bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->SetPosition(0.9, 0.1);
  bar->SetWidth(0.08);
  bar->SetHeight(0.8);
  renderer->AddViewProp(bar);

  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetFocalPoint(0.5, 0.5, 0.3 * kHeight);
  cam->SetPosition(2.4, -1.9, 1.7);
  cam->SetViewUp(0, 0, 1);
  renderer->ResetCamera(-0.1, 1.1, -0.1, 1.1, 0.0, kHeight);
  cam->Zoom(1.15);
  out.renderer = renderer;
  return out;
}

}  // namespace roverlab::views

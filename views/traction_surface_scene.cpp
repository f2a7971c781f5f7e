#include "views/traction_surface_scene.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCubeAxesActor.h>
#include <vtkDoubleArray.h>
#include <vtkGlyph3D.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/common/error.h"
#include "views/view.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

namespace {

constexpr double kHeight = 0.7;  // display height of the value axis (load and slip span 1)

vtkSmartPointer<vtkLookupTable> lookup(double lo, double hi) {
  vtkNew<vtkLookupTable> lut;
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

void group_colour(int group, double rgb[3]) {
  // Away from the surface's blue-white-red: green, purple, brown.
  static constexpr double kColours[3][3] = {{0.0, 0.62, 0.15}, {0.55, 0.1, 0.75}, {0.55, 0.35, 0.05}};
  const auto& c = kColours[static_cast<std::size_t>(((group - 1) % 3 + 3) % 3)];
  for (int k = 0; k < 3; ++k) rgb[k] = c[k];
}

namespace {

// The surface's values on an n x n grid over the load and slip ranges (load
// major), and the value range shown: the grid's and the points'.
struct SurfaceGrid {
  int n = 0;
  std::vector<double> values;
  double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  double& at(int i, int j) {
    return values[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)];
  }
  double at(int i, int j) const {
    return values[static_cast<std::size_t>(i) * static_cast<std::size_t>(n) + static_cast<std::size_t>(j)];
  }
};

SurfaceGrid sample_surface(const TractionSurfaceData& d, int grid) {
  SurfaceGrid g;
  g.n = std::max(grid, 4);
  const int n = g.n;
  g.values.resize(static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double W = d.load_min + (d.load_max - d.load_min) * i / (n - 1);
      const double s = d.slip_min + (d.slip_max - d.slip_min) * j / (n - 1);
      const double x = d.surface(W, s);
      g.at(i, j) = x;
      g.lo = std::min(g.lo, x);
      g.hi = std::max(g.hi, x);
    }
  }
  for (const auto& p : d.points) {
    g.lo = std::min(g.lo, p.value);
    g.hi = std::max(g.hi, p.value);
  }
  if (!(g.hi > g.lo)) g.hi = g.lo + 1.0;
  return g;
}

// The reference surface's values on the same grid (empty without one); the
// shown value range grows to hold them.
SurfaceGrid sample_reference(const TractionSurfaceData& d, SurfaceGrid& shown) {
  SurfaceGrid r;
  if (!d.reference) return r;
  TractionSurfaceData ref = d;
  ref.surface = *d.reference;
  ref.points.clear();
  r = sample_surface(ref, shown.n);
  shown.lo = std::min(shown.lo, r.lo);
  shown.hi = std::max(shown.hi, r.hi);
  return r;
}

// Display coordinates: load and slip over [0, 1], the value over [0, kHeight].
struct DisplayBox {
  const TractionSurfaceData& d;
  double lo, hi;
  double x(double load) const { return (load - d.load_min) / (d.load_max - d.load_min); }
  double y(double slip) const { return (slip - d.slip_min) / (d.slip_max - d.slip_min); }
  double z(double value) const { return kHeight * (value - lo) / (hi - lo); }
};

// The surface as quads coloured by value through `lut`.
vtkSmartPointer<vtkActor> surface_actor(const SurfaceGrid& g, const DisplayBox& box, const std::string& quantity,
                                        vtkLookupTable* lut) {
  const int n = g.n;
  vtkNew<vtkPoints> points;
  vtkNew<vtkDoubleArray> scalars;
  scalars->SetName(quantity.c_str());
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double x = g.at(i, j);
      points->InsertNextPoint(static_cast<double>(i) / (n - 1), static_cast<double>(j) / (n - 1), box.z(x));
      scalars->InsertNextValue(x);
    }
  }
  vtkNew<vtkCellArray> quads;
  for (int i = 0; i + 1 < n; ++i) {
    for (int j = 0; j + 1 < n; ++j) {
      const vtkIdType ids[4] = {i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1};
      quads->InsertNextCell(4, ids);
    }
  }
  vtkNew<vtkPolyData> surface;
  surface->SetPoints(points);
  surface->SetPolys(quads);
  surface->GetPointData()->SetScalars(scalars);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputData(surface);
  mapper->SetLookupTable(lut);
  mapper->SetScalarRange(g.lo, g.hi);
  mapper->ScalarVisibilityOn();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  actor->GetProperty()->SetAmbient(0.35);
  actor->GetProperty()->SetDiffuse(0.7);
  return actor;
}

// The data points of one group (0: ungrouped, dark) as spheres, each with
// its residual as a line to the surface while there are few points.
void add_point_group(vtkRenderer* renderer, const TractionSurfaceData& d, const DisplayBox& box, int group) {
  vtkNew<vtkPoints> centres;
  std::vector<Eigen::Vector3d> residuals;
  for (std::size_t i = 0; i < d.points.size(); ++i) {
    if ((d.point_group.size() == d.points.size() ? d.point_group[i] : 0) != group) continue;
    const auto& p = d.points[i];
    const double x = box.x(p.load), y = box.y(p.slip);
    centres->InsertNextPoint(x, y, box.z(p.value));
    residuals.emplace_back(x, y, box.z(p.value));
    residuals.emplace_back(x, y, box.z(d.surface(p.load, p.slip)));
  }
  if (centres->GetNumberOfPoints() == 0) return;
  const bool many = d.points.size() > 300;  // a rover's estimates: smaller, no residual lines
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(many ? 0.007 : 0.012);
  sphere->SetThetaResolution(many ? 6 : 12);
  sphere->SetPhiResolution(many ? 6 : 12);
  vtkNew<vtkGlyph3D> glyphs;
  glyphs->SetSourceConnection(sphere->GetOutputPort());
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(centres);
  glyphs->SetInputData(cloud);
  glyphs->SetScaleModeToDataScalingOff();
  Eigen::Vector3d colour(0.1, 0.1, 0.1);
  if (group > 0) group_colour(group, colour.data());
  auto spheres = actor_of(glyphs->GetOutputPort(), colour);
  spheres->GetMapper()->ScalarVisibilityOff();
  spheres->GetProperty()->SetAmbient(0.6);
  renderer->AddActor(spheres);
  if (many) return;
  auto lines = actor_of(segments(residuals, true), colour);
  lines->GetProperty()->SetLineWidth(2.0);
  renderer->AddActor(lines);
}

void add_points(vtkRenderer* renderer, const TractionSurfaceData& d, const DisplayBox& box) {
  if (d.points.empty()) return;
  std::vector<int> groups = {0};
  if (d.point_group.size() == d.points.size()) {
    groups = d.point_group;
    std::sort(groups.begin(), groups.end());
    groups.erase(std::unique(groups.begin(), groups.end()), groups.end());
  }
  for (int g : groups) add_point_group(renderer, d, box, g);
}

// "drawbar pull (ding_tyii model)" -> the quantity and what the surface is
// ("ding_tyii model"): the axis names the quantity, a caption the rest.
std::pair<std::string, std::string> split_quantity(const std::string& q) {
  const auto at = q.find(" (");
  if (at == std::string::npos || q.back() != ')') return {q, ""};
  return {q.substr(0, at), q.substr(at + 2, q.size() - at - 3)};
}

// Round values inside [lo, hi], four to eight of them: steps of 1, 2 or 5 times a power of ten.
std::vector<double> round_ticks(double lo, double hi) {
  const double span = hi - lo;
  if (!(span > 0) || !std::isfinite(span)) return {lo};
  const double decade = std::pow(10.0, std::floor(std::log10(span / 4.0)));
  double step = decade;
  for (double m : {1.0, 2.0, 5.0, 10.0}) {
    step = m * decade;
    if (span / step <= 7.0) break;
  }
  std::vector<double> ticks;
  for (double v = std::ceil(lo / step) * step; v <= hi + 1e-9 * span; v += step) {
    ticks.push_back(std::abs(v) < 1e-9 * step ? 0.0 : v);
  }
  return ticks;
}

// Axes in real units around the display box.
vtkSmartPointer<vtkCubeAxesActor> axes_of(const TractionSurfaceData& d, double lo, double hi, vtkCamera* camera) {
  vtkNew<vtkCubeAxesActor> axes;
  axes->SetBounds(0, 1, 0, 1, 0, kHeight);
  axes->SetXAxisRange(d.load_min, d.load_max);
  axes->SetYAxisRange(d.slip_min, d.slip_max);
  axes->SetZAxisRange(lo, hi);
  axes->SetXTitle("load W (N)");
  axes->SetYTitle("slip s");
  axes->SetZTitle((split_quantity(d.quantity).first + " (" + d.unit + ")").c_str());
  axes->SetCamera(camera);
  axes->SetFlyModeToOuterEdges();
  // The scene's own round tick labels (tick_labels) replace the axes' (the
  // load axis's last and the slip axis's first met at a corner: "70 0.0").
  axes->XAxisLabelVisibilityOff();
  axes->YAxisLabelVisibilityOff();
  axes->ZAxisLabelVisibilityOff();
  axes->XAxisTickVisibilityOff();
  axes->YAxisTickVisibilityOff();
  axes->ZAxisTickVisibilityOff();
  axes->XAxisMinorTickVisibilityOff();
  axes->YAxisMinorTickVisibilityOff();
  axes->ZAxisMinorTickVisibilityOff();
  for (int k = 0; k < 3; ++k) {
    axes->GetTitleTextProperty(k)->SetColor(0.1, 0.1, 0.1);
    axes->GetLabelTextProperty(k)->SetColor(0.1, 0.1, 0.1);
  }
  axes->GetXAxesLinesProperty()->SetColor(0.2, 0.2, 0.2);
  axes->GetYAxesLinesProperty()->SetColor(0.2, 0.2, 0.2);
  axes->GetZAxesLinesProperty()->SetColor(0.2, 0.2, 0.2);
  return axes;
}

// Round tick values of [lo, hi] at least kTickMargin of the span from either
// end (a label at an end would meet the next axis's at the corner), with
// the fraction of the axis each is at.
constexpr double kTickMargin = 0.06;
std::vector<std::pair<double, double>> inner_ticks(double lo, double hi) {
  std::vector<std::pair<double, double>> out;
  for (double v : round_ticks(lo, hi)) {
    const double f = (v - lo) / (hi - lo);
    if (f >= kTickMargin && f <= 1.0 - kTickMargin) out.emplace_back(v, f);
  }
  return out;
}

// One text in world coordinates, centred on `at`.
void add_text(vtkRenderer* renderer, const std::string& text, const Eigen::Vector3d& at, int size) {
  vtkNew<vtkTextActor> label;
  label->SetInput(text.c_str());
  label->GetTextProperty()->SetFontSize(size);
  label->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
  label->GetTextProperty()->SetJustificationToCentered();
  label->GetTextProperty()->SetVerticalJustificationToCentered();
  label->GetPositionCoordinate()->SetCoordinateSystemToWorld();
  label->GetPositionCoordinate()->SetValue(at.x(), at.y(), at.z());
  renderer->AddViewProp(label);
}

// Round tick marks and labels on the edges the default camera shows (load
// along slip = min, slip along load = max, the value up the near-left
// corner), none near an end: labels of two axes never share a corner.
void add_label(vtkRenderer* renderer, double value, const Eigen::Vector3d& at) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  add_text(renderer, text, at, 14);
}

void add_ticks(vtkRenderer* renderer, const TractionSurfaceData& d, double lo, double hi) {
  std::vector<Eigen::Vector3d> marks;
  const double tick = 0.025, gap = 0.075;
  for (const auto& [v, f] : inner_ticks(d.load_min, d.load_max)) {
    marks.emplace_back(f, 0.0, 0.0);
    marks.emplace_back(f, -tick, 0.0);
    add_label(renderer, v, {f, -gap, 0.0});
  }
  for (const auto& [v, f] : inner_ticks(d.slip_min, d.slip_max)) {
    marks.emplace_back(1.0, f, 0.0);
    marks.emplace_back(1.0 + tick, f, 0.0);
    add_label(renderer, v, {1.0 + gap, f, 0.0});
  }
  for (const auto& [v, f] : inner_ticks(lo, hi)) {
    marks.emplace_back(0.0, 0.0, f * kHeight);
    marks.emplace_back(-tick, 0.0, f * kHeight);
    add_label(renderer, v, {-gap, 0.0, f * kHeight});
  }
  auto lines = actor_of(segments(marks, true), Eigen::Vector3d(0.2, 0.2, 0.2));
  renderer->AddActor(lines);
  // The axis titles beyond the labels (the cube axes' own went with their labels).
  add_text(renderer, "load W (N)", {0.5, -0.23, 0.0}, 16);
  add_text(renderer, "slip s", {1.24, 0.5, 0.0}, 16);
  add_text(renderer, split_quantity(d.quantity).first + " (" + d.unit + ")", {0.0, 0.0, kHeight + 0.09}, 16);
}

vtkSmartPointer<vtkScalarBarActor> colour_bar(vtkLookupTable* lut, const std::string& unit) {
  vtkNew<vtkScalarBarActor> bar;
  bar->SetLookupTable(lut);
  bar->SetNumberOfLabels(5);
  bar->GetTitleTextProperty()->SetColor(0.1, 0.1, 0.1);
  bar->UnconstrainedFontSizeOn();
  bar->GetTitleTextProperty()->SetFontSize(14);
  bar->GetLabelTextProperty()->SetFontSize(14);
  bar->SetTitle(unit.c_str());
  bar->GetLabelTextProperty()->SetColor(0.1, 0.1, 0.1);
  // Round values (the bar's own five labels were its range in fifths: 38.9, 26.8, ...).
  vtkNew<vtkDoubleArray> labels;
  for (double v : round_ticks(lut->GetTableRange()[0], lut->GetTableRange()[1])) labels->InsertNextValue(v);
  bar->SetCustomLabels(labels);
  bar->SetUseCustomLabels(true);
  bar->SetLabelFormat("%g");
  bar->SetPosition(0.9, 0.1);
  bar->SetWidth(0.08);
  bar->SetHeight(0.8);
  return bar;
}

// The key of the point groups drawn (e.g. "smooth", "grousered" or "wheel 1"), each
// line in its group's colour, at the top left under the caption.
void add_key(vtkRenderer* renderer, const TractionSurfaceData& d) {
  if (d.point_group.size() != d.points.size() || d.group_names.empty()) return;
  std::vector<int> drawn = d.point_group;
  std::sort(drawn.begin(), drawn.end());
  drawn.erase(std::unique(drawn.begin(), drawn.end()), drawn.end());
  double y = 0.94 - 0.055;
  for (int g : drawn) {
    if (g < 1 || static_cast<std::size_t>(g) > d.group_names.size()) continue;
    double rgb[3];
    group_colour(g, rgb);
    vtkNew<vtkTextActor> line;
    line->SetInput(d.group_names[static_cast<std::size_t>(g - 1)].c_str());
    line->GetTextProperty()->SetFontSize(15);
    line->GetTextProperty()->SetColor(rgb);
    line->GetTextProperty()->BoldOn();
    line->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    line->GetPositionCoordinate()->SetValue(0.02, y);
    renderer->AddViewProp(line);
    y -= 0.045;
  }
}

void place_camera(vtkRenderer* renderer) {
  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetFocalPoint(0.5, 0.5, 0.3 * kHeight);
  cam->SetPosition(2.4, -1.9, 1.7);
  cam->SetViewUp(0, 0, 1);
  renderer->ResetCamera(-0.1, 1.1, -0.1, 1.1, 0.0, kHeight);
  cam->Zoom(1.15);
}

}  // namespace

TractionSurfaceScene make_traction_surface_scene(const TractionSurfaceData& d, int grid) {
  if (!(d.load_max > d.load_min) || !(d.slip_max > d.slip_min)) throw DataError("empty load or slip range");
  SurfaceGrid g = sample_surface(d, grid);
  const SurfaceGrid reference = sample_reference(d, g);
  const DisplayBox box{d, g.lo, g.hi};
  auto lut = lookup(g.lo, g.hi);
  TractionSurfaceScene out;
  out.value_min = g.lo;
  out.value_max = g.hi;
  out.renderer = vtkSmartPointer<vtkRenderer>::New();
  out.renderer->SetBackground(1.0, 1.0, 1.0);
  out.renderer->AddActor(surface_actor(g, box, d.quantity, lut));
  if (d.reference) {
    auto ref = surface_actor(reference, box, d.quantity, lut);
    ref->GetMapper()->ScalarVisibilityOff();
    ref->GetProperty()->SetColor(0.55, 0.55, 0.55);
    ref->GetProperty()->SetOpacity(0.35);
    out.renderer->AddActor(ref);
  }
  add_points(out.renderer, d, box);
  out.renderer->AddActor(axes_of(d, g.lo, g.hi, out.renderer->GetActiveCamera()));
  add_ticks(out.renderer, d, g.lo, g.hi);
  out.renderer->AddViewProp(colour_bar(lut, d.unit));
  // What the surface and the points are, above the picture (it was crammed into the height axis's title).
  if (const std::string what = split_quantity(d.quantity).second; !what.empty()) {
    vtkNew<vtkTextActor> caption;
    caption->SetInput(("surface: " + what).c_str());
    caption->GetTextProperty()->SetFontSize(16);
    caption->GetTextProperty()->SetColor(0.1, 0.1, 0.1);
    caption->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    caption->GetPositionCoordinate()->SetValue(0.02, 0.94);
    out.renderer->AddViewProp(caption);
  }
  add_key(out.renderer, d);
  place_camera(out.renderer);
  return out;
}

namespace {

// The surface as a Scene: it does not follow the timeline.
class SurfaceScene : public Scene {
 public:
  explicit SurfaceScene(TractionSurfaceScene scene) : scene_(std::move(scene)) {}
  void attach(vtkRenderWindow* window) override { window->AddRenderer(scene_.renderer); }
  void detach(vtkRenderWindow* window) override { window->RemoveRenderer(scene_.renderer); }
  bool follows_time() const override { return false; }
  void set_time(double /*t*/) override {}
  double start_time() const override { return 0.0; }
  double end_time() const override { return 0.0; }

 private:
  TractionSurfaceScene scene_;
};

class TractionSurfaceView : public View {
 public:
  std::string name() const override { return "traction-surface"; }
  std::string title() const override { return "Traction surface"; }
  std::string needs(const SceneInput& in) const override {
    if (!in.surface) {
      return "no traction data: give a single-wheel CSV (load_N, slip, drawbar_pull_N / torque_Nm) or a soil";
    }
    if (!(in.surface->load_max > in.surface->load_min) || !(in.surface->slip_max > in.surface->slip_min)) {
      return "empty load or slip range";
    }
    return {};
  }
  bool uses_surface_data() const override { return true; }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<SurfaceScene>(make_traction_surface_scene(*in.surface));
  }
};

}  // namespace

std::unique_ptr<View> make_traction_surface_view() { return std::make_unique<TractionSurfaceView>(); }

}  // namespace roverlab::views

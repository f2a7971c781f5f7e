// The panel figures of lab data (views/panel_figure.h) and their three views:
// single-wheel forces against slip per slip angle, the held-out residuals
// against slip angle, and plate force against depth.
#include <vtkAxis.h>
#include <vtkChartMatrix.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkCoordinate.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPlot.h>
#include <vtkPlotArea.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkVector.h>

#include <algorithm>
#include <limits>

#include "views/panel_figure.h"
#include "views/view.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

namespace {

void widen(double v, double& lo, double& hi) {
  if (!std::isfinite(v)) return;
  lo = std::min(lo, v);
  hi = std::max(hi, v);
}

// lo..hi with 5 % either side; +-1 around a single value; 0..1 when empty.
void pad(double& lo, double& hi) {
  if (!(lo <= hi)) {
    lo = 0.0;
    hi = 1.0;
    return;
  }
  const double margin = hi > lo ? 0.05 * (hi - lo) : 1.0;
  lo -= margin;
  hi += margin;
}

}  // namespace

PanelRanges panel_ranges(const PanelFigure& figure) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  PanelRanges r;
  r.x_min = kInf;
  r.x_max = -kInf;
  for (const auto& row : figure.rows) {
    double lo = kInf, hi = -kInf;
    for (const auto& panel : row.panels) {
      for (const auto& s : panel.series) {
        for (double x : s.x) widen(x, r.x_min, r.x_max);
        for (double y : s.y) widen(y, lo, hi);
        for (std::size_t i = 0; i < s.curve_x.size() && i < s.curve_y.size(); ++i) {
          if (!std::isfinite(s.curve_y[i])) continue;
          widen(s.curve_x[i], r.x_min, r.x_max);
          const double band = std::isfinite(s.band) ? s.band : 0.0;
          widen(s.curve_y[i] - band, lo, hi);
          widen(s.curve_y[i] + band, lo, hi);
        }
      }
    }
    pad(lo, hi);
    r.y_min.push_back(lo);
    r.y_max.push_back(hi);
  }
  pad(r.x_min, r.x_max);
  return r;
}

namespace {

// Group g's colour; a negative group (a reference line) is grey.
void group_colour(int group, unsigned char rgb[3]) {
  if (group < 0) {
    rgb[0] = rgb[1] = rgb[2] = 110;
    return;
  }
  static const unsigned char table[8][3] = {{31, 119, 180},  {214, 39, 40}, {44, 160, 44},   {255, 127, 14},
                                            {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {23, 190, 207}};
  const int i = group % 8;
  for (int k = 0; k < 3; ++k) rgb[k] = table[i][k];
}

// The runs of consecutive finite values of y (a curve breaks where the model has no value).
std::vector<std::pair<std::size_t, std::size_t>> finite_runs(const std::vector<double>& y) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  std::size_t i = 0;
  while (i < y.size()) {
    while (i < y.size() && !std::isfinite(y[i])) ++i;
    const std::size_t start = i;
    while (i < y.size() && std::isfinite(y[i])) ++i;
    if (i > start) runs.emplace_back(start, i);
  }
  return runs;
}

// A text at (x, y) pixels from the point at `across` of the viewport's width on its top edge.
vtkSmartPointer<vtkTextActor> text_actor(const std::string& text, int size, const unsigned char rgb[3], bool bold,
                                         double across, double x, double y) {
  auto t = vtkSmartPointer<vtkTextActor>::New();
  t->SetInput(text.c_str());
  t->GetTextProperty()->SetFontSize(size);
  t->GetTextProperty()->SetColor(rgb[0] / 255.0, rgb[1] / 255.0, rgb[2] / 255.0);
  t->GetTextProperty()->SetBold(bold ? 1 : 0);
  // Placed in pixels from a point of the viewport's top edge, whatever its size.
  vtkNew<vtkCoordinate> top_left;
  top_left->SetCoordinateSystemToNormalizedViewport();
  top_left->SetValue(across, 1.0);
  t->GetPositionCoordinate()->SetCoordinateSystemToViewport();
  t->GetPositionCoordinate()->SetReferenceCoordinate(top_left);
  t->SetPosition(x, y);
  return t;
}

// About `count` ticks at round values (1, 2 or 5 times a power of ten) inside lo..hi.
void set_ticks(vtkAxis* axis, double lo, double hi, int count) {
  const double raw = (hi - lo) / count;
  if (!(raw > 0)) return;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  double step = power;
  for (double m : {2.0, 5.0, 10.0}) {
    if (std::abs(m * power - raw) < std::abs(step - raw)) step = m * power;
  }
  vtkNew<vtkDoubleArray> ticks;
  for (double t = std::ceil(lo / step) * step; t <= hi + 1e-9 * step; t += step) {
    ticks->InsertNextValue(std::abs(t) < 1e-9 * step ? 0.0 : t);
  }
  axis->SetCustomTickPositions(ticks);
}

class PanelFigureScene : public Scene {
 public:
  explicit PanelFigureScene(const PanelFigure& figure)
      : x_title_(figure.x_title), ranges_(panel_ranges(figure)), notes_(figure.notes) {
    view_ = vtkSmartPointer<vtkContextView>::New();
    view_->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
    rows_ = static_cast<int>(figure.rows.size());
    for (const auto& row : figure.rows) columns_ = std::max(columns_, static_cast<int>(row.panels.size()));
    vtkNew<vtkChartMatrix> matrix;
    view_->GetScene()->AddItem(matrix);
    matrix->SetSize(vtkVector2i(std::max(columns_, 1), std::max(rows_, 1)));
    matrix->SetBorders(70, 50, 20, 100);  // left, bottom, right, top (the caption and key above)
    matrix->SetGutter(vtkVector2f(columns_ > 4 ? 18.0F : 40.0F, 48.0F));
    matrix->Allocate();
    for (int r = 0; r < rows_; ++r) {
      const PanelRow& row = figure.rows[static_cast<std::size_t>(r)];
      for (int c = 0; c < columns_; ++c) {
        vtkChartXY* ch = chart(r, c);
        if (c >= static_cast<int>(row.panels.size())) {
          ch->SetVisible(false);
          continue;
        }
        for (const auto& s : row.panels[static_cast<std::size_t>(c)].series) add_series(ch, s);
        style_chart(ch, row, r, c);  // after the plots: adding one resets an axis's range
      }
    }
    add_key(figure);
  }

  void attach(vtkRenderWindow* window) override {
    view_->SetRenderWindow(window);
    if (window->GetInteractor() != nullptr) view_->SetInteractor(window->GetInteractor());
  }
  void detach(vtkRenderWindow* window) override {
    if (view_->GetRenderWindow() == window) window->RemoveRenderer(view_->GetRenderer());
  }
  // The key's entries side by side, spaced for a window `pixels` wide.
  bool follows_time() const override { return false; }
  void set_time(double /*t*/) override {}
  double start_time() const override { return 0.0; }
  double end_time() const override { return 0.0; }
  std::vector<std::string> notes() const override { return notes_; }

 private:
  vtkChartXY* chart(int row, int column) const {
    auto* matrix = vtkChartMatrix::SafeDownCast(view_->GetScene()->GetItem(0));
    // vtkChartMatrix counts rows from the bottom.
    return vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(column, rows_ - 1 - row)));
  }

  void style_chart(vtkChartXY* ch, const PanelRow& row, int r, int c) const {
    ch->SetShowLegend(false);
    ch->SetTitle(row.panels[static_cast<std::size_t>(c)].title);
    ch->GetTitleProperties()->SetFontSize(14);
    ch->GetTitleProperties()->SetBold(1);
    vtkAxis* x = ch->GetAxis(vtkAxis::BOTTOM);
    vtkAxis* y = ch->GetAxis(vtkAxis::LEFT);
    if (columns_ > 4) set_ticks(x, ranges_.x_min, ranges_.x_max, 3);  // narrow panels: few round ticks
    x->SetBehavior(vtkAxis::FIXED);
    x->SetRange(ranges_.x_min, ranges_.x_max);
    y->SetBehavior(vtkAxis::FIXED);
    y->SetRange(ranges_.y_min[static_cast<std::size_t>(r)], ranges_.y_max[static_cast<std::size_t>(r)]);
    x->SetTitle(r + 1 == rows_ ? x_title_ : "");
    y->SetTitle(c == 0 ? row.y_title : "");
    for (vtkAxis* a : {x, y}) {
      a->GetLabelProperties()->SetFontSize(12);
      a->GetTitleProperties()->SetFontSize(14);
      a->GetTitleProperties()->SetBold(0);
    }
  }

  void add_series(vtkChartXY* ch, const PanelSeries& s) {
    unsigned char rgb[3];
    group_colour(s.group, rgb);
    for (const auto& [begin, end] : finite_runs(s.curve_y)) {
      std::vector<double> x(s.curve_x.begin() + static_cast<long>(begin), s.curve_x.begin() + static_cast<long>(end));
      std::vector<double> y(s.curve_y.begin() + static_cast<long>(begin), s.curve_y.begin() + static_cast<long>(end));
      if (std::isfinite(s.band)) {
        std::vector<double> lower = y, upper = y;
        for (auto& v : lower) v -= s.band;
        for (auto& v : upper) v += s.band;
        auto* area = vtkPlotArea::SafeDownCast(ch->AddPlot(vtkChart::AREA));
        area->SetInputData(table_of({{"x", x}, {"lower", lower}, {"upper", upper}}));
        area->SetInputArray(0, "x");
        area->SetInputArray(1, "lower");
        area->SetInputArray(2, "upper");
        area->SetColor(rgb[0], rgb[1], rgb[2], s.group < 0 ? 60 : 45);
      }
      vtkPlot* line = ch->AddPlot(vtkChart::LINE);
      line->SetInputData(table_of({{"x", x}, {"y", y}}), 0, 1);
      line->SetColor(rgb[0], rgb[1], rgb[2], 255);
      line->SetWidth(2.5);
    }
    if (s.x.empty()) return;
    vtkPlot* points = ch->AddPlot(vtkChart::POINTS);
    points->SetInputData(table_of({{"x", s.x}, {"y", s.y}}), 0, 1);
    points->SetColor(rgb[0], rgb[1], rgb[2], 255);
    if (auto* p = vtkPlotPoints::SafeDownCast(points)) {
      p->SetMarkerStyle(vtkPlotPoints::CIRCLE);
      p->SetMarkerSize(s.x.size() > 200 ? 3.5F : 7.0F);  // dense records: the curves stay visible
    }
  }

  // The caption on top, the key below it: each group's name in its colour,
  // the line shared equally among them (12 pt when there are more than three).
  void add_key(const PanelFigure& figure) {
    const unsigned char dark[3] = {30, 30, 30};
    texts_.push_back(text_actor(figure.caption, 14, dark, false, 0.0, 12.0, -44.0));  // two lines
    const std::size_t n = figure.group_names.size();
    for (std::size_t g = 0; g < n; ++g) {
      unsigned char rgb[3];
      group_colour(static_cast<int>(g), rgb);
      texts_.push_back(text_actor(figure.group_names[g], n > 3 ? 12 : 14, rgb, true,
                                  static_cast<double>(g) / static_cast<double>(std::max<std::size_t>(n, 3)), 12.0,
                                  -68.0));
    }
    for (const auto& t : texts_) view_->GetRenderer()->AddActor2D(t);
  }

 private:
  std::string x_title_;
  vtkSmartPointer<vtkContextView> view_;
  std::vector<vtkSmartPointer<vtkTextActor>> texts_;
  PanelRanges ranges_;
  int rows_ = 0, columns_ = 0;
  std::vector<std::string> notes_;
};

// A view of one of SceneInput::lab's figures.
class LabFigureView : public View {
 public:
  LabFigureView(std::string name, std::string title, std::string heading, double height,
                std::optional<PanelFigure> LabFigures::*figure, std::string needs)
      : name_(std::move(name)),
        title_(std::move(title)),
        heading_(std::move(heading)),
        height_(height),
        figure_(figure),
        needs_(std::move(needs)) {}
  std::string name() const override { return name_; }
  std::string title() const override { return title_; }
  std::string heading() const override { return heading_; }
  bool uses_lab_figures() const override { return true; }
  double report_height() const override { return height_; }
  std::string needs(const SceneInput& in) const override {
    if (!in.lab) return needs_;
    if (!((*in.lab).*figure_)) return in.lab->why_not.empty() ? needs_ : in.lab->why_not;
    return {};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<PanelFigureScene>(*((*in.lab).*figure_));
  }

 private:
  std::string name_, title_, heading_;
  double height_;
  std::optional<PanelFigure> LabFigures::*figure_;
  std::string needs_;
};

}  // namespace

std::unique_ptr<View> make_slip_panels_view() {
  return std::make_unique<LabFigureView>(
      "slip-panels", "Per slip angle", "Drawbar pull and lateral force against slip, one panel per slip angle", 1.0,
      &LabFigures::slip_panels, "a single-wheel CSV (load_N, slip, drawbar_pull_N or lateral_force_N)");
}

std::unique_ptr<View> make_slip_angle_residuals_view() {
  return std::make_unique<LabFigureView>("slip-angle-residuals", "Residuals by slip angle",
                                         "Held-out residuals against slip angle", 0.7, &LabFigures::residuals,
                                         "a single-wheel CSV (load_N, slip, drawbar_pull_N or lateral_force_N)");
}

std::unique_ptr<View> make_force_depth_view() {
  return std::make_unique<LabFigureView>("force-depth", "Plate force", "Plate force against depth, fitted curves", 0.8,
                                         &LabFigures::force_depth,
                                         "a plate test CSV (depth_m, force_N, plate size in the header)");
}

}  // namespace roverlab::views

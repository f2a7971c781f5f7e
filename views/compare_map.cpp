#include "views/compare_map.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "views/timeseries_chart.h"

namespace roverlab::views {

namespace {

vtkSmartPointer<vtkTable> xy_table(const std::vector<double>& x, const std::vector<double>& y) {
  auto table = vtkSmartPointer<vtkTable>::New();
  vtkNew<vtkDoubleArray> ax, ay;
  ax->SetName("east");
  ay->SetName("north");
  ax->SetNumberOfValues(static_cast<vtkIdType>(x.size()));
  ay->SetNumberOfValues(static_cast<vtkIdType>(y.size()));
  for (std::size_t i = 0; i < x.size(); ++i) {
    ax->SetValue(static_cast<vtkIdType>(i), x[i]);
    ay->SetValue(static_cast<vtkIdType>(i), y[i]);
  }
  table->AddColumn(ax);
  table->AddColumn(ay);
  return table;
}

}  // namespace

CompareMap::CompareMap(const log::Log& base, const std::vector<std::pair<std::string, const log::Log*>>& runs) {
  view_ = vtkSmartPointer<vtkContextView>::New();
  view_->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  vtkNew<vtkChartXY> chart;
  view_->GetScene()->AddItem(chart);
  chart->SetShowLegend(true);
  chart->GetLegend()->SetInline(false);
  chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
  chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  chart->GetLegend()->GetLabelProperties()->SetFontSize(14);
  chart->SetTitle("Every run's track (markers at the cursor time)");
  chart->GetTitleProperties()->SetFontSize(15);
  add_track("baseline", base, comparison::Alignment{});
  for (const auto& [name, run] : runs) {
    comparison::Alignment alignment;
    try {
      alignment = comparison::align_runs(base, *run, comparison::AlignmentOptions{});
    } catch (const DataError& e) {
      throw DataError(name + ": " + e.what());
    }
    add_track(name, *run, alignment);
  }
  if (tracks_.empty()) throw DataError("no run has a position track");
  start_ = tracks_.front().time.empty() ? 0.0 : tracks_.front().time.front();
  end_ = tracks_.front().time.empty() ? 0.0 : tracks_.front().time.back();
  fit_axes();
  set_time(0.5 * (start_ + end_));
}

CompareMap::~CompareMap() = default;

void CompareMap::add_track(const std::string& name, const log::Log& lg, const comparison::Alignment& alignment) {
  const comparison::PositionTrack p = comparison::position_track(lg);
  if (p.stream.empty()) {
    notes_.push_back(name + " has no position track (truth/motion, truth/pose, gps, estimate/ins/pose, odometry)");
    return;
  }
  const log::Stream& s = lg.stream(p.stream);
  Track t{name, p.stream, p.x, p.y, s.time(), s.channel(p.x).values, s.channel(p.y).values, alignment, nullptr};
  const std::size_t k = tracks_.size();
  unsigned char rgb[3];
  line_colour(k, rgb);
  vtkChartXY* c = chart();
  vtkPlot* line = c->AddPlot(vtkChart::LINE);
  line->SetInputData(xy_table(t.x, t.y), 0, 1);
  line->SetColor(rgb[0], rgb[1], rgb[2], 255);
  line->SetWidth(k == 0 ? 5.0f : 2.0f);  // a run on the same path leaves the baseline's edges visible
  line->SetLabel(name + " (" + p.stream + ")");
  t.marker = xy_table({NAN}, {NAN});
  auto* dot = vtkPlotPoints::SafeDownCast(c->AddPlot(vtkChart::POINTS));
  dot->SetInputData(t.marker, 0, 1);
  dot->SetColor(rgb[0], rgb[1], rgb[2], 255);
  dot->SetMarkerStyle(vtkPlotPoints::CIRCLE);
  dot->SetMarkerSize(k == 0 ? 22.0f : 12.0f);  // a run where the baseline is leaves its marker a ring
  dot->SetLegendVisibility(false);
  tracks_.push_back(std::move(t));
}

vtkChartXY* CompareMap::chart() const { return vtkChartXY::SafeDownCast(view_->GetScene()->GetItem(0)); }

Eigen::Vector2d CompareMap::marker(std::size_t k) const {
  const auto& m = tracks_[k].marker;
  return {m->GetValue(0, 0).ToDouble(), m->GetValue(0, 1).ToDouble()};
}

void CompareMap::set_time(double t) {
  for (auto& track : tracks_) {
    const double at = track.alignment.other_times({t}).front();
    double x = NAN, y = NAN;
    if (!track.time.empty() && at >= track.time.front() && at <= track.time.back()) {
      x = log::interpolate_linear(track.time, track.x, at);
      y = log::interpolate_linear(track.time, track.y, at);
    }
    track.marker->SetValue(0, 0, x);
    track.marker->SetValue(0, 1, y);
    track.marker->Modified();
  }
}

// One scale on both axes: the ranges cover every track with the plot's own aspect.
void CompareMap::fit_axes() {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& t : tracks_) {
    for (std::size_t i = 0; i < t.x.size(); ++i) {
      if (!std::isfinite(t.x[i]) || !std::isfinite(t.y[i])) continue;
      x0 = std::min(x0, t.x[i]);
      x1 = std::max(x1, t.x[i]);
      y0 = std::min(y0, t.y[i]);
      y1 = std::max(y1, t.y[i]);
    }
  }
  if (!(x1 >= x0)) {
    x0 = y0 = -1;
    x1 = y1 = 1;
  }
  int w = 1280, h = 800;
  if (vtkRenderWindow* window = view_->GetRenderWindow(); window != nullptr && window->GetSize()[0] > 0) {
    w = window->GetSize()[0];
    h = window->GetSize()[1];
  }
  // The plot area: the window less the axes' margins, the title and the legend's column at the right.
  const double aspect = std::max(0.2, (w - 360.0) / std::max(1.0, h - 110.0));
  double half_w = 0.55 * std::max(x1 - x0, 1e-3), half_h = 0.55 * std::max(y1 - y0, 1e-3);
  if (half_w / half_h > aspect) {
    half_h = half_w / aspect;
  } else {
    half_w = half_h * aspect;
  }
  const double cx = 0.5 * (x0 + x1), cy = 0.5 * (y0 + y1);
  vtkChartXY* c = chart();
  c->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
  c->GetAxis(vtkAxis::BOTTOM)->SetRange(cx - half_w, cx + half_w);
  c->GetAxis(vtkAxis::BOTTOM)->SetTitle(tracks_.front().x_name + " (m)");
  c->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
  c->GetAxis(vtkAxis::LEFT)->SetRange(cy - half_h, cy + half_h);
  c->GetAxis(vtkAxis::LEFT)->SetTitle(tracks_.front().y_name + " (m)");
}

void CompareMap::attach(vtkRenderWindow* window) {
  view_->SetRenderWindow(window);
  if (window->GetInteractor() != nullptr) view_->SetInteractor(window->GetInteractor());
}

void CompareMap::detach(vtkRenderWindow* window) {
  if (view_->GetRenderWindow() == window) window->RemoveRenderer(view_->GetRenderer());
}

void CompareMap::fit_width(int /*pixels*/) { fit_axes(); }

namespace {

class CompareMapView : public View {
 public:
  std::string name() const override { return "compare-map"; }
  std::string title() const override { return "Compare tracks"; }
  std::string heading() const override { return "Every run's track"; }
  bool compares_runs() const override { return true; }
  bool top_down_camera() const override { return true; }
  std::string needs(const SceneInput& in) const override {
    if (in.log == nullptr) return "needs a log";
    if (in.compared.empty()) return "needs another run to compare with (render --compare FILE, File > Compare with...)";
    if (comparison::position_track(*in.log).stream.empty()) return "the baseline has no position track";
    return {};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<CompareMap>(*in.log, in.compared);
  }
};

}  // namespace

std::unique_ptr<View> make_compare_map_view() { return std::make_unique<CompareMapView>(); }

}  // namespace roverlab::views

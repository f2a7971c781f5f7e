#include "views/scatter_scene.h"

#include <vtkAxis.h>
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

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/common/error.h"

namespace roverlab::views {

namespace {

const log::Channel& channel_of(const log::Log& lg, const ChannelRef& c) {
  const log::Stream* s = lg.find_stream(c.stream);
  if (s == nullptr) throw DataError("no stream '" + c.stream + "' (channels are given as stream:channel)");
  const log::Channel* ch = s->find_channel(c.channel);
  if (ch == nullptr) throw DataError("stream '" + c.stream + "' has no channel '" + c.channel + "'");
  return *ch;
}

}  // namespace

ScatterPoints paired_samples(const log::Log& lg, const ChannelRef& x, const ChannelRef& y) {
  const auto& xs = channel_of(lg, x).values;
  channel_of(lg, y);
  const log::Stream& xstream = lg.stream(x.stream);
  ScatterPoints p;
  p.x_samples = xstream.size();
  p.interpolated = x.stream != y.stream;
  // Another stream's channel at x's times: NaN outside its span, so dropped.
  const std::vector<double> ys = p.interpolated ? lg.stream(y.stream).interpolate(y.channel, xstream.time())
                                                : lg.stream(y.stream).channel(y.channel).values;
  for (std::size_t i = 0; i < xs.size() && i < ys.size(); ++i) {
    if (!std::isfinite(xs[i]) || !std::isfinite(ys[i])) continue;
    p.x.push_back(xs[i]);
    p.y.push_back(ys[i]);
  }
  return p;
}

std::string scatter_axis_title(const log::Log& lg, const ChannelRef& c) {
  const std::string& unit = channel_of(lg, c).unit;
  std::string title = c.stream + ":" + c.channel;
  if (!unit.empty() && unit != "1") title += " (" + unit + ")";
  return title;
}

ScatterScene::ScatterScene(const log::Log& lg, ChannelRef x, ChannelRef y)
    : points_(paired_samples(lg, x, y)), x_(std::move(x)), y_(std::move(y)) {
  const log::Stream& xs = lg.stream(x_.stream);
  start_ = xs.empty() ? 0.0 : xs.start_time();
  end_ = xs.empty() ? 0.0 : xs.end_time();
  view_ = vtkSmartPointer<vtkContextView>::New();
  view_->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  chart_ = vtkSmartPointer<vtkChartXY>::New();
  view_->GetScene()->AddItem(chart_);
  vtkNew<vtkTable> table;
  vtkNew<vtkDoubleArray> cx;
  vtkNew<vtkDoubleArray> cy;
  cx->SetName("x");
  cy->SetName("y");
  cx->SetNumberOfValues(static_cast<vtkIdType>(points_.x.size()));
  cy->SetNumberOfValues(static_cast<vtkIdType>(points_.y.size()));
  for (std::size_t i = 0; i < points_.x.size(); ++i) {
    cx->SetValue(static_cast<vtkIdType>(i), points_.x[i]);
    cy->SetValue(static_cast<vtkIdType>(i), points_.y[i]);
  }
  table->AddColumn(cx);
  table->AddColumn(cy);
  vtkPlot* plot = chart_->AddPlot(vtkChart::POINTS);
  plot->SetInputData(table, 0, 1);
  plot->SetColor(31, 119, 180, 255);
  if (auto* pts = vtkPlotPoints::SafeDownCast(plot)) pts->SetMarkerSize(points_.x.size() > 2000 ? 3.0F : 6.0F);
  set_axis(vtkAxis::BOTTOM, points_.x, scatter_axis_title(lg, x_));
  set_axis(vtkAxis::LEFT, points_.y, scatter_axis_title(lg, y_));
}

ScatterScene::~ScatterScene() = default;

// Every point inside the axes: the data's range and 5 % either side (a
// constant channel gets +-1 around its value).
void ScatterScene::set_axis(int axis, const std::vector<double>& values, const std::string& title) {
  vtkAxis* a = chart_->GetAxis(axis);
  a->SetTitle(title);
  if (values.empty()) return;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  const double pad = *hi > *lo ? 0.05 * (*hi - *lo) : 1.0;
  a->SetBehavior(vtkAxis::FIXED);
  a->SetRange(*lo - pad, *hi + pad);
}

void ScatterScene::attach(vtkRenderWindow* window) {
  view_->SetRenderWindow(window);
  if (window->GetInteractor() != nullptr) view_->SetInteractor(window->GetInteractor());
}

void ScatterScene::detach(vtkRenderWindow* window) {
  if (view_->GetRenderWindow() == window) window->RemoveRenderer(view_->GetRenderer());
}

std::vector<std::string> ScatterScene::notes() const {
  std::vector<std::string> out;
  char line[256];
  if (points_.interpolated) {
    std::snprintf(line, sizeof line, "%s:%s interpolated linearly to the times of stream '%s'", y_.stream.c_str(),
                  y_.channel.c_str(), x_.stream.c_str());
    out.emplace_back(line);
  }
  if (points_.x.size() < points_.x_samples) {
    std::snprintf(line, sizeof line, "%zu of %zu samples drawn (the rest NaN or outside the other stream's span)",
                  points_.x.size(), points_.x_samples);
    out.emplace_back(line);
  }
  return out;
}

namespace {

class ScatterView : public View {
 public:
  std::string name() const override { return "scatter"; }
  std::string title() const override { return "Scatter"; }
  std::string heading() const override { return "One channel against another"; }
  bool plots_channel_pair() const override { return true; }
  std::string needs(const SceneInput& in) const override {
    if (in.channels.size() != 2)
      return "a scatter plot needs two channels, x then y (render --x STREAM:CH --y STREAM:CH)";
    try {
      const ScatterPoints p = paired_samples(*in.log, in.channels[0], in.channels[1]);
      if (p.x.empty())
        return "no sample has both " + in.channels[0].stream + ":" + in.channels[0].channel + " and " +
               in.channels[1].stream + ":" + in.channels[1].channel + " finite (streams apart in time?)";
    } catch (const DataError& e) {
      return e.what();
    }
    return {};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<ScatterScene>(*in.log, in.channels[0], in.channels[1]);
  }
};

}  // namespace

std::unique_ptr<View> make_scatter_view() { return std::make_unique<ScatterView>(); }

}  // namespace roverlab::views

#include "views/timeseries_chart.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>

#include "core/common/error.h"
#include "views/display_series.h"

namespace roverlab::views {

std::vector<ChannelRef> parse_channels(const log::Log& lg, const std::string& spec) {
  std::vector<ChannelRef> out;
  std::size_t a = 0;
  while (a <= spec.size()) {
    std::size_t b = spec.find(',', a);
    if (b == std::string::npos) b = spec.size();
    const std::string item = spec.substr(a, b - a);
    a = b + 1;
    if (item.empty()) continue;
    const std::size_t colon = item.rfind(':');
    const std::string stream = colon == std::string::npos ? item : item.substr(0, colon);
    const log::Stream* s = lg.find_stream(stream);
    if (s == nullptr) throw DataError("no stream '" + stream + "' (channels are given as stream:channel)");
    if (colon == std::string::npos) {
      for (const auto& c : s->channels()) out.push_back({stream, c.name});
    } else {
      const std::string channel = item.substr(colon + 1);
      if (s->find_channel(channel) == nullptr) throw DataError("stream '" + stream + "' has no channel '" + channel + "'");
      out.push_back({stream, channel});
    }
  }
  if (out.empty()) throw DataError("no channels given");
  return out;
}

std::vector<ChannelRef> default_channels(const log::Log& lg) {
  std::vector<ChannelRef> out;
  for (const auto& s : lg.streams()) {
    if (s.channels().empty() || s.size() < 2) continue;
    for (const auto& c : s.channels()) {
      if (out.size() < 4) out.push_back({s.name(), c.name});
    }
    break;
  }
  if (out.empty()) throw DataError("the log has no channels to plot");
  return out;
}

void line_colour(std::size_t i, unsigned char rgb[3]) {
  static const unsigned char table[8][3] = {{31, 119, 180}, {214, 39, 40},  {44, 160, 44},  {255, 127, 14},
                                            {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {23, 190, 207}};
  for (int k = 0; k < 3; ++k) rgb[k] = table[i % 8][k];
}

TimeSeriesChart::TimeSeriesChart(const log::Log& lg, std::vector<ChannelRef> channels) {
  view_ = vtkSmartPointer<vtkContextView>::New();
  view_->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  auto chart = vtkSmartPointer<vtkChartXY>::New();
  view_->GetScene()->AddItem(chart);
  chart->SetShowLegend(true);
  chart->GetLegend()->SetInline(true);
  chart->GetLegend()->GetLabelProperties()->SetFontSize(14);
  chart->GetAxis(vtkAxis::BOTTOM)->SetTitle("time (s)");
  reset(lg, std::move(channels));
}

void TimeSeriesChart::reset(const log::Log& lg, std::vector<ChannelRef> channels) {
  log_ = &lg;
  channels_ = std::move(channels);
  vtkChartXY* chart = this->chart();
  bool first = true;
  for (const auto& c : channels_) {
    const log::Stream& s = lg.stream(c.stream);
    if (s.empty()) continue;
    start_ = first ? s.start_time() : std::min(start_, s.start_time());
    end_ = first ? s.end_time() : std::max(end_, s.end_time());
    first = false;
  }
  chart->GetAxis(vtkAxis::LEFT)->SetTitle("value (units in the legend)");
  if (channels_.size() == 1) {
    const auto& ch = lg.stream(channels_[0].stream).channel(channels_[0].channel);
    chart->GetAxis(vtkAxis::LEFT)->SetTitle(channels_[0].channel + " (" + ch.unit + ")");
  }
  t0_ = start_;
  t1_ = end_;
  cursor_t_ = start_;
  rebuild();
}

TimeSeriesChart::~TimeSeriesChart() = default;

vtkContextView* TimeSeriesChart::view() const { return view_; }

vtkChartXY* TimeSeriesChart::chart() const { return vtkChartXY::SafeDownCast(view_->GetScene()->GetItem(0)); }

void TimeSeriesChart::set_window(double t0, double t1, std::size_t columns) {
  t0_ = std::max(t0, start_);
  t1_ = std::min(t1, end_);
  if (!(t1_ > t0_)) {
    t0_ = start_;
    t1_ = end_;
  }
  columns_ = std::max<std::size_t>(columns, 16);
  rebuild();
}

void TimeSeriesChart::rebuild() {
  vtkChartXY* chart = this->chart();
  chart->ClearPlots();
  tables_.clear();
  y_min_ = INFINITY;
  y_max_ = -INFINITY;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const auto& c = channels_[i];
    const log::Stream& s = log_->stream(c.stream);
    auto table = make_display_table(s, c.channel, t0_, t1_, columns_);
    const std::string label = c.stream + ":" + c.channel + " [" + s.channel(c.channel).unit + "]";
    table->GetColumn(1)->SetName(label.c_str());
    for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r) {
      const double v = table->GetValue(r, 1).ToDouble();
      if (std::isfinite(v)) {
        y_min_ = std::min(y_min_, v);
        y_max_ = std::max(y_max_, v);
      }
    }
    vtkPlot* line = chart->AddPlot(vtkChart::LINE);
    line->SetInputData(table, 0, 1);
    unsigned char rgb[3];
    line_colour(i, rgb);
    line->SetColor(rgb[0], rgb[1], rgb[2], 255);
    line->SetWidth(2.0);
    tables_.push_back(table);
  }
  if (!std::isfinite(y_min_)) {
    y_min_ = 0;
    y_max_ = 1;
  }
  if (y_max_ - y_min_ < 1e-12) {
    y_min_ -= 0.5;
    y_max_ += 0.5;
  }
  const double pad = 0.05 * (y_max_ - y_min_);
  chart->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
  chart->GetAxis(vtkAxis::LEFT)->SetRange(y_min_ - pad, y_max_ + pad);
  chart->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
  chart->GetAxis(vtkAxis::BOTTOM)->SetRange(t0_, t1_);
  // Cursor: a vertical black line over the full value range.
  cursor_ = vtkSmartPointer<vtkTable>::New();
  auto ct = vtkSmartPointer<vtkDoubleArray>::New();
  ct->SetName("cursor time");
  auto cy = vtkSmartPointer<vtkDoubleArray>::New();
  cy->SetName("cursor");
  cursor_->AddColumn(ct);
  cursor_->AddColumn(cy);
  cursor_->SetNumberOfRows(2);
  vtkPlot* cursor = chart->AddPlot(vtkChart::LINE);
  cursor->SetInputData(cursor_, 0, 1);
  cursor->SetColor(0, 0, 0, 255);
  cursor->SetWidth(1.5);
  cursor->SetLabel("");
  cursor->SetLegendVisibility(false);
  set_cursor(cursor_t_);
}

void TimeSeriesChart::set_cursor(double t) {
  cursor_t_ = t;
  const double pad = 0.05 * (y_max_ - y_min_);
  cursor_->SetValue(0, 0, t);
  cursor_->SetValue(1, 0, t);
  cursor_->SetValue(0, 1, y_min_ - pad);
  cursor_->SetValue(1, 1, y_max_ + pad);
  cursor_->Modified();
}

std::vector<std::size_t> TimeSeriesChart::drawn_points() const {
  std::vector<std::size_t> out;
  for (const auto& t : tables_) out.push_back(static_cast<std::size_t>(t->GetNumberOfRows()));
  return out;
}

}  // namespace roverlab::views

#include "views/compare_chart.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartMatrix.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPlot.h>
#include <vtkPlotArea.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkVector.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/common/error.h"
#include "views/display_series.h"
#include "views/timeseries_chart.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

namespace {

constexpr std::size_t kMaxChannels = 4;  // two plots each

void widen(std::pair<double, double>& range, const std::vector<double>& values) {
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    range.first = std::min(range.first, v);
    range.second = std::max(range.second, v);
  }
}

// The significance of channel c's difference: its statistic over its threshold.
double strength(const comparison::ChannelComparison& c) {
  return c.test.threshold > 0 ? c.test.statistic / c.test.threshold : 0.0;
}

}  // namespace

std::vector<comparison::RunComparison> compare_all(const log::Log& base,
                                                   const std::vector<std::pair<std::string, const log::Log*>>& runs) {
  comparison::CompareOptions options;
  options.keep_differences = true;
  std::vector<comparison::RunComparison> out;
  for (const auto& [name, run] : runs) {
    try {
      out.push_back(comparison::compare_runs(base, *run, options));
    } catch (const DataError& e) {
      throw DataError(name + ": " + e.what());
    }
  }
  return out;
}

std::vector<ChannelRef> differing_channels(const std::vector<comparison::RunComparison>& runs, std::size_t count) {
  std::vector<std::pair<double, ChannelRef>> ranked;  // (-(differs + strength), channel)
  for (const auto& r : runs) {
    for (const auto& c : r.channels) {
      const double score = (c.differs ? 1e6 : 0.0) + strength(c);
      const auto it = std::find_if(ranked.begin(), ranked.end(), [&](const auto& e) {
        return e.second.stream == c.stream && e.second.channel == c.channel;
      });
      if (it == ranked.end()) {
        ranked.push_back({score, {c.stream, c.channel}});
      } else {
        it->first = std::max(it->first, score);
      }
    }
  }
  std::stable_sort(ranked.begin(), ranked.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::vector<ChannelRef> out;
  for (std::size_t k = 0; k < ranked.size() && k < count; ++k) out.push_back(ranked[k].second);
  return out;
}

CompareChart::CompareChart(const log::Log& base, const std::vector<std::pair<std::string, const log::Log*>>& runs,
                           std::vector<ChannelRef> channels)
    : base_(&base), prefix_(comparison::CompareOptions{}.difference_prefix) {
  std::vector<comparison::RunComparison> compared = compare_all(base, runs);
  if (channels.empty()) channels = differing_channels(compared, 2);
  if (channels.empty()) throw DataError("the runs share no channel that can be compared");
  if (channels.size() > kMaxChannels) {
    notes_.push_back("drawn: the first " + std::to_string(kMaxChannels) + " of the " + std::to_string(channels.size()) +
                     " channels asked for");
    channels.resize(kMaxChannels);
  }
  channels_ = std::move(channels);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    Run run{runs[r].first, std::move(compared[r]), {}};
    for (const auto& ch : channels_) {
      const auto& cs = run.comparison.channels;
      const auto it = std::find_if(cs.begin(), cs.end(),
                                   [&](const auto& c) { return c.stream == ch.stream && c.channel == ch.channel; });
      if (it == cs.end())
        throw DataError(run.name + ": " + ch.stream + ":" + ch.channel + " is not compared (only in one run)");
      run.index.push_back(static_cast<std::size_t>(it - cs.begin()));
    }
    char line[256];
    std::snprintf(line, sizeof line, "%s aligned by %s, offset %+.4f s; %zu of %zu shared channels differ",
                  run.name.c_str(), run.comparison.alignment.how.c_str(), run.comparison.alignment.offset_s,
                  run.comparison.differing(), run.comparison.channels.size());
    notes_.emplace_back(line);
    runs_.push_back(std::move(run));
  }
  start_ = std::numeric_limits<double>::infinity();
  end_ = -start_;
  for (const auto& ch : channels_) {
    const log::Stream& s = base.stream(ch.stream);
    if (s.empty()) continue;
    start_ = std::min(start_, s.start_time());
    end_ = std::max(end_, s.end_time());
  }
  if (!(start_ <= end_)) start_ = end_ = 0;
  cursor_ = start_;
  view_ = vtkSmartPointer<vtkContextView>::New();
  view_->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  vtkNew<vtkChartMatrix> matrix;
  view_->GetScene()->AddItem(matrix);
  build_plots();
}

CompareChart::~CompareChart() = default;

const comparison::ChannelComparison& CompareChart::channel_comparison(std::size_t r, std::size_t k) const {
  return runs_[r].comparison.channels[runs_[r].index[k]];
}

const std::vector<double>& CompareChart::difference_time(std::size_t r, std::size_t k) const {
  return runs_[r].comparison.differences.stream(prefix_ + "/" + channels_[k].stream).time();
}

const std::vector<double>& CompareChart::difference(std::size_t r, std::size_t k) const {
  return runs_[r]
      .comparison.differences.stream(prefix_ + "/" + channels_[k].stream)
      .channel(channels_[k].channel)
      .values;
}

double CompareChart::band_half_width(std::size_t r, std::size_t k) const {
  const auto& c = channel_comparison(r, k);
  return 2.0 * std::hypot(c.base_sigma, c.other_sigma);
}

double CompareChart::difference_at_cursor(std::size_t r, std::size_t k) const {
  const auto& t = difference_time(r, k);
  if (t.empty() || cursor_ < t.front() || cursor_ > t.back()) return NAN;
  return log::interpolate_linear(t, difference(r, k), cursor_);
}

vtkChartXY* CompareChart::chart(std::size_t row) const {
  auto* matrix = vtkChartMatrix::SafeDownCast(view_->GetScene()->GetItem(0));
  const int rows = matrix->GetSize().GetY();
  return vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(0, rows - 1 - static_cast<int>(row))));
}

void CompareChart::build_plots() {
  auto* matrix = vtkChartMatrix::SafeDownCast(view_->GetScene()->GetItem(0));
  matrix->SetSize(vtkVector2i(1, static_cast<int>(2 * channels_.size())));
  matrix->SetGutterY(30.0f);
  matrix->SetBorderLeft(80);
  matrix->Allocate();
  cursors_.clear();
  ranges_.clear();
  for (std::size_t k = 0; k < channels_.size(); ++k) {
    add_values(k);
    add_differences(k);
  }
  for (std::size_t row = 0; row < 2 * channels_.size(); ++row) {
    vtkChartXY* c = chart(row);
    c->SetShowLegend(true);
    c->GetLegend()->SetInline(true);
    c->GetLegend()->GetLabelProperties()->SetFontSize(13);
    c->GetTitleProperties()->SetFontSize(13);
    auto& range = ranges_[row];
    if (!(range.second > range.first)) range = {range.first - 0.5, range.first + 0.5};
    if (!std::isfinite(range.first)) range = {-1, 1};
    const double pad = 0.05 * (range.second - range.first);
    range = {range.first - pad, range.second + pad};
    c->GetAxis(vtkAxis::LEFT)->SetBehavior(vtkAxis::FIXED);
    c->GetAxis(vtkAxis::LEFT)->SetRange(range.first, range.second);
    c->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
    c->GetAxis(vtkAxis::BOTTOM)->SetRange(start_, end_);
    c->GetAxis(vtkAxis::BOTTOM)->SetTitle(row + 1 == 2 * channels_.size() ? "baseline time (s)" : "");
    add_cursor(c);
  }
  set_time(cursor_);
}

// Row 2k: the baseline's channel as recorded, and each run on the baseline's times.
void CompareChart::add_values(std::size_t k) {
  const ChannelRef& ch = channels_[k];
  const log::Stream& s = base_->stream(ch.stream);
  const log::Channel& values = s.channel(ch.channel);
  vtkChartXY* c = chart(2 * k);
  c->ClearPlots();
  std::pair<double, double> range{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
  unsigned char rgb[3];
  const DisplaySeries b = decimate_min_max(s.time(), values.values, start_, end_, columns_);
  widen(range, b.value);
  vtkPlot* line = c->AddPlot(vtkChart::LINE);
  line->SetInputData(table_of({{"time", b.time}, {"baseline", b.value}}), 0, 1);
  line_colour(0, rgb);
  line->SetColor(rgb[0], rgb[1], rgb[2], 255);
  line->SetWidth(2.5);
  line->SetLabel("baseline");
  for (std::size_t r = 0; r < runs_.size(); ++r) {
    const std::vector<double>& t = difference_time(r, k);
    const std::vector<double>& d = difference(r, k);
    const std::vector<double> at = s.interpolate(ch.channel, t);
    std::vector<double> run(t.size());
    for (std::size_t i = 0; i < t.size(); ++i) run[i] = at[i] + d[i];  // other = base + (other - base)
    const DisplaySeries o = decimate_min_max(t, run, start_, end_, columns_);
    widen(range, o.value);
    vtkPlot* p = c->AddPlot(vtkChart::LINE);
    p->SetInputData(table_of({{"time", o.time}, {"run", o.value}}), 0, 1);
    line_colour(r + 1, rgb);
    p->SetColor(rgb[0], rgb[1], rgb[2], 255);
    p->SetWidth(1.5);
    p->SetLabel(runs_[r].name);
  }
  c->GetAxis(vtkAxis::LEFT)->SetTitle(ch.channel + " (" + values.unit + ")");
  c->SetTitle(ch.stream + ":" + ch.channel);
  ranges_.push_back(range);
}

// Row 2k + 1: each run minus the baseline, over the +-2 sigma band of the two streams' noise.
void CompareChart::add_differences(std::size_t k) {
  vtkChartXY* c = chart(2 * k + 1);
  c->ClearPlots();
  std::pair<double, double> range{0.0, 0.0};
  unsigned char rgb[3];
  std::string title = channels_[k].channel + ": run - baseline";
  for (std::size_t r = 0; r < runs_.size(); ++r) {
    const double half = band_half_width(r, k);
    line_colour(r + 1, rgb);
    if (std::isfinite(half)) {
      auto* area = vtkPlotArea::SafeDownCast(c->AddPlot(vtkChart::AREA));
      std::vector<double> t(64), low(t.size(), -half), high(t.size(), half);
      for (std::size_t i = 0; i < t.size(); ++i) t[i] = start_ + (end_ - start_) * static_cast<double>(i) / 63.0;
      area->SetInputData(table_of({{"time", t}, {"low", low}, {"high", high}}));
      area->SetInputArray(0, "time");
      area->SetInputArray(1, "low");
      area->SetInputArray(2, "high");
      area->SetColor(rgb[0], rgb[1], rgb[2], 50);
      area->SetLegendVisibility(false);  // named in its line's legend entry
      widen(range, {-half, half});
    }
    const DisplaySeries d = decimate_min_max(difference_time(r, k), difference(r, k), start_, end_, columns_);
    widen(range, d.value);
    vtkPlot* p = c->AddPlot(vtkChart::LINE);
    p->SetInputData(table_of({{"time", d.time}, {"difference", d.value}}), 0, 1);
    p->SetColor(rgb[0], rgb[1], rgb[2], 255);
    p->SetWidth(1.5);
    const auto& cc = channel_comparison(r, k);
    p->SetLabel(runs_[r].name + " - baseline (shaded: +-2 sigma noise)");
    title += std::string(r ? "; " : ": ") + runs_[r].name + (cc.differs ? " differs" : " within noise");
  }
  c->GetAxis(vtkAxis::LEFT)
      ->SetTitle("difference (" + base_->stream(channels_[k].stream).channel(channels_[k].channel).unit + ")");
  c->SetTitle(title);
  ranges_.push_back(range);
}

void CompareChart::add_cursor(vtkChartXY* c) {
  auto cursor = table_of({{"cursor time", {0.0, 0.0}}, {"cursor", {0.0, 0.0}}});
  vtkPlot* p = c->AddPlot(vtkChart::LINE);
  p->SetInputData(cursor, 0, 1);
  p->SetColor(0, 0, 0, 255);
  p->SetWidth(1.5);
  p->SetLegendVisibility(false);
  cursors_.push_back(cursor);
}

void CompareChart::set_time(double t) {
  cursor_ = t;
  for (std::size_t row = 0; row < cursors_.size(); ++row) move_cursor(cursors_[row], t, ranges_[row]);
}

void CompareChart::attach(vtkRenderWindow* window) {
  view_->SetRenderWindow(window);
  if (window->GetInteractor() != nullptr) view_->SetInteractor(window->GetInteractor());
}

void CompareChart::detach(vtkRenderWindow* window) {
  if (view_->GetRenderWindow() == window) window->RemoveRenderer(view_->GetRenderer());
}

void CompareChart::fit_width(int pixels) {
  columns_ = static_cast<std::size_t>(std::max(pixels, 16));
  build_plots();
}

namespace {

class CompareView : public View {
 public:
  std::string name() const override { return "compare"; }
  std::string title() const override { return "Compare runs"; }
  std::string heading() const override { return "The runs overlaid, and each one's difference from the baseline"; }
  bool compares_runs() const override { return true; }  // and plots SceneInput::channels (not a plot pane)
  std::string needs(const SceneInput& in) const override {
    if (in.log == nullptr) return "needs a log";
    if (in.compared.empty()) return "needs another run to compare with (render --compare FILE, File > Compare with...)";
    return {};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<CompareChart>(*in.log, in.compared, in.channels);
  }
};

}  // namespace

std::unique_ptr<View> make_compare_view() { return std::make_unique<CompareView>(); }

}  // namespace roverlab::views

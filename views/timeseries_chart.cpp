#include "views/timeseries_chart.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartMatrix.h>
#include <vtkChartXY.h>
#include <vtkCommand.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotArea.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>
#include <vtkVector.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/common/error.h"
#include "core/log/conventions.h"
#include "views/display_series.h"
#include "views/vtk_parts.h"

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
      if (s->find_channel(channel) == nullptr)
        throw DataError("stream '" + stream + "' has no channel '" + channel + "'");
      out.push_back({stream, channel});
    }
  }
  if (out.empty()) throw DataError("no channels given");
  return out;
}

std::string sigma_channel_of(const log::Stream& stream, const std::string& channel) {
  // "pitch" -> "pitch_sigma"; "drawbar_pull_1" -> "drawbar_pull_sigma_1"; "contact_angle_FL" ->
  // "contact_angle_FL_sigma".
  std::vector<std::string> names = {channel + "_sigma"};
  const auto cut = channel.rfind('_');
  if (cut != std::string::npos) names.push_back(channel.substr(0, cut) + "_sigma" + channel.substr(cut));
  for (const auto& n : names) {
    if (stream.find_channel(n) != nullptr) return n;
  }
  return {};
}

namespace {

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// Whether a truth changes at all (a contact angle on flat ground does not: a
// flat line says little).
bool varies(const std::vector<double>& values) {
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  return lo != values.end() && *hi - *lo > 1e-9 * std::max(1.0, std::abs(*hi));
}

// An estimate and the truth of the same channel, where the truth changes: the
// quantity that says most first (the contact angle, drawbar pull, slip, load),
// then any other.
std::vector<ChannelRef> estimate_against_truth(const log::Log& lg) {
  static const std::vector<std::string> order = {"contact_angle", "drawbar_pull", "slip", "normal_load", ""};
  for (const auto& quantity : order) {
    for (const auto& e : lg.streams()) {
      if (!starts_with(e.name(), log::kEstimatePrefix) || e.size() < 2) continue;
      for (const auto& c : e.channels()) {
        if (c.name.find("_sigma") != std::string::npos || !starts_with(c.name, quantity.c_str())) continue;
        for (const auto& t : lg.streams()) {
          if (starts_with(t.name(), "truth/") && t.size() >= 2 && t.find_channel(c.name) != nullptr &&
              varies(t.channel(c.name).values))
            return {{e.name(), c.name}, {t.name(), c.name}};
        }
      }
    }
  }
  return {};
}

// An estimate beside the reference it is scored against in its own stream
// (estimate/ins/slip: slip_ratio and reference_slip).
std::vector<ChannelRef> estimate_against_reference(const log::Log& lg) {
  for (const auto& e : lg.streams()) {
    if (!starts_with(e.name(), log::kEstimatePrefix) || e.size() < 2) continue;
    for (const auto& c : e.channels()) {
      if (!starts_with(c.name, "reference_")) continue;
      const std::string quantity = c.name.substr(10);
      for (const auto& other : e.channels()) {
        if (&other != &c && starts_with(other.name, quantity.c_str()))
          return {{e.name(), other.name}, {e.name(), c.name}};
      }
    }
  }
  return {};
}

}  // namespace

namespace {

// How a channel moves: the share of its variance that its means over
// one-second bins keep (R^2 of the bins, 0 .. 1: motion is slow, sensor noise
// fast), what white noise would keep (about one over the samples in a bin),
// and whether it is a ramp (a cumulative quantity such as a wheel angle, a
// position or a count: the bin means move one way in 75 % of their steps and
// end half their range or more from where they began).
struct Movement {
  double share = 0, noise_share = 1;
  bool ramp = false;
};

Movement movement_of(const log::Stream& s, const log::Channel& c) {
  Movement m;
  const auto& t = s.time();
  const double span = s.duration();
  if (!(span > 0) || t.size() < 20 || !varies(c.values)) return m;
  const double bin = std::max(1.0, 5.0 * span / static_cast<double>(t.size()));
  std::vector<double> sum, count;
  double total = 0, total_sq = 0, n = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double v = c.values[k];
    if (!std::isfinite(v)) continue;
    const auto b = static_cast<std::size_t>((t[k] - t.front()) / bin);
    if (b >= sum.size()) sum.resize(b + 1, 0.0), count.resize(b + 1, 0.0);
    sum[b] += v;
    count[b] += 1;
    total += v;
    total_sq += v * v;
    n += 1;
  }
  if (n < 20) return m;
  const double mean = total / n, var_total = total_sq / n - mean * mean;
  if (!(var_total > 0)) return m;
  double var_between = 0;
  std::vector<double> means;
  for (std::size_t b = 0; b < sum.size(); ++b) {
    if (count[b] == 0) continue;
    means.push_back(sum[b] / count[b]);
    var_between += count[b] * (means.back() - mean) * (means.back() - mean);
  }
  m.share = std::min(1.0, var_between / n / var_total);
  m.noise_share = static_cast<double>(means.size()) / n;
  int up = 0, down = 0;
  for (std::size_t b = 1; b < means.size(); ++b) {
    const double d = means[b] - means[b - 1];
    if (d > 0) ++up;
    if (d < 0) ++down;
  }
  const auto [lo, hi] = std::minmax_element(means.begin(), means.end());
  m.ramp = up + down >= 3 && std::max(up, down) >= 0.75 * (up + down) &&
           std::abs(means.back() - means.front()) >= 0.5 * (*hi - *lo);
  return m;
}

// A rate or a speed follows what the rover does.
bool is_rate(const std::string& unit) { return unit == "m/s" || unit == "rad/s" || unit == "deg/s"; }

// With no estimate to plot, the channels (outside estimate/) that follow the
// motion: first the rates and speeds whose slow share is 0.1 or more and
// twice what white noise keeps (the IMU's raw noise is not), then any other
// channel at least half slow that is not a ramp; each group by its slow
// share. Up to four, in at most two units (two plots).
std::vector<ChannelRef> moving_channels(const log::Log& lg) {
  struct Scored {
    double score;
    ChannelRef ref;
    std::string unit;
  };
  std::vector<Scored> scored;
  for (const auto& s : lg.streams()) {
    if (starts_with(s.name(), log::kEstimatePrefix) || s.size() < 2) continue;
    for (const auto& c : s.channels()) {
      const Movement m = movement_of(s, c);
      if (is_rate(c.unit) && m.share >= std::max(0.1, 2 * m.noise_share)) {
        scored.push_back({1.0 + m.share, {s.name(), c.name}, c.unit});
      } else if (!is_rate(c.unit) && !m.ramp && m.share >= 0.5) {
        scored.push_back({m.share, {s.name(), c.name}, c.unit});
      }
    }
  }
  std::stable_sort(scored.begin(), scored.end(), [](const Scored& a, const Scored& b) { return a.score > b.score; });
  std::vector<ChannelRef> out;
  std::vector<std::string> units;
  for (const auto& one : scored) {
    if (out.size() == 4) break;
    const bool known = std::find(units.begin(), units.end(), one.unit) != units.end();
    if (!known && units.size() == 2) continue;
    if (!known) units.push_back(one.unit);
    out.push_back(one.ref);
  }
  return out;
}

}  // namespace

std::vector<ChannelRef> default_channels(const log::Log& lg) {
  if (auto pair = estimate_against_truth(lg); !pair.empty()) return pair;
  if (auto pair = estimate_against_reference(lg); !pair.empty()) return pair;
  if (auto moving = moving_channels(lg); !moving.empty()) return moving;
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
  static const unsigned char table[8][3] = {{31, 119, 180},  {214, 39, 40}, {44, 160, 44},   {255, 127, 14},
                                            {148, 103, 189}, {140, 86, 75}, {227, 119, 194}, {23, 190, 207}};
  for (int k = 0; k < 3; ++k) rgb[k] = table[i % 8][k];
}

TimeSeriesChart::TimeSeriesChart(const log::Log& lg, std::vector<ChannelRef> channels) {
  view_ = vtkSmartPointer<vtkContextView>::New();
  view_->GetRenderer()->SetBackground(1.0, 1.0, 1.0);
  vtkNew<vtkChartMatrix> matrix;
  view_->GetScene()->AddItem(matrix);
  view_->GetRenderer()->AddObserver(vtkCommand::EndEvent, this, &TimeSeriesChart::fit_left_border);
  reset(lg, std::move(channels));
}

// vtkChartMatrix keeps a fixed left border (50 px) for every plot, whatever
// its tick labels: "-0.0011" and a y title do not fit. After each render, the
// widest tick label and the title's height (as the text renderer measures
// them) set the border the next render uses.
void TimeSeriesChart::fit_left_border(vtkObject* /*renderer*/, unsigned long /*event*/, void* /*data*/) {
  vtkTextRenderer* text = vtkTextRenderer::GetInstance();
  auto* window = view_->GetRenderWindow();
  if (text == nullptr || window == nullptr) return;
  const int dpi = window->GetDPI();
  int needed = 50;
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    vtkAxis* axis = chart(g)->GetAxis(vtkAxis::LEFT);
    int widest = 0, bbox[4] = {0, 0, 0, 0};
    vtkStringArray* labels = axis->GetTickLabels();
    for (vtkIdType i = 0; labels != nullptr && i < labels->GetNumberOfValues(); ++i) {
      if (text->GetBoundingBox(axis->GetLabelProperties(), labels->GetValue(i), bbox, dpi))
        widest = std::max(widest, bbox[1] - bbox[0]);
    }
    int title = 0;
    if (text->GetBoundingBox(axis->GetTitleProperties(), axis->GetTitle(), bbox, dpi))
      title = std::min(bbox[1] - bbox[0], bbox[3] - bbox[2]);  // the title is drawn turned: its height
    // Tick marks and gaps: 5 px from the axis to the labels, 10 px to the title, 8 px to the edge.
    needed = std::max(needed, widest + title + 23);
  }
  auto* matrix = vtkChartMatrix::SafeDownCast(view_->GetScene()->GetItem(0));
  int borders[4];
  matrix->GetBorders(borders);
  if (needed != borders[0]) matrix->SetBorderLeft(needed);
}

int TimeSeriesChart::left_border() const {
  int borders[4];
  vtkChartMatrix::SafeDownCast(view_->GetScene()->GetItem(0))->GetBorders(borders);
  return borders[0];
}

void TimeSeriesChart::reset(const log::Log& lg, std::vector<ChannelRef> channels) {
  log_ = &lg;
  channels_ = std::move(channels);
  // One plot per unit, in the order the units first appear.
  groups_.clear();
  std::vector<std::string> units;
  for (std::size_t i = 0; i < channels_.size(); ++i) {
    const std::string& unit = lg.stream(channels_[i].stream).channel(channels_[i].channel).unit;
    const auto it = std::find(units.begin(), units.end(), unit);
    if (it == units.end()) {
      units.push_back(unit);
      groups_.push_back({i});
    } else {
      groups_[static_cast<std::size_t>(it - units.begin())].push_back(i);
    }
  }
  auto* matrix = vtkChartMatrix::SafeDownCast(view_->GetScene()->GetItem(0));
  matrix->SetSize(vtkVector2i(1, static_cast<int>(std::max<std::size_t>(groups_.size(), 1))));
  matrix->SetGutterY(30.0f);
  matrix->Allocate();
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    vtkChartXY* c = chart(g);
    c->SetShowLegend(true);
    c->GetLegend()->SetInline(true);
    c->GetLegend()->GetLabelProperties()->SetFontSize(13);
    c->GetAxis(vtkAxis::BOTTOM)->SetTitle(g + 1 == groups_.size() ? "time (s)" : "");
    c->GetAxis(vtkAxis::LEFT)->SetTitle(y_title(g));
  }
  bool first = true;
  for (const auto& c : channels_) {
    const log::Stream& s = lg.stream(c.stream);
    if (s.empty()) continue;
    start_ = first ? s.start_time() : std::min(start_, s.start_time());
    end_ = first ? s.end_time() : std::max(end_, s.end_time());
    first = false;
  }
  t0_ = start_;
  t1_ = end_;
  cursor_t_ = start_;
  rebuild();
}

namespace {

// The quantity a channel holds: its name without an axis or wheel suffix,
// in words ("specific_force_x" -> "specific force", "angle_FL" -> "angle").
// A field path of a ROS message ("position.robot_joint") is a name, kept as it is.
std::string quantity_of(std::string name) {
  if (name.find('.') != std::string::npos) return name;
  const auto cut = name.rfind('_');
  if (cut != std::string::npos) {
    const std::string tail = name.substr(cut + 1);
    static const std::vector<std::string> suffixes = {"x",  "y", "z", "FL", "FR", "RL", "RR", "ML",
                                                      "MR", "1", "2", "3",  "4",  "5",  "6"};
    if (std::find(suffixes.begin(), suffixes.end(), tail) != suffixes.end()) name.erase(cut);
  }
  std::replace(name.begin(), name.end(), '_', ' ');
  return name;
}

}  // namespace

std::string TimeSeriesChart::y_title(std::size_t g) const {
  std::vector<std::string> quantities;
  std::string unit;
  for (std::size_t i : groups_.at(g)) {
    const auto& c = log_->stream(channels_[i].stream).channel(channels_[i].channel);
    unit = c.unit;
    const std::string q = quantity_of(c.name);
    if (std::find(quantities.begin(), quantities.end(), q) == quantities.end()) quantities.push_back(q);
  }
  std::string title;
  for (std::size_t k = 0; k < quantities.size() && k < 2; ++k) title += (k > 0 ? ", " : "") + quantities[k];
  if (quantities.size() > 2) title += ", ...";
  // A ratio (unit "1") is named alone; any other unit follows its quantity.
  if (!unit.empty() && unit != "1") title += " (" + unit + ")";
  return title.empty() ? "value" : title;
}

TimeSeriesChart::~TimeSeriesChart() = default;

vtkContextView* TimeSeriesChart::view() const { return view_; }

void TimeSeriesChart::attach(vtkRenderWindow* window) {
  view_->SetRenderWindow(window);
  if (window->GetInteractor() != nullptr) view_->SetInteractor(window->GetInteractor());
}

void TimeSeriesChart::detach(vtkRenderWindow* window) {
  if (view_->GetRenderWindow() == window) window->RemoveRenderer(view_->GetRenderer());
}

void TimeSeriesChart::fit_width(int pixels) { set_window(t0_, t1_, static_cast<std::size_t>(std::max(pixels, 1))); }

void TimeSeriesChart::zoom_to_fit() {
  user_values_.assign(groups_.size(), false);
  set_window(start_, end_, columns_);
}

vtkChartXY* TimeSeriesChart::chart(std::size_t i) const {
  auto* matrix = vtkChartMatrix::SafeDownCast(view_->GetScene()->GetItem(0));
  const int rows = matrix->GetSize().GetY();
  // vtkChartMatrix counts rows from the bottom.
  return vtkChartXY::SafeDownCast(matrix->GetChart(vtkVector2i(0, rows - 1 - static_cast<int>(i))));
}

void TimeSeriesChart::set_window(double t0, double t1, std::size_t columns) {
  t0_ = std::max(t0, start_);
  t1_ = std::min(t1, end_);
  if (!(t1_ > t0_)) {
    t0_ = start_;
    t1_ = end_;
  }
  columns_ = std::max<std::size_t>(columns, 16);
  refresh();
}

void TimeSeriesChart::rebuild() {
  bands_.clear();
  user_values_.assign(groups_.size(), false);
  labels_.assign(channels_.size(), std::string());
  tables_.assign(channels_.size(), nullptr);
  plots_.assign(channels_.size(), nullptr);
  cursors_.clear();
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    vtkChartXY* chart = this->chart(g);
    chart->ClearPlots();
    for (std::size_t i : groups_[g]) {
      // The estimate's +-1 sigma band under its line, when the stream holds the sigma.
      const std::string sigma = sigma_channel_of(log_->stream(channels_[i].stream), channels_[i].channel);
      if (!sigma.empty()) {
        auto* area = vtkPlotArea::SafeDownCast(chart->AddPlot(vtkChart::AREA));
        unsigned char rgb[3];
        line_colour(i, rgb);
        area->SetColor(rgb[0], rgb[1], rgb[2], 70);
        area->SetLabel("+-1 sigma of " + channels_[i].channel);
        bands_.push_back({i, sigma, area, nullptr});
      }
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      unsigned char rgb[3];
      line_colour(i, rgb);
      line->SetColor(rgb[0], rgb[1], rgb[2], 255);
      line->SetWidth(2.0);
      plots_[i] = line;
    }
    // Cursor: a vertical black line over the plot's value range.
    auto cursor = table_of({{"cursor time", {0.0, 0.0}}, {"cursor", {0.0, 0.0}}});
    vtkPlot* cp = chart->AddPlot(vtkChart::LINE);
    cp->SetInputData(cursor, 0, 1);
    cp->SetColor(0, 0, 0, 255);
    cp->SetWidth(1.5);
    cp->SetLegendVisibility(false);
    cursors_.push_back(cursor);
  }
  link_time_axes();
  refresh();
}

// Each plot's time axis tells the others when it moves (vtkChart::UpdateRange);
// its value axis tells the chart that the user has set it.
void TimeSeriesChart::link_time_axes() {
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    vtkAxis* axis = chart(g)->GetAxis(vtkAxis::BOTTOM);
    axis->RemoveObservers(vtkChart::UpdateRange);
    axis->AddObserver(vtkChart::UpdateRange, this, &TimeSeriesChart::time_axis_moved);
    vtkAxis* values = chart(g)->GetAxis(vtkAxis::LEFT);
    values->RemoveObservers(vtkChart::UpdateRange);
    values->AddObserver(vtkChart::UpdateRange, this, &TimeSeriesChart::value_axis_moved);
  }
}

void TimeSeriesChart::value_axis_moved(vtkObject* caller, unsigned long /*event*/, void* /*data*/) {
  if (linking_) return;
  for (std::size_t g = 0; g < groups_.size() && g < user_values_.size(); ++g) {
    if (chart(g)->GetAxis(vtkAxis::LEFT) == caller) user_values_[g] = true;
  }
}

void TimeSeriesChart::time_axis_moved(vtkObject* caller, unsigned long /*event*/, void* /*data*/) {
  if (linking_) return;
  auto* axis = vtkAxis::SafeDownCast(caller);
  if (axis == nullptr || !(axis->GetMaximum() > axis->GetMinimum())) return;
  linking_ = true;
  // The window the user chose, for every plot; the data redecimated for it (refresh sets the axes).
  t0_ = axis->GetMinimum();
  t1_ = axis->GetMaximum();
  refresh();
  linking_ = false;
  if (user_window_) user_window_(t0_, t1_);
}

void TimeSeriesChart::refresh() {
  ranges_.clear();
  for (std::size_t g = 0; g < groups_.size(); ++g) {
    vtkChartXY* chart = this->chart(g);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i : groups_[g]) {
      const auto& c = channels_[i];
      const log::Stream& s = log_->stream(c.stream);
      auto table = make_display_table(s, c.channel, t0_, t1_, columns_);
      const std::string label = c.stream + ":" + c.channel + " (" + s.channel(c.channel).unit + ")";
      table->GetColumn(1)->SetName(label.c_str());
      labels_[i] = label;
      for (vtkIdType r = 0; r < table->GetNumberOfRows(); ++r) {
        const double v = table->GetValue(r, 1).ToDouble();
        if (std::isfinite(v)) {
          lo = std::min(lo, v);
          hi = std::max(hi, v);
        }
      }
      plots_[i]->SetInputData(table, 0, 1);
      tables_[i] = table;
    }
    if (!std::isfinite(lo)) {
      lo = 0;
      hi = 1;
    }
    if (hi - lo < 1e-12) {
      lo -= 0.5;
      hi += 0.5;
    }
    for (auto& band : bands_) {
      if (std::find(groups_[g].begin(), groups_[g].end(), band.channel) != groups_[g].end()) refresh_band(band, lo, hi);
    }
    const bool was_linking = linking_;
    linking_ = true;  // setting the window is not the user zooming
    vtkAxis* values = chart->GetAxis(vtkAxis::LEFT);
    values->SetBehavior(vtkAxis::FIXED);
    if (g < user_values_.size() && user_values_[g]) {  // the user's value range stays
      ranges_.emplace_back(values->GetMinimum(), values->GetMaximum());
    } else {
      const double pad = 0.05 * (hi - lo);
      ranges_.emplace_back(lo - pad, hi + pad);
      values->SetRange(lo - pad, hi + pad);
    }
    chart->GetAxis(vtkAxis::BOTTOM)->SetBehavior(vtkAxis::FIXED);
    chart->GetAxis(vtkAxis::BOTTOM)->SetRange(t0_, t1_);
    linking_ = was_linking;
  }
  set_cursor(cursor_t_);
}

std::vector<TimeSeriesChart::Reading> TimeSeriesChart::readout() const {
  std::vector<Reading> out;
  for (const auto& c : channels_) {
    const log::Stream& s = log_->stream(c.stream);
    const log::Channel& ch = s.channel(c.channel);
    const bool inside = !s.empty() && cursor_t_ >= s.start_time() && cursor_t_ <= s.end_time();
    out.push_back(
        {c.stream, c.channel, ch.unit, inside ? log::interpolate_linear(s.time(), ch.values, cursor_t_) : NAN});
  }
  return out;
}

void TimeSeriesChart::set_cursor(double t) {
  cursor_t_ = t;
  // The legend reads every curve's value at the cursor.
  const std::vector<Reading> now = readout();
  for (std::size_t i = 0; i < plots_.size() && i < now.size(); ++i) {
    if (plots_[i] == nullptr || labels_[i].empty()) continue;
    char value[40];
    std::snprintf(value, sizeof value, " = %.4g", now[i].value);
    // No value (the stream has not started, has ended, or holds NaN there): said in words, not "= -".
    plots_[i]->SetLabel(labels_[i] + (std::isfinite(now[i].value) ? value : " (no value at the cursor)"));
  }
  for (std::size_t g = 0; g < cursors_.size(); ++g) move_cursor(cursors_[g], t, ranges_[g]);
}

// The band's table (time, value - sigma, value + sigma), every k-th sample in
// the window so that about 2 * columns remain; widens [lo, hi] to hold it.
void TimeSeriesChart::refresh_band(Band& band, double& lo, double& hi) {
  const log::Stream& s = log_->stream(channels_[band.channel].stream);
  const auto& value = s.channel(channels_[band.channel].channel).values;
  const auto& sigma = s.channel(band.sigma).values;
  const auto& time = s.time();
  const auto first = static_cast<std::size_t>(std::lower_bound(time.begin(), time.end(), t0_) - time.begin());
  const auto last = static_cast<std::size_t>(std::upper_bound(time.begin(), time.end(), t1_) - time.begin());
  const std::size_t step = std::max<std::size_t>(1, (last - std::min(first, last)) / (2 * columns_));
  auto table = vtkSmartPointer<vtkTable>::New();
  vtkNew<vtkDoubleArray> t, low, high;
  t->SetName("time");
  low->SetName("value - sigma");
  high->SetName("+-1 sigma");
  for (std::size_t k = first; k < last; k += step) {
    if (!std::isfinite(value[k]) || !std::isfinite(sigma[k])) continue;
    t->InsertNextValue(time[k]);
    low->InsertNextValue(value[k] - sigma[k]);
    high->InsertNextValue(value[k] + sigma[k]);
    lo = std::min(lo, value[k] - sigma[k]);
    hi = std::max(hi, value[k] + sigma[k]);
  }
  table->AddColumn(t);
  table->AddColumn(low);
  table->AddColumn(high);
  band.area->SetInputData(table);
  band.area->SetInputArray(0, "time");
  band.area->SetInputArray(1, "value - sigma");
  band.area->SetInputArray(2, "+-1 sigma");
  band.table = table;
}

std::size_t TimeSeriesChart::band_count() const { return bands_.size(); }

std::vector<std::size_t> TimeSeriesChart::drawn_points() const {
  std::vector<std::size_t> out;
  for (const auto& t : tables_) out.push_back(t ? static_cast<std::size_t>(t->GetNumberOfRows()) : 0u);
  return out;
}

namespace {

class TimeSeriesView : public View {
 public:
  std::string name() const override { return "timeseries"; }
  std::string title() const override { return "Plots"; }
  std::string heading() const override { return "Time series"; }
  bool uses_channels() const override { return true; }
  double report_height() const override { return 0.5; }
  bool resets_scene() const override { return true; }
  std::string needs(const SceneInput& in) const override {
    for (const auto& c : in.channels) {
      const log::Stream* s = in.log->find_stream(c.stream);
      if (s == nullptr) return "no stream '" + c.stream + "'";
      if (s->find_channel(c.channel) == nullptr) return "stream '" + c.stream + "' has no channel '" + c.channel + "'";
    }
    std::vector<ChannelRef> shown = in.channels;
    if (shown.empty()) {
      try {
        shown = default_channels(*in.log);
      } catch (const DataError& e) {
        return e.what();
      }
    }
    if (shown.empty()) return "no channel to plot";
    // A line needs two finite samples; a chart of NaN would be empty axes.
    const bool drawable = std::any_of(shown.begin(), shown.end(), [&](const ChannelRef& c) {
      const auto& values = in.log->stream(c.stream).channel(c.channel).values;
      return std::count_if(values.begin(), values.end(), [](double v) { return std::isfinite(v); }) >= 2;
    });
    if (!drawable)
      return "no channel to plot has two finite samples (" + shown.front().stream + ":" + shown.front().channel +
             (shown.size() > 1 ? " and the others are" : " is") + " NaN)";
    return {};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<TimeSeriesChart>(*in.log, channels(in));
  }
  bool reset_scene(Scene& scene, const SceneInput& in) const override {
    auto* chart = dynamic_cast<TimeSeriesChart*>(&scene);
    if (chart == nullptr) return false;
    chart->reset(*in.log, channels(in));
    return true;
  }

 private:
  // The channels asked for, else the log's defaults.
  static std::vector<ChannelRef> channels(const SceneInput& in) {
    return in.channels.empty() ? default_channels(*in.log) : in.channels;
  }
};

}  // namespace

std::unique_ptr<View> make_timeseries_view() { return std::make_unique<TimeSeriesView>(); }

}  // namespace roverlab::views

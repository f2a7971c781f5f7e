#pragma once
// Time-series plots: channels of a log as lines, one plot per unit stacked
// in a vtkChartMatrix and sharing the time axis, decimated for display
// (min/max per pixel column, never from the model), with a cursor line at
// the timeline's time in every plot.

#include <functional>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "core/log/log.h"
#include "views/view.h"

class vtkChartMatrix;
class vtkChartXY;
class vtkContextView;
class vtkPlot;
class vtkPlotArea;
class vtkObject;
class vtkTable;

namespace roverlab::views {

// "stream:channel" (stream names may hold '/'); a bare stream name means all
// of its channels. Throws DataError naming what the log lacks.
std::vector<ChannelRef> parse_channels(const log::Log& log, const std::string& spec);

// Channels a plot shows when none are asked for, chosen for what they show:
// an estimate against the truth of the same channel (contact angle, drawbar
// pull, slip, load first), else an estimate against the reference in its own
// stream (reference_slip), else (a raw log) the channels that follow the
// motion: rates and speeds (m/s, rad/s) whose variance is slower than a
// second for 10 % or more and twice what white noise would be (not raw IMU
// noise), then channels at least half slow that are not ramps (a wheel
// angle, a position, a count), each by that share; up to four, in at most
// two units. Only when none qualifies, up to four of the first stream.
std::vector<ChannelRef> default_channels(const log::Log& log);

// The channel holding `channel`'s 1-sigma in `stream` ("pitch_sigma",
// "drawbar_pull_sigma_1"); empty when there is none.
std::string sigma_channel_of(const log::Stream& stream, const std::string& channel);

// Distinct line colours (RGB 0..255) for plot i.
void line_colour(std::size_t i, unsigned char rgb[3]);

class TimeSeriesChart : public Scene {
 public:
  TimeSeriesChart(const log::Log& log, std::vector<ChannelRef> channels);
  ~TimeSeriesChart() override;
  // Shows other channels (of this or another log) in the same view and chart;
  // the whole time range, cursor at the start.
  void reset(const log::Log& log, std::vector<ChannelRef> channels);
  vtkContextView* view() const;
  // Draws the context view in `window` (with the window's interactor, if any).
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  // The window shown (the whole time range at first), decimated to `pixels` columns.
  void fit_width(int pixels) override;
  // Plot i from the top (one per unit).
  vtkChartXY* chart(std::size_t i = 0) const;
  std::size_t plot_count() const { return groups_.size(); }
  // Plot g's value-axis title: the quantities it shows and their unit, e.g. "angular rate (rad/s)".
  std::string y_title(std::size_t g) const;
  // Shown window in time; redecimates to about `columns` buckets.
  void set_window(double t0, double t1, std::size_t columns = 1000);
  void set_cursor(double t);
  void set_time(double t) override { set_cursor(t); }
  double start_time() const override { return start_; }
  double end_time() const override { return end_; }
  const std::vector<ChannelRef>& channels() const { return channels_; }
  // Every curve's value at the cursor time (linear between samples, NaN
  // outside its stream's span); each legend entry shows it ("... = 0.12", or
  // "(no value at the cursor)"). The cursor starts mid-log, as every view's (render --help).
  struct Reading {
    std::string stream, channel, unit;
    double value = 0;
  };
  std::vector<Reading> readout() const;
  double cursor_time() const { return cursor_t_; }
  // Zoom is linked: a plot's time axis zoomed or panned (mouse wheel, drag)
  // sets every plot's time axis to the same window, and only the time axis:
  // a plot's value axis fits the data in the window until the user zooms or
  // pans that plot, then stays where the user put it.
  std::pair<double, double> window() const { return {t0_, t1_}; }
  // The time window shown, keeping the decimation's columns (another chart's zoom, followed).
  void show_window(double t0, double t1) { set_window(t0, t1, columns_); }
  // Called with the window when the user zooms or pans a time axis (not when set_window is).
  void on_user_window(std::function<void(double, double)> listener) { user_window_ = std::move(listener); }
  // True when the user has zoomed or panned plot g's value axis (it no longer fits the data).
  bool value_axis_set_by_user(std::size_t g) const { return g < user_values_.size() && user_values_[g]; }
  // The whole time range, every value axis fitted to its data again.
  void zoom_to_fit();
  // Channels drawn with a +-1 sigma band (those whose stream holds their sigma).
  std::size_t band_count() const;
  // Points drawn for each channel in the current window (after decimation).
  std::vector<std::size_t> drawn_points() const;
  // The left margin (pixels) the plots keep for the value axes' tick labels
  // and titles: widened after a render whose tick labels needed more (the
  // next render lays the plots out with it; views::capture renders twice).
  int left_border() const;

 private:
  void rebuild();  // plots and cursors, after the channels changed
  void refresh();  // decimated data and axis ranges, after the window changed
  struct Band {
    std::size_t channel;
    std::string sigma;
    vtkPlotArea* area;  // owned by its chart
    vtkSmartPointer<vtkTable> table;
  };
  void refresh_band(Band& band, double& lo, double& hi);
  void link_time_axes();
  void time_axis_moved(vtkObject* axis, unsigned long event, void* data);
  void value_axis_moved(vtkObject* axis, unsigned long event, void* data);
  void fit_left_border(vtkObject* renderer, unsigned long event, void* data);
  std::vector<std::string> labels_;  // per channel, without the value at the cursor
  bool linking_ = false;             // the chart sets the axes itself: not the user
  std::vector<bool> user_values_;    // per plot: the user set its value axis
  std::function<void(double, double)> user_window_;
  std::vector<Band> bands_;
  const log::Log* log_;
  std::vector<ChannelRef> channels_;
  vtkSmartPointer<vtkContextView> view_;
  std::vector<vtkSmartPointer<vtkTable>> tables_;
  std::vector<vtkPlot*> plots_;                   // per channel, owned by their chart
  std::vector<std::vector<std::size_t>> groups_;  // channel indices per plot
  std::vector<vtkSmartPointer<vtkTable>> cursors_;
  std::vector<std::pair<double, double>> ranges_;  // value range per plot
  double start_ = 0, end_ = 0, t0_ = 0, t1_ = 0, cursor_t_ = 0;
  std::size_t columns_ = 1000;
};

}  // namespace roverlab::views

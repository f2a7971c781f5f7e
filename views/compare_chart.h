#pragma once
// Runs side by side (issue 45): for each channel, the baseline and every
// other run overlaid on the baseline's times (aligned and resampled as
// `roverlab compare` does, core/comparison), and below it each run's
// difference from the baseline with the +-2 sigma band of the two streams'
// noise; a cursor in every plot. `render A --compare B --view compare`.

#include <string>
#include <utility>
#include <vector>

#include <vtkSmartPointer.h>

#include "core/comparison/compare.h"
#include "core/log/log.h"
#include "views/view.h"

class vtkChartXY;
class vtkContextView;
class vtkTable;

namespace roverlab::views {

// Each run compared with `base` as `roverlab compare` does by default
// (clocks as recorded), keeping the difference channels. Throws DataError
// (naming the run) when a run cannot be aligned.
std::vector<comparison::RunComparison> compare_all(const log::Log& base,
                                                   const std::vector<std::pair<std::string, const log::Log*>>& runs);

// The channels worth drawing: those that differ in some run, the most
// significant first (test statistic over its threshold), then the others by
// the same ratio; at most `count`.
std::vector<ChannelRef> differing_channels(const std::vector<comparison::RunComparison>& runs, std::size_t count);

class CompareChart : public Scene {
 public:
  // Throws DataError when a channel is not compared in every run.
  CompareChart(const log::Log& base, const std::vector<std::pair<std::string, const log::Log*>>& runs,
               std::vector<ChannelRef> channels);
  ~CompareChart() override;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  void fit_width(int pixels) override;
  void set_time(double t) override;
  double start_time() const override { return start_; }
  double end_time() const override { return end_; }
  std::vector<std::string> notes() const override { return notes_; }

  // What a test reads. Row 2k draws channel k's values, row 2k + 1 its differences.
  vtkChartXY* chart(std::size_t row) const;
  const std::vector<ChannelRef>& channels() const { return channels_; }
  std::size_t run_count() const { return runs_.size(); }
  // Run r's comparison with the baseline; the difference curve drawn for
  // channel k (other minus baseline on the baseline's times, before decimation).
  const comparison::RunComparison& comparison(std::size_t r) const { return runs_[r].comparison; }
  const comparison::ChannelComparison& channel_comparison(std::size_t r, std::size_t k) const;
  const std::vector<double>& difference_time(std::size_t r, std::size_t k) const;
  const std::vector<double>& difference(std::size_t r, std::size_t k) const;
  // The half-width of run r's band for channel k: 2 sqrt(base_sigma^2 + other_sigma^2).
  double band_half_width(std::size_t r, std::size_t k) const;
  // Run r's difference for channel k at the cursor (linear, NaN outside).
  double difference_at_cursor(std::size_t r, std::size_t k) const;

 private:
  struct Run {
    std::string name;
    comparison::RunComparison comparison;
    std::vector<std::size_t> index;  // per channel: its entry in comparison.channels
  };
  void build_plots();
  void add_values(std::size_t k);
  void add_differences(std::size_t k);
  void add_cursor(vtkChartXY* chart);

  const log::Log* base_;
  std::vector<Run> runs_;
  std::vector<ChannelRef> channels_;
  std::vector<std::string> notes_;
  vtkSmartPointer<vtkContextView> view_;
  std::vector<vtkSmartPointer<vtkTable>> cursors_;
  std::vector<std::pair<double, double>> ranges_;  // per row
  std::string prefix_;
  double start_ = 0, end_ = 0, cursor_ = 0;
  std::size_t columns_ = 1000;
};

}  // namespace roverlab::views

#pragma once
// What a time-series plot draws: a channel decimated for display. The model
// keeps every sample; only what goes to the screen is reduced, by min/max
// bucketing, so that spikes and dropouts stay visible at any zoom.

#include <cstddef>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>
#include <vtkTable.h>

#include "core/log/stream.h"

namespace roverlab::views {

struct DisplaySeries {
  std::vector<double> time;
  std::vector<double> value;
};

// Samples of (time, values) with t0 <= t <= t1 reduced to at most
// 2 * buckets points: in each of `buckets` equal index ranges, the minimum and
// the maximum in time order. NaN samples are skipped. When the window holds
// no more than 2 * buckets samples they are returned unchanged.
DisplaySeries decimate_min_max(const std::vector<double>& time, const std::vector<double>& values, double t0, double t1,
                               std::size_t buckets);

// A two-column vtkTable ("time", channel name) for vtkChartXY, from the
// decimated channel. Throws DataError when the channel is absent.
vtkSmartPointer<vtkTable> make_display_table(const log::Stream& stream, const std::string& channel, double t0,
                                             double t1, std::size_t buckets);

}  // namespace roverlab::views
